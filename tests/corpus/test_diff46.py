"""Issue 39 (brief diff46), on the real pairs that showed it: `tfx diff` says once what several edges did together,
and measures a stop as wtf's stale does. The designed
reproductions are beside the code's own tests (tests/analysis/test_diff_groups.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import Corpus
from tests.corpus.test_corpus43a import JANUARY, OCTOBER
from tests.corpus.test_corpus44b import PAUSED, TB4
from tests.corpus.test_diff42 import _diff

OPENNI = ["openni_depth_frame", "openni_depth_optical_frame", "openni_rgb_frame", "openni_rgb_optical_frame"]


def test_the_pr2s_kinect_at_another_rate_is_one_difference(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """JSK's real PR2 in October and January 2012. The Kinect's five edges (head_plate_frame -> openni_camera and the
    four below it) come in October's robot_state_publisher messages of 48 fixed transforms at 50 Hz, in January
    from static_transform_publishers at 10 Hz: diff said five rate lines, now one with the four beneath it (34
    differences, 38 before)."""
    code, found = _diff(tfx, corpus, OCTOBER, JANUARY)
    assert len(found) == 34 and code == 1
    rates = [d for d in found if d["change"] == "rate"]
    assert [(d["frame"], d["said_with"], d["sent_in"]) for d in rates] == [("openni_camera", OPENNI, "a")]
    assert rates[0]["message"] == (
        "head_plate_frame -> openni_camera at 10.0 Hz in B, 50.0 Hz in A (B 80% slower); the edges of the 4 frames "
        "beneath it, sent in the same messages in A, changed rate with it: " + ", ".join(OPENNI)
    )


def test_the_turtlebot4_simulation_paused_at_the_end_stopped_no_edge(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The TurtleBot 4 simulator's two runs of March 2025: in the later, /clock advances 12 ms over the recording's
    last 2.2 s (the simulation all but paused) and tf's last samples arrive then, 9 ms of simulated time before
    /clock's last value. diff said five edges 'stopped early in B ... silent for its last 2.2 s', measured on the
    record clock, where wtf (on the simulation's time, as a listener with use_sim_time sees it) says tf is fresh.
    A stop is now measured as wtf's stale is: no difference."""
    code, found = _diff(tfx, corpus, TB4, PAUSED)
    assert (code, found) == (0, [])
