"""One figure, one number, in every command (issue 39): a frame with two parents counted as monitor's edge rows in
``tfx frames``, a silence in view-frames that is monitor's, a rate that cannot be measured flagged against an
expected one by ``tfx diff``, and ``echo --play`` lines never repeating a moment; each on a real recording."""

from __future__ import annotations

import itertools
import json
import re
from pathlib import Path
from typing import Any

import pytest

from tests.bags import TfMessage, write_bag
from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_issue39 import CALIBRATION_2025, LAP
from tftools.core.transform import Transform
from tftools.sources.recording import read_recording

#: base_link under base_footprint (/robot_state_publisher, once on /tf_static), then odom (/neato, 413 on /tf);
#: CALIBRATION_2025's box_base_model under stim320_imu and box_base in one /tf_static message.
NEATO_URDF = "ros1-neato-urdf-beside-driver-2018-bag"
#: world -> talk at 10 Hz from /talker. (LAP: a real TurtleBot3's lap, its wheels' newest stamp 1162.476 s old at
#: its end, their last arrival 1121.827 s before it.)
TALKER = "talker-world-talk-2018-bag"


def _path(corpus: Corpus, recording_id: str) -> Path:
    return corpus(BY_ID[recording_id])


def _json(tfx: Tfx, *args: str | Path) -> Any:  # noqa: F811
    result = tfx(*args, "--format", "json")
    assert result.stdout.strip(), result.stderr
    return json.loads(result.stdout)


