"""``tfx wtf --format jsonl`` read back for ``--resume``: the same reports, within limits, a cut last line tolerated."""

from __future__ import annotations

import io

import pytest

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import Thresholds
from tftools.analysis.wtf.fleet import BagReport, unreadable
from tftools.core.time import NS_PER_S
from tftools.render import wtf_lines
from tftools.render.wtf import bag_dict

START = 1_700_000_000 * NS_PER_S + 2_000_000


def reports() -> list[BagReport]:
    stale = Finding(
        Severity.error, "stale", "odom -> base_link stopped", "restart /ekf", ("odom", "base_link"), ("/ekf",),
        START + 3 * NS_PER_S, START + 9 * NS_PER_S, 200,
    )  # fmt: skip
    skipped = Finding(Severity.info, "static_volatile", "not checked: no metadata", "", skipped=True)
    checked = BagReport(("run1.bag",), [stale, skipped], None, ("ros1",), START, START + 10 * NS_PER_S, 500, 6)
    checked.sensor_topics, checked.sensor_target, checked.sensor_target_reason = ("/scan",), "odom", "the default"
    split = BagReport(("a_0.db3", "a_1.db3"), [], None, ("rosbag2-sqlite3",), START, START + NS_PER_S, 10, 3)
    return [checked, split, unreadable(("bad.mcap",), "bad.mcap: corrupt", "")]


def written(bags: list[BagReport], summary: bool = True) -> bytes:
    out = io.StringIO()
    for bag in bags:
        wtf_lines.write_recording(bag, out, strict=False)
    if summary:
        wtf_lines.write_summary(bags, out, False, Thresholds(), 1)
    return out.getvalue().encode()


def read(data: bytes) -> wtf_lines.Resumed:
    return wtf_lines.read_report(io.BytesIO(data), "run.jsonl")


def test_a_report_reads_back_as_the_reports_written() -> None:
    resumed = read(written(reports()))
    assert not resumed.cut_short
    assert [bag_dict(b, False) for b in resumed.reports] == [bag_dict(b, False) for b in reports()]
    assert resumed.reports[0].findings[0].first_time == pytest.approx(START + 3 * NS_PER_S, abs=500)


def test_the_last_line_cut_short_is_left_out_and_said() -> None:
    data = written(reports(), summary=False)
    resumed = read(data[:-40])
    assert resumed.cut_short and [b.paths for b in resumed.reports] == [("run1.bag",), ("a_0.db3", "a_1.db3")]


def test_a_later_line_for_a_recording_replaces_an_earlier_one() -> None:
    first, *_ = reports()
    again = BagReport(first.paths, [], None, ("ros1",), START, START + NS_PER_S, 5, 2)
    (resumed,) = read(written([first]) + written([again])).reports
    assert resumed.findings == [] and resumed.transforms == 5


@pytest.mark.parametrize(
    ("data", "says"),
    [
        (b'{"type": "recording"}\n', "line 1 is not a recording"),
        (b"[1, 2]\n", "line 1 is not a line of a tfx wtf report"),
        (b"not json\n{}", "line 1 is not JSON"),
        (b'{"type":"recording","paths":[1]}\n', "line 1 is not a recording"),
        (b"x" * (wtf_lines.MAX_LINE_BYTES + 10), "longer than 16 MiB"),
    ],
)
def test_what_is_not_a_report_is_refused_in_one_line(data: bytes, says: str) -> None:
    with pytest.raises(wtf_lines.ReportError, match=says):
        read(data)


def test_sensor_data_of_a_recording_without_tf_reads_back_without_a_target() -> None:
    """No tree, no frame to check sensor data in: written as null (not "", which a script takes for a frame),
    read back as the same report."""
    from tftools.analysis.targets import NO_TREE

    auv = BagReport(("auv.db3",), [], None, ("rosbag2-sqlite3",), START, START + NS_PER_S, 0, 0)
    auv.sensor_topics, auv.sensor_target, auv.sensor_target_reason = ("/ping1d/range",), "", NO_TREE
    line = written([auv], summary=False)
    assert b'"target":null' in line
    assert [bag_dict(b, False) for b in read(line).reports] == [bag_dict(auv, False)]
