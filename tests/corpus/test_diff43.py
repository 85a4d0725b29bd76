"""Issue 39 (brief diff43), each on the real recordings that showed it: `tfx diff`'s edge that stopped early in one
run only, and edge held still on /tf whose values jitter at float rounding. The designed reproductions are beside
the code's own tests (tests/analysis/test_expected.py)."""

from __future__ import annotations

import json
from typing import Any

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tftools.analysis.expected import shape_of
from tftools.sources.recording import read_recording

NEATO_2022 = "ros2-neato-real-wall-follower-statics-20hz-2022-db3"
NEATO_STOPPED = "ros2-neato-real-wall-follower-stopped-2023-db3"
DISC_PAUSES = "ros2-csce452-disc-robot-own-simulator-tf-pauses-while-scanning-two-static-laser-publishers-2023-db3"
DISC_STOPS = "ros2-csce452-disc-robot-own-simulator-tf-stops-at-first-wheel-command-2023-db3"
UR5 = "ros2-ur5-two-clocks-topic-tf-2023-db3"
KRISHI_UR5 = "ros2-krishi-cobot-ur5-fruits-two-trees-2025-db3"
HUSKY_UR = "ros2-husky-ur-moveit2-gazebo-2025-db3"
HUSKY_UR_LONG = "ros2-husky-ur-moveit2-gazebo-long-2025-db3"


def _diff(tfx: Tfx, corpus: Corpus, first: str, second: str) -> tuple[int, list[dict[str, Any]]]:  # noqa: F811
    result = tfx("diff", corpus(BY_ID[first]), corpus(BY_ID[second]), "--format", "json")
    return result.code, json.loads(result.stdout)["differences"]


def test_the_neato_whose_odometry_stopped_11_s_before_the_end_against_a_run_sent_to_its_end(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Two real Neato wall-follower runs: in the 2023 one the driver's odom -> base_footprint and its wheels last
    arrive 59.7 s into 71.1 s (wtf's stale says so), in the 2022 one until 30.8 s of 30.9 s. diff said no
    difference; it now says, once per edge, which stopped early and when, against the run sent to its end."""
    code, found = _diff(tfx, corpus, NEATO_2022, NEATO_STOPPED)
    stopped = {d["frame"]: d["message"] for d in found if d["change"] == "stopped"}
    assert sorted(stopped) == ["base_footprint", "wheel_left_link", "wheel_right_link"], found
    assert stopped["base_footprint"] == (
        "odom -> base_footprint stopped early in B: its last sample (stamped 1694540917.403) arrived 59.7 s into "
        "B's 71.1 s, silent for its last 11.3 s; in A it was sent to the end (30.8 s of 30.9 s)"
    )
    assert code == 1
    _, itself = _diff(tfx, corpus, NEATO_STOPPED, NEATO_STOPPED)
    assert itself == []  # stopped in both: no difference


def test_the_disc_robots_simulator_whose_tf_stopped_at_the_first_wheel_command(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The CSCE 452 disc robot's own simulator: world -> base_link sent for the first 0.5 s of a 10.7 s run, then
    never again (the bytes: its last /tf record 0.5 s in), against a run that sent it for all of its 27.9 s."""
    _, found = _diff(tfx, corpus, DISC_PAUSES, DISC_STOPS)
    (stopped,) = [d for d in found if d["change"] == "stopped"]
    assert stopped["message"].startswith("world -> base_link stopped early in B: its last sample"), stopped
    assert (
        "arrived 0.5 s into B's 10.7 s, silent for its last 10.2 s; in A it was sent to the end" in (stopped["message"])
    )


def test_two_ur5s_joints_held_on_tf_at_float_rounding_are_compared_whole(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The UR5 of ros2-ur5-two-clocks sends its arm's joints on /tf, held still for the whole recording, each
    sample apart from the first by up to 1.3e-15 m. diff called them moving, compared their translations only
    ("moved by 135.8 mm (its translation, fixed in both) ... turning by up to 0.00°") and left the rotations
    out; they are held (``figures.HELD_M``), so compared whole: 135.8 mm and 114.81° from the other UR5's."""
    _, found = _diff(tfx, corpus, UR5, KRISHI_UR5)
    moved = {d["frame"]: d["message"] for d in found if d["change"] == "moved"}
    assert moved["upper_arm_link"] == (
        "shoulder_link -> upper_arm_link (on /tf, never changing in either) moved by 135.8 mm and 114.81°: xyz "
        "[0.0000, 0.1358, 0.0000] m rpy [0.00, -46.94, 0.00]° in A, xyz [0.0000, 0.0000, 0.0000] m rpy [90.00, "
        "33.80, 0.00]° in B"
    )
    assert not [m for m in moved.values() if "turning by up to 0.00°" in m]


def test_the_husky_ur_arms_shoulder_held_in_both_runs_is_no_difference(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Two runs of the Husky with a UR arm in Gazebo: ur_shoulder_link held on /tf at z 0.1519 in both, its
    rotation jittering by 1e-16 (395 and 480 samples). Held in both, at one value: no difference."""
    held = [
        shape_of(read_recording([str(corpus(BY_ID[i]))])).frames["ur_shoulder_link"].held
        for i in (HUSKY_UR, HUSKY_UR_LONG)
    ]
    assert [h.times if h is not None else None for h in held] == [395, 480]
    code, found = _diff(tfx, corpus, HUSKY_UR, HUSKY_UR_LONG)
    assert (code, found) == (0, [])