@pytest.mark.parametrize("recording_id", [NEATO_URDF, CALIBRATION_2025])
def test_a_frame_with_two_parents_is_monitors_edge_rows_in_frames(recording_id: str, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``tfx frames`` gave the frame of tf2's one history as one (414 samples of base_link from both publishers),
    ``tfx monitor`` a row per edge (1 under base_footprint, 413 under odom): frames now says each parent's edge as
    monitor's row counts it, beside the frame's own figures."""
    path = _path(corpus, recording_id)
    frames = _json(tfx, "frames", "-b", path)["frames"]
    rows = _json(tfx, "monitor", "-b", path)["edges"]
    several = [f for f in frames if len(f["parents"]) > 1]
    assert several
    for frame in several:
        mine = [r for r in rows if r["child"] == frame["frame"]]
        assert [e["parent"] for e in frame["edges"]] == frame["parents"] == [r["parent"] for r in mine]
        for edge, row in zip(frame["edges"], mine, strict=True):
            for key in ("authorities", "count", "rate_hz", "first_stamp", "last_stamp"):
                assert edge[key] == row[key], (frame["frame"], edge["parent"], key)
        assert sum(e["count"] for e in frame["edges"]) == frame["count"]
    if recording_id == NEATO_URDF:
        text = " ".join(tfx("frames", "-b", path).stdout.split())
        assert "parents over time (samples): base_footprint (1) → odom (413)" in text


#: base_link -> link1 and link1 -> w_link, constant on /tf: 544 stamps in 570 transforms (stamps sent again).
JETACKER_REAL = "ros2-jetacker-real-two-odometries-2026-db3"
#: car_rear_axel -> velodyne(_rear), constant on /tf: 29 stamps in 29 transforms.
CAR = "car-path-follower-2022-bag"


@pytest.mark.parametrize("recording_id", [JETACKER_REAL, CAR])
def test_a_constant_edge_on_tf_is_said_at_monitors_rate(recording_id: str, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """static_on_dynamic counted every transform received over the stamps' span: '3.2 times a second (570
    transforms ...)' on the Jetacker beside monitor's 3.02 stamps/s and 544 samples; now monitor's rate and
    samples, with the transforms received beside them where stamps came again."""
    path = _path(corpus, recording_id)
    rows = {(r["parent"], r["child"]): r for r in _json(tfx, "monitor", "-b", path)["edges"]}
    found = [f for b in _json(tfx, "wtf", path)["bags"] for f in b["findings"] if f["code"] == "static_on_dynamic"]
    assert len(found) == 2
    for finding in found:
        row = rows[tuple(finding["frames"][:2])]
        (hz, stamps) = re.findall(r"([\d.]+) times a second \((\d+) (?:stamps in \d+ )?transforms", finding["message"])[
            0
        ]
        assert float(hz) == round(row["rate_hz"], 1) and int(stamps) == row["count"], finding["message"]
        assert ("stamps in" in finding["message"]) == (recording_id == JETACKER_REAL)


#: record times of 0 to 74 ns (a rosbag2_py writer's) for 27.7 s of stamps: they time no arrival.
LOGISTIC = "ros2-logistic-cobot-pymoveit2-no-record-clock-2024-db3"


def test_record_times_that_are_no_clock_give_no_arrival_figure(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The detections' clock error gave 'arrival_minus_stamp_s': -1731467407.96 in its JSON, record time 46 ns minus
    a 2024 stamp, where the record times time nothing (the finding says so); and obj_2, a detection at rest, was a
    static transform to put on /tf_static."""
    findings = [f for b in _json(tfx, "wtf", _path(corpus, LOGISTIC))["bags"] for f in b["findings"]]
    assert [f for f in findings if f["code"] == "clock" and f["severity"] == "error"]
    assert not [f for f in findings if "arrival_minus_stamp_s" in f["figures"]]
    assert not [f for f in findings if f["code"] == "static_on_dynamic"]


def test_view_frames_says_monitors_silence_beside_the_stamps_age(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """view-frames' "s old" is the newest stamp's age at the end; monitor's silence the time since the last
    arrival: on the lap they differ by the wheels' delay (1162.476 s old, silent for the last 1121.827 s). Each is
    said as what it is, and view-frames' silence is monitor's number."""
    path = _path(corpus, LAP)
    rows = {(r["parent"], r["child"]): r for r in _json(tfx, "monitor", "-b", path)["edges"]}
    result = tfx("view-frames", "-b", path, "--format", "dot", "-o", "-")
    dot = result.stdout
    checked = 0
    for (parent, child), row in rows.items():
        if row["static"] or row["silent_s"] is None:
            continue
        line = next(ln for ln in dot.splitlines() if f'"{parent}" -> "{child}"' in ln or f"{parent} -> {child}" in ln)
        (silent,) = re.findall(r"Silent for the last (\d+\.\d+) s", line)
        assert float(silent) == pytest.approx(row["silent_s"], abs=0.0005), (parent, child)
        checked += 1
    assert checked >= 3
    assert "1162.476 s old" in dot and "Silent for the last 1121.827 s" in dot


def test_diff_flags_an_edge_seen_once_against_the_rate_expected(corpus: Corpus, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """The talker's world -> talk at 10 Hz in the tree ``wtf --init`` wrote of it; its first message alone (the
    recording's own bytes: stamp, value, publisher, record time) has one sample, no rate: ``tfx diff`` said nothing
    (a single sample and a left-out ``rate_hz`` were both 0, "any rate"), exit 0."""
    path = _path(corpus, TALKER)
    tree = tmp_path / "tree.yaml"
    init = tfx("wtf", "--init", path)
    assert init.code == 0, init.stderr
    tree.write_text(init.stdout)
    hist = read_recording([path]).buffer.history("talk")
    assert hist is not None
    x, y, z, qx, qy, qz, qw = (float(v) for v in hist.values[0])
    first = Transform((x, y, z), (qx, qy, qz, qw), int(hist.stamps[0]), "world", "talk")
    once = write_bag(tmp_path / "first.bag", [TfMessage("/tf", int(hist.record_times[0]), [first], "/talker")])
    result = tfx("diff", tree, once)
    assert result.code == 1, result.stdout
    assert "world -> talk at no rate (one sample, or none stamped apart) in B, 10.0 Hz in A" in result.stdout
    report = _json(tfx, "diff", tree, once)
    (rate,) = [d for d in report["differences"] if d["change"] == "rate"]
    assert rate["rate_change"] == -1.0
    assert tfx("diff", path, path).code == 0
    left_out = tmp_path / "any_rate.yaml"
    left_out.write_text(re.sub(r", rate_hz: [\d.]+", "", init.stdout))
    assert "rate_hz" not in left_out.read_text().split("frames:")[1]
    assert tfx("diff", left_out, once).code == 0  # no rate expected: any rate, one sample too


def test_echo_play_outrun_by_its_replay_shows_each_moment_once(corpus: Corpus, monkeypatch: pytest.MonkeyPatch) -> None:
    """``echo --play`` on the lap, its replay played to the end before the first line was due (a loaded machine,
    a terminal that blocks): every line due meanwhile was made at once at the same time of the replay's clock,
    1,361 lines of one moment, where monitor's tables skip a tick at a clock time already shown; now one line."""
    from tftools.analysis.echo import EchoQuery, echo_stream
    from tftools.sources.replay import Replay
    from tftools.sources.stream import StreamedRecording, stream_recording

    played = StreamedRecording.replay

    def outrun(self: StreamedRecording, **kw: Any) -> Replay:
        replay = played(self, **kw)
        # its first step 10,000 s of wall time after it began: the whole lap played before the first line is due
        replay._monotonic = itertools.chain([0.0], itertools.repeat(10_000.0)).__next__
        return replay

    monkeypatch.setattr(StreamedRecording, "replay", outrun)
    times: list[int] = []
    with stream_recording([_path(corpus, LAP)]) as streamed:
        echo_stream(
            streamed,
            EchoQuery(target="odom", source="base_footprint"),
            lambda series, buffer: times.append(buffer.now()),
        )
    assert len(times) == 1
