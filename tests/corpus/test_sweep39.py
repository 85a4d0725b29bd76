"""Defects found by sweep39 (every command on every recording, read as a new user would), each on the recording
that showed it; the designed reproductions are beside the code's own tests."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording
from tests.corpus.recordings import BY_ID, RECORDINGS, Corpus
from tests.corpus.test_issue39 import _findings

JETACKER_REAL = "ros2-jetacker-real-two-odometries-2026-db3"


def test_a_real_jetackers_two_joints_of_one_message_are_said_once(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """ros2_db3_jetacker_real_two_odometries: base_link -> link1 and link1 -> w_link come in one /tf message (a ROS 2
    bag names no node). wtf said two static_on_dynamic warnings (570 transforms each) and two time_backwards
    warnings (7 out of order each, at the same stamps): 4 warnings for 2 things. Now one of each, the other edge
    beneath it; the verdict is unchanged."""
    code, bag, findings = _findings(tfx, corpus(BY_ID[JETACKER_REAL]))
    for kind in ("static_on_dynamic", "time_backwards"):
        alike = [f for f in findings if f["code"] == kind]
        assert [f["frames"] for f in alike] == [["base_link", "link1"], ["link1", "w_link"]], alike
        assert alike[0]["cause"] == "" and alike[1]["cause"] == alike[0]["key"] != "", alike
    assert code == 1 and bag["verdict"] == "failed"


def test_a_real_jetackers_stall_with_late_samples_is_the_link_not_a_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The JetAcker over WiFi: its 3 edges silent for 2.2-2.9 s from +145.1 s while 45 transforms arrived, each a
    sample not received before (25 stamped before the stall: delivered late). The hint said the clock they are
    stamped with stood still (a paused simulation, a driver's clock); it now names the link."""
    findings = _findings(tfx, corpus(BY_ID[JETACKER_REAL]))[2]
    (late,) = [f for f in findings if f["code"] == "stall" and "meanwhile" in f["message"]]
    assert "45 transforms arrived on /tf meanwhile, new samples but none stamped inside it" in late["message"]
    assert "stood still (a paused" not in late["hint"] and "lossy network or WiFi" in late["hint"], late["hint"]


FRANKA = "json-mcap-franka-teleop-2025"


def test_frankas_two_frames_on_both_tf_topics_in_one_message_are_one_error(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Franka teleop's MCAP sends world -> base and base -> fr3_link0 together, once on /tf_static and 5 times on
    /tf: two mixed_static errors alike ('2 errors'). One error now, fr3_link0's beneath it; still exit 1 (the
    other error: its /robot_description's arm, which tf never carries: test_rules48)."""
    code, bag, findings = _findings(tfx, corpus(BY_ID[FRANKA]))
    mixed = [f for f in findings if f["code"] == "mixed_static"]
    assert [f["frames"][0] for f in mixed] == ["base", "fr3_link0"], mixed
    assert mixed[1]["cause"] == mixed[0]["key"] != "", mixed
    roots = [f["code"] for f in findings if f["severity"] == "error" and not f["cause"]]
    assert roots.count("mixed_static") == 1 and bag["summary"]["errors"] == len(roots), bag["summary"]
    assert code == 1


def _said_on_stderr(stderr: str) -> list[str]:
    """What a command said on stderr beyond its own lines ('wrote ...', its one-line error and hint): an internal
    error, a library's warning turned into a note, or a traceback."""
    return [
        line
        for line in stderr.splitlines()
        if "internal error" in line or line.startswith(("tfx: note:", "Traceback")) or "Warning" in line
    ]


@pytest.mark.slow
@pytest.mark.parametrize("recording", RECORDINGS, ids=[r.id for r in RECORDINGS])
def test_every_command_on_every_recording_ends_in_its_own_words(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """sweep39's sweep as a check: wtf, monitor, frames, view-frames, report, filter and echo of a real edge on each
    recording exit 0, 1 or 2 with no internal error, library warning or traceback on stderr, and wtf, report and
    view-frames give one verdict (view-frames 2 only where there is no tf to draw)."""
    bag = corpus(recording)
    runs = {
        "wtf": tfx("wtf", "-b", bag, "-f", "json"),
        "report": tfx("report", "-b", bag, "-o", tmp_path / "r.html"),
        "view-frames": tfx("view-frames", "-b", bag, "-o", tmp_path / "f.dot"),
        "monitor": tfx("monitor", "-b", bag, "-f", "json"),
        "frames": tfx("frames", "-b", bag, "-f", "json"),
        "filter": tfx("filter", "-b", bag, "-f", "json"),
    }
    edges = recording.meta.get("dynamic_edges") or recording.meta.get("static_edges")
    if isinstance(edges, list) and edges:
        runs["echo"] = tfx("echo", *edges[0], "-b", bag, "-f", "json", "--at", "+1")
    for name, result in runs.items():
        assert result.code in (0, 1, 2), f"{name}: exit {result.code}"
        assert not _said_on_stderr(result.stderr), f"{name}: {result.stderr}"
    verdicts = {name: runs[name].code for name in ("wtf", "report", "view-frames")}
    no_tf = "no_tf" in recording.meta["expected"]["errors"]
    assert verdicts["wtf"] == verdicts["report"] and (verdicts["view-frames"] == verdicts["wtf"] or no_tf), verdicts
