"""Issue 39 (brief diff48), on the real pairs that showed it: `tfx diff` says a frame renamed as a rename with its
small move, groups edges each in its own message but stamped alike by one source, and says once a frame that only
turned to undo the edge above it. The designed reproductions are beside the code's own tests
(tests/analysis/test_diff_renames.py, test_diff_groups.py, test_diff_kept.py)."""

from __future__ import annotations

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import Corpus
from tests.corpus.test_diff42 import _diff

HOLO_OCT04 = (
    "ros2-eyrc-hologlyph-holonomic-bot-gazebo-plugin-default-base-footprint-two-trees-wheels-on-wall-clock-2023-db3"
)
HOLO_OCT31 = "ros2-eyrc-hologlyph-holonomic-bot-gazebo-started-after-recording-wall-clock-wheels-before-clock-2023-db3"
HOLO_OCT10 = (
    "ros2-eyrc-hologlyph-holonomic-bot-gazebo-planar-move-three-times-odometry-thrice-metadata-renamed-2023-db3"
)
NEATO_2023 = "ros2-neato-real-two-static-publishers-2023-db3"
NEATO_2024 = "ros2-neato-real-two-static-publishers-2024-db3"
STAGE_WEEK11 = "ros1-stage-three-robots-one-never-joined-leading-slashes-pfms-2024-bag"
STAGE_QUIZ5 = "ros1-stage-three-robots-all-joined-mixed-leading-slashes-pfms-quiz5-a1-bag"
STAGE_A4 = "ros1-stage-three-robots-no-world-three-trees-all-slashed-clock-pfms-a4-2020-bag"
GT_2024 = "grandtour-calibration-2024-bag"
GT_2025 = "grandtour-calibration-2025-bag"
IMU_FIVE = "ros2-ias0220-imu-device-five-static-publishers-2025-db3"
IMU_SEVEN = "ros2-ias0220-imu-device-seven-static-publishers-2025-db3"
TB3_WAFFLE = "ros2-turtlebot3-walker-humble-2023-db3"
TB3_BURGER = "ros2-turtlebot3-walker-humble-patrikpordi-2023-db3"
#: The same run in two formats: no difference.
ONE_RUN_TWO_FORMATS = (
    ("ros2-cybership-voyager-mocap-basin-2025-db3", "ros2-cybership-voyager-mocap-basin-2025-mcap"),
    ("evo-tf-example-bag", "evo-tf-example-db3"),
    ("tfbag-franka-panda-bag", "tfbag-franka-panda-db3"),
)


def _said(found: list[dict[str, object]]) -> list[tuple[object, ...]]:
    return [(d["change"], d["frame"], d["other"] or "", round(float(str(d["translation_mm"])), 1)) for d in found]


