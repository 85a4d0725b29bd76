"""Issue 39's defects left open by the last round, each on the real recording that showed it (designed
reproductions beside them: tests/analysis/test_stamped_zero.py, test_echo_span_hint.py, test_sim_clock_times.py,
test_monitor_play_ahead.py; tests/cli/test_report.py for the one no-transforms hint). Each skips while its
recording awaits placement, as the rest of the corpus tests do."""

from __future__ import annotations

import itertools
import json
import re

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

FSM = "ros2-neato-real-fsm-odom-jump-2023-db3"
PERSON_FOLLOWER = "ros2-neato-real-person-follower-isha-2023-db3"
SQUARE = "ros2-neato-real-robot-clock-drive-square-isha-2023-db3"
NO_TF = "ros2-abitobot-gz-no-tf-2025-mcap"
LAP = "ros2-turtlebot3-real-wifi-outage-2025-db3"


def _words(text: str) -> str:
    return " ".join(text.split())


@pytest.mark.parametrize(("recording_id", "markers"), [(FSM, 5), (PERSON_FOLLOWER, 4)])
def test_markers_stamped_0_before_their_chain_are_said_so_with_no_cache_hint(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    recording_id: str,
    markers: int,
) -> None:
    """/wall's visualization markers, stamped 0, the first few arriving before odom -> base_footprint's first
    sample: '5 older than the 10 s cache holds by the time tf reached them' (and, on the person follower,
    'a cache of 1800 s would keep those'), nothing of the stamp."""
    result = tfx("wtf", "-b", corpus(BY_ID[recording_id]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (lost,) = [f for f in bag["findings"] if f["code"] == "sensor_lost"]
    assert lost["message"].startswith(f"/wall: {markers} of ") and lost["count"] == markers
    assert "all of them stamped 0 (header.stamp unset)" in lost["message"], lost["message"]
    assert "before the recording's tf of their chain existed" in lost["message"]
    assert "a cache of" not in lost["message"] and "set header.stamp" in lost["hint"]


def test_echo_at_past_the_recordings_end_says_its_span_and_the_times_that_work(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """A 27.9 s drive asked at +40.9: tf2's extrapolation text as tf2 says it, and the chain's span beneath."""
    path = corpus(BY_ID[SQUARE])
    result = tfx("echo", "odom", "base_link", "-b", path, "--at", "+40.9")
    assert result.code == 1 and "Lookup would require extrapolation into the future." in result.stdout
    hint = _words(result.stderr)
    assert "67.901 is after the recording's tf of odom <- base_link (28.000 to 54.700, 26.700 s" in hint, hint
    reach = re.search(r"--at (\S+) to (\S+) look it up there", hint)
    assert reach is not None and reach.groups() == ("+0.999", "+27.699"), hint
    for bound in reach.groups():
        looked = tfx("echo", "odom", "base_link", "-b", path, f"--at={bound}")
        assert looked.code == 0 and looked.stderr == "", (bound, looked.stderr)


def test_wtf_gives_every_commands_hint_for_a_recording_without_transforms(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    path = corpus(BY_ID[NO_TF])
    (bag,) = json.loads(tfx("wtf", "-b", path, "--format", "json").stdout)["bags"]
    (no_tf,) = [f for f in bag["findings"] if f["code"] == "no_tf"]
    frames = tfx("frames", "-b", path)
    said = frames.stderr.rstrip().removesuffix(")")  # "(hint)", or "; hint" after its data's frames, in parentheses
    assert frames.code == 2 and said.endswith(no_tf["hint"]), (frames.stderr, no_tf)
    # in ROS 2's words: the command that records /tf there is ros2 bag record, not rosbag record
    assert no_tf["hint"].startswith(
        "was /tf recorded? record it with ros2 bag record /tf /tf_static, or pick other topics with --topic; "
    )


@pytest.mark.slow
def test_monitor_play_at_40x_never_shows_one_window_twice(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The 22.7 min lap at --rate 40 (34 s of wall time): 831 of 1361 tables repeated the one before where the
    tables fell behind the replay. How many tables come depends on the machine; that none repeats does not."""
    result = tfx("monitor", "-b", corpus(BY_ID[LAP]), "--play", "--rate", "40")
    assert result.code == 0, result.stderr
    times = [line.split()[1] for line in result.stdout.splitlines() if line.startswith("time ")]
    assert times and all(float(b) > float(a) for a, b in itertools.pairwise(times)), times
