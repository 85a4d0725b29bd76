"""Issue 39 (brief diff43), each on the real recordings that showed it: `tfx diff`'s edge that stopped early in one
run only, and edge held still on /tf whose values jitter at float rounding; nav_msgs/Odometry's child_frame_id and
pose against tf; `tfx monitor`'s two delays said apart. The designed reproductions are beside the code's own tests
(tests/analysis/test_expected.py, test_wtf_odometry.py, tests/sources/codecs/test_odometry.py)."""

from __future__ import annotations

import json
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_diff42 import _diff
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
NEATO_URDF = "ros1-neato-urdf-beside-driver-2018-bag"
DRONE = "ros1-gazebo-drone-hover-pose-at-1-khz-on-sim-ticks-repeated-stamps-pfms-quiz5-2023-bag"
#: Recordings whose /odom comes from the node that sends the edge on tf (TurtleBot3's, the Neato's driver, the
#: MIT car's vesc_to_odom, a Kobuki in Gazebo re-sending stamps, a Guardian): odometry and tf agree.
HEALTHY_ODOMETRY = (
    "ros2-turtlebot3-real-foxy-2023-db3",
    "ros2-turtlebot3-real-wifi-outage-2025-db3",
    "ros2-neato-real-fsm-odom-jump-2023-db3",
    "ros1-neato-square-dance-2018-bag",
    "ros2-mit-rss-racecar-real-vesc-odometry-safety-stop-three-static-publishers-2026-db3",
    "ros1-gazebo-kobuki-repeated-stamps-2017-bag",
    "ros1-robotnik-guardian-real-lab-run-empty-tf-messages-rsp-post-dated-no-callerid-2014-bag",
    "ros1-sail-zed-ekf-gps-two-odometries-2022-bag",
)


def test_the_neato_whose_odometry_stopped_11_s_before_the_end_against_a_run_sent_to_its_end(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Two real Neato wall-follower runs: in the 2023 one the driver's odom -> base_footprint and its wheels last
    arrive 59.7 s into 71.1 s (wtf's stale says so), in the 2022 one until 30.8 s of 30.9 s. diff said no
    difference; it now says which stopped early and when, against the run sent to its end: once, as the three
    stopped at one point (diff46: three lines before, one a stopped edge)."""
    code, found = _diff(tfx, corpus, NEATO_2022, NEATO_STOPPED)
    stopped = {d["frame"]: d for d in found if d["change"] == "stopped"}
    assert sorted(stopped) == ["base_footprint"], found
    assert stopped["base_footprint"]["said_with"] == ["wheel_left_link", "wheel_right_link"]
    assert stopped["base_footprint"]["message"] == (
        "odom -> base_footprint stopped early in B: its last sample (stamped 1694540917.403) arrived 59.7 s into "
        "B's 71.1 s, silent for its last 11.3 s; in A it was sent to the end (30.8 s of 30.9 s); the edges of 2 more "
        "frames stopped in B at the same point, each sent to the end in A: wheel_left_link, wheel_right_link"
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


def _wtf(tfx: Tfx, corpus: Corpus, recording: str) -> list[dict[str, Any]]:  # noqa: F811
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[recording]), "--format", "json").stdout)["bags"]
    findings: list[dict[str, Any]] = bag["findings"]
    return findings


def test_the_neatos_odometry_against_the_base_link_tf2_holds_static(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The Neato's driver sends /odom and odom -> base_link on /tf, but base_link came first on /tf_static (its
    URDF's base_footprint -> base_link): ROS 1's tf2 holds it static, each /tf sample replacing its value for every
    time. At each of the 413 /odom stamps tf gives base_link's last value, 1.431 m at most (median 0.969 m) from
    the odometry's: by the bytes (rosbags' reader), the last /tf base_link at (3.009, 0.435) against every /odom
    pose, 1.4307 m at most, median 0.9689 m."""
    (odometry,) = [f for f in _wtf(tfx, corpus, NEATO_URDF) if f["code"] == "odometry"]
    assert odometry["severity"] == "info"
    assert odometry["message"].startswith(
        "/odom: 413 nav_msgs/msg/Odometry messages state odom -> base_link; at the 413 of their stamps tf has "
        "samples at too, tf's value is up to 1.431 m"
    ), odometry["message"]
    assert "(median 0.969 m)" in odometry["message"]


@pytest.mark.parametrize("recording", HEALTHY_ODOMETRY)
def test_odometry_sent_beside_its_own_tf_is_no_finding(corpus: Corpus, tfx: Tfx, recording: str) -> None:  # noqa: F811
    """Each of these sends nav_msgs/Odometry and the same edge on tf from one node: at their common stamps they
    agree within 1 mm and 0.1° (the Kobuki's re-sent stamps 14 um and 0.01° from the first, which tf2 keeps)."""
    assert [f["message"] for f in _wtf(tfx, corpus, recording) if f["code"] == "odometry"] == []


def test_monitor_says_what_the_drones_publisher_delay_is_over_beside_its_edges(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Gazebo's drone pose re-sent at 1 kHz on 1 ms sim ticks: /gazebo_connect sent 2810 transforms, of which tf2
    stored 574 (287 on each edge), the rest re-sent stamps. Its delay (1.5 ms, over all 2810) sat beside its
    edges' (1.1 ms, over the stored ones) with no word of why they differ; a line now says what each is over."""
    result = tfx("monitor", "-b", corpus(BY_ID[DRONE]))
    assert (
        "/gazebo_connect: its delays are over the 2810 transforms it sent on /tf (tf_monitor's Node line), 2236 of "
        "them in no frame's" in " ".join(result.stdout.split())
    ), result.stdout
    (node,) = [
        a
        for a in json.loads(tfx("monitor", "-b", corpus(BY_ID[DRONE]), "--format", "json").stdout)["authorities"]
        if a["authority"] == "/gazebo_connect"
    ]
    assert (node["delays_counted"], node["delays_beyond_edges"]) == (2810, 2236)
    healthy = tfx("monitor", "-b", corpus(BY_ID["ros2-turtlebot3-real-foxy-2023-db3"]))
    assert "in no frame's" not in healthy.stdout


def test_the_agvs_odometry_hint_names_the_child_frame_its_messages_state(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The replayed AGV's /odom_enc: 427 nav_msgs/Odometry in 'odom_enc', which no transform names, each stating
    odom_enc -> base_footprint (its child_frame_id, by the bytes). The hint said "its transform to the robot (to the
    messages' child_frame_id)" without naming it; it names base_footprint now, in wtf and in filter alike."""
    agv = "ros1-agv-two-lasers-mounts-on-tf-and-tf-static-replayed-2018-bag"
    (lost,) = [f for f in _wtf(tfx, corpus, agv) if f["code"] == "sensor_frame" and "/odom_enc" in f["message"]]
    assert "its transform to the robot (to base_footprint, the messages' child_frame_id) is not on tf" in lost["hint"]
    said = " ".join(tfx("filter", "/odom_enc", "-b", corpus(BY_ID[agv])).stdout.split())
    assert "(to base_footprint, the messages' child_frame_id)" in said, said