def test_the_hologlyph_wheels_renamed_across_two_urdf_versions_are_two_renames(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Two teams' e-Yantra Hologlyph bags (October 4 and 31, 2023), by the bytes: base_link's wheels held on /tf at
    left_wheel (0.58, -0.34, 0.18) yaw -120, rear_wheel (-0.58, -0.34, 0.18) yaw 120 in one; front_wheel (0.5889,
    -0.34, 0.18) yaw -120, left_wheel (-0.5889, -0.34, 0.18) yaw 120 in the other; right_wheel (0, 0.68, 0.18) in
    both. diff said 'left_wheel moved 1168.9 mm' with rear_wheel lost and front_wheel added: two wheels renamed,
    each 8.9 mm away, now said so, whichever comes first."""
    code, found = _diff(tfx, corpus, HOLO_OCT04, HOLO_OCT31)
    assert code == 1
    assert _said(found) == [
        ("renamed", "front_wheel", "left_wheel", 8.9),
        ("renamed", "left_wheel", "rear_wheel", 8.9),
    ]
    assert found[0]["message"].startswith(
        "left_wheel in A is front_wheel in B, renamed: the one frame of base_link in each near that place, 8.9 mm and "
        "0.02° apart"
    )
    _, back = _diff(tfx, corpus, HOLO_OCT31, HOLO_OCT04)
    assert _said(back) == [("renamed", "left_wheel", "front_wheel", 8.9), ("renamed", "rear_wheel", "left_wheel", 8.9)]


def test_a_hologlyph_wheel_renamed_beside_one_really_moved_names_its_namesake(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """October 31 against October 10 (a third team's): left_wheel (-0.5889, -0.34, 0.18) is rear_wheel (-0.58,
    -0.34, 0.18) there, 8.9 mm away; that bag's left_wheel is at (0.49, -0.30, 0.16) yaw 61.3, 100 mm from any
    wheel of the other, and front_wheel is nowhere: one rename, a wheel lost, a left_wheel added at a place no
    wheel was (its namesake named), not 'left_wheel moved 1079.8 mm'. October 4 against October 10 renames
    nothing: the same names, one wheel 100.5 mm elsewhere, the rear turned 0.34 degrees."""
    _, found = _diff(tfx, corpus, HOLO_OCT31, HOLO_OCT10)
    assert _said(found) == [
        ("lost", "front_wheel", "", 0.0),
        ("renamed", "rear_wheel", "left_wheel", 8.9),
        ("added", "left_wheel", "rear_wheel", 0.0),
    ]
    _, same_names = _diff(tfx, corpus, HOLO_OCT04, HOLO_OCT10)
    assert _said(same_names) == [("moved", "left_wheel", "", 100.5), ("moved", "rear_wheel", "", 0.0)]


def test_the_neato_driver_slower_in_2024_is_one_rate_difference(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The real Neato of 2023 and 2024: its driver sends odom -> base_footprint and each wheel in messages of their
    own (by the bytes, 329 and 195 of each), the three stamped alike, sample for sample, in both; at 6.1 Hz in
    2023, 4.7 Hz in 2024. Three rate lines before; one now, the wheels said with it."""
    code, found = _diff(tfx, corpus, NEATO_2023, NEATO_2024)
    assert code == 1
    assert [(d["change"], d["frame"], d["said_with"], d["sent_in"]) for d in found] == [
        ("rate", "base_footprint", ["wheel_left_link", "wheel_right_link"], "stamped")
    ]
    assert found[0]["message"] == (
        "odom -> base_footprint at 4.7 Hz in B, 6.1 Hz in A (B 22% slower); the edges of the 2 frames beneath it, "
        "each in messages of its own but stamped as it was, sample for sample, in A and in B (one source), changed "
        "rate with it: wheel_left_link, wheel_right_link"
    )


def test_stages_local_map_turned_opposite_the_robot_is_said_with_the_robot(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Three PFMS Stage bags: robot_0 at rest, held on /tf at yaw 31.51 (week 11), -0.06 (quiz 5) and -179.52
    degrees (a4); local_map/local_map held under robot_0/base_laser_link turned -31.51, 0.06 and 179.52: it keeps
    its orientation in robot_0/odom. diff said it as a second 'moved' line each time: now one, with the robot's."""
    _, found = _diff(tfx, corpus, STAGE_WEEK11, STAGE_QUIZ5)
    assert [(d["change"], d["frame"], d["said_with"]) for d in found] == [
        ("reparented", "robot_2/odom", []),
        ("moved", "robot_0/base_footprint", ["local_map/local_map"]),
    ]
    assert found[1]["message"].endswith(
        "; beneath it, local_map/local_map kept its orientation in robot_0/odom: its own edge "
        "(robot_0/base_laser_link -> local_map/local_map) turned by 31.57° only to undo it"
    )
    _, again = _diff(tfx, corpus, STAGE_QUIZ5, STAGE_A4)
    assert [d["frame"] for d in again if d["change"] == "moved"] == ["robot_0/base_footprint"]


def test_stages_world_absent_is_one_line_with_the_robots_odom_frames_it_held(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """PFMS quiz 5 joins its three robots' odom frames under world; a4 has no world, each robot_N/odom a root: one
    line for world, its three children said roots with it (four lines before), and robot_0 with its local_map."""
    _, found = _diff(tfx, corpus, STAGE_QUIZ5, STAGE_A4)
    assert [(d["change"], d["frame"], d["said_with"]) for d in found] == [
        ("lost", "world", ["robot_0/odom", "robot_1/odom", "robot_2/odom"]),
        ("moved", "robot_0/base_footprint", ["local_map/local_map"]),
    ]
    assert found[0]["message"] == (
        "world is in A (a root), not in B; its 3 children in A are roots in B: robot_0/odom, robot_1/odom, robot_2/odom"
    )


def test_the_grandtour_calibrations_say_no_swap_under_a_turned_parent_and_the_zed_renamed(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The GrandTour box's 2024 and 2025 calibrations (static only), by the bytes: box_base -> alphasense_base
    turned 179.99 degrees (rpy -80.04, 0.04, -89.99 against 80.04, -0.06, 90.01); under it cam2 at (-0.0550,
    -0.0011) then (0.0549, 0.0011), cam3 the other way round: each at its own place in box_base (0.2, 1.2 mm), so no
    swap of names; cam4 (0.1038, -0.0114, -0.0694) then (-0.1035, 0.0111, -0.0687), 1.0 mm and 0.13 degrees from
    its place in box_base: said with alphasense_base. box_base -> zed_base_link at (0.3877, -0.0469, 0.1316) is
    zed2i_base at (0.3877, -0.0469, 0.1321): renamed; the six frames beneath zed2i_base_link, absent from 2025,
    one line with it."""
    code, found = _diff(tfx, corpus, GT_2024, GT_2025)
    assert code == 1
    by_frame = {(d["change"], d["frame"]): d for d in found}
    assert by_frame["moved", "alphasense_base"]["said_with"] == ["cam4_sensor_frame"]
    assert by_frame["moved", "alphasense_base"]["message"].endswith(
        "; beneath it, cam4_sensor_frame kept its place in box_base (within 1.0 mm and 0.13°): its own edge "
        "(alphasense_base -> cam4_sensor_frame) moved by 208.5 mm and 179.90° to undo it"
    )
    assert ("moved", "cam2_sensor_frame") in by_frame and ("moved", "cam3_sensor_frame") in by_frame
    renames = [(d["other"], d["frame"], round(d["translation_mm"], 1)) for d in found if d["change"] == "renamed"]
    assert renames == [("zed_base_link", "zed2i_base", 0.4)]
    assert len(by_frame["lost", "zed2i_base_link"]["said_with"]) == 6
    assert len(found) == 22


def test_the_imu_bags_root_renamed_is_one_line(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Two students' IAS0220 IMU bags (2025): imu_link static at identity under world in one, under map in the
    other, the range sensor beneath it: 'world lost, imu_link reparented, map added' said as one rename."""
    code, found = _diff(tfx, corpus, IMU_FIVE, IMU_SEVEN)
    assert code == 1
    assert [(d["change"], d["frame"], d["other"], d["said_with"]) for d in found] == [
        ("renamed", "map", "world", ["imu_link"])
    ]
    assert found[0]["message"] == (
        "world in A is map in B, renamed: a root in both, with its child beneath it in both: imu_link"
    )


def test_a_turtlebot3_waffles_camera_absent_from_a_burger_is_one_line(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Two TurtleBot3 walker bags (Humble, 2023): a waffle's camera_link -> camera_rgb_frame ->
    camera_rgb_optical_frame, absent from the burger: one line (three before), whichever comes first."""
    _, found = _diff(tfx, corpus, TB3_WAFFLE, TB3_BURGER)
    lost = [(d["frame"], d["said_with"]) for d in found if d["change"] == "lost"]
    assert lost == [
        ("camera_link", ["camera_rgb_frame", "camera_rgb_optical_frame"]),
        ("caster_back_left_link", []),
        ("caster_back_right_link", []),
    ]
    assert len(found) == 8
    _, back = _diff(tfx, corpus, TB3_BURGER, TB3_WAFFLE)
    assert next(d["frame"] for d in back if d["change"] == "added") == "camera_link"


@pytest.mark.parametrize(("first", "second"), ONE_RUN_TWO_FORMATS)
def test_one_run_in_two_formats_has_no_difference(
    first: str,
    second: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The same run recorded (or converted) in two formats: the same tree, rates, values; no difference."""
    assert _diff(tfx, corpus, first, second) == (0, [])
