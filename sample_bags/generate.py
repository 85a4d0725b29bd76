"""Regenerate the sample bags: a healthy mobile manipulator recorded for 15 s, in three formats.

Run from anywhere: ``python3 sample_bags/generate.py``. It writes ``robot.bag`` (ROS1),
``robot_db3/`` (ROS2, sqlite3) and ``robot_mcap/`` (ROS2, MCAP) beside this script, replacing them.

The robot, as its publishers see it::

    map -> odom                      /amcl                     10 Hz
    odom -> base_footprint           /ekf_localization         50 Hz
    base_footprint -> base_link      /robot_state_publisher    static (/tf_static, latched)
    base_link -> laser, imu_link, camera_link, arm_base        static
    camera_link -> camera_optical_frame, arm_link6 -> gripper  static
    base_link -> left_wheel, right_wheel                       /robot_state_publisher  30 Hz
    arm_base -> arm_link1 -> ... -> arm_link6                  /arm/robot_state_publisher  50 Hz

Each message is recorded 1-5 ms after its stamp, as on a real machine.
"""

from __future__ import annotations

import math
import shutil
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository, for its test bag writer
from tests.bags import BagFormat, TfMessage, write_bag

START = 1_700_000_000 * NS_PER_S
DURATION = 15 * NS_PER_S
HERE = Path(__file__).resolve().parent
OUTPUTS = {BagFormat.ros1: "robot.bag", BagFormat.rosbag2_sqlite3: "robot_db3", BagFormat.rosbag2_mcap: "robot_mcap"}

STATIC = [
    ("base_footprint", "base_link", (0.0, 0.0, 0.09), (0.0, 0.0, 0.0)),
    ("base_link", "laser", (0.22, 0.0, 0.18), (0.0, 0.0, 0.0)),
    ("base_link", "imu_link", (0.0, 0.0, 0.05), (0.0, 0.0, 0.0)),
    ("base_link", "camera_link", (0.25, 0.0, 0.35), (0.0, 0.2, 0.0)),
    ("camera_link", "camera_optical_frame", (0.0, 0.0, 0.0), (-math.pi / 2, 0.0, -math.pi / 2)),
    ("base_link", "arm_base", (0.05, 0.0, 0.30), (0.0, 0.0, 0.0)),
    ("arm_link6", "gripper", (0.0, 0.0, 0.12), (0.0, 0.0, 0.0)),
]
ARM_LINKS = [  # parent, child, offset, joint axis
    ("arm_base", "arm_link1", (0.0, 0.0, 0.10), 2),
    ("arm_link1", "arm_link2", (0.0, 0.0, 0.12), 1),
    ("arm_link2", "arm_link3", (0.30, 0.0, 0.0), 1),
    ("arm_link3", "arm_link4", (0.25, 0.0, 0.0), 0),
    ("arm_link4", "arm_link5", (0.08, 0.0, 0.0), 1),
    ("arm_link5", "arm_link6", (0.06, 0.0, 0.0), 0),
]


def main() -> None:
    messages = sorted(robot_messages(), key=lambda m: m.record_time)
    for fmt, name in OUTPUTS.items():
        target = HERE / name
        if target.is_dir():
            shutil.rmtree(target)
        target.unlink(missing_ok=True)
        write_bag(target, messages, fmt)
        print(f"wrote {target.relative_to(HERE.parent)}")


def robot_messages() -> Iterator[TfMessage]:
    rng = np.random.default_rng(7)
    yield TfMessage("/tf_static", START + 2_000_000, [_static(*s) for s in STATIC], "/robot_state_publisher")
    yield from _periodic(rng, 10, "/amcl", lambda t: [_map_to_odom(t)])
    yield from _periodic(rng, 50, "/ekf_localization", lambda t: [_odom_to_base(t)])
    yield from _periodic(rng, 30, "/robot_state_publisher", _wheels)
    yield from _periodic(rng, 50, "/arm/robot_state_publisher", _arm)


def _periodic(
    rng: np.random.Generator, hz: int, publisher: str, make: Callable[[int], list[Transform]]
) -> Iterator[TfMessage]:
    period = NS_PER_S // hz
    phase = int(rng.integers(0, period))
    for stamp in range(START + phase, START + DURATION, period):
        stamp += int(rng.integers(-300_000, 300_000))  # scheduling jitter
        delay = int(rng.integers(1_000_000, 5_000_000))
        yield TfMessage("/tf", stamp + delay, make(stamp), publisher)


def _seconds(stamp: int) -> float:
    return (stamp - START) / NS_PER_S


def _static(parent: str, child: str, xyz: tuple[float, float, float], rpy: tuple[float, float, float]) -> Transform:
    return Transform.from_rpy(xyz, rpy, stamp=START, frame_id=parent, child_frame_id=child)


def _map_to_odom(stamp: int) -> Transform:
    s = _seconds(stamp)  # localisation slowly corrects odometry drift
    xyz = (1.5 + 0.01 * s, -0.7 + 0.004 * s, 0.0)
    return Transform.from_rpy(xyz, (0.0, 0.0, 0.3 + 0.002 * s), stamp, "map", "odom")


def _odom_to_base(stamp: int) -> Transform:
    s = _seconds(stamp)  # drives a circle of 2 m radius at 0.4 m/s
    heading = 0.2 * s
    xyz = (2.0 * math.sin(heading), 2.0 - 2.0 * math.cos(heading), 0.0)
    return Transform.from_rpy(xyz, (0.0, 0.0, heading), stamp, "odom", "base_footprint")


def _wheels(stamp: int) -> list[Transform]:
    angle = (_seconds(stamp) * 0.4 / 0.1) % (2 * math.pi)  # wheel radius 0.1 m
    return [
        Transform.from_rpy((0.0, y, 0.0), (0.0, angle * k, 0.0), stamp, "base_link", child)
        for y, k, child in ((0.2, 0.95, "left_wheel"), (-0.2, 1.05, "right_wheel"))
    ]


def _arm(stamp: int) -> list[Transform]:
    s = _seconds(stamp)
    result = []
    for i, (parent, child, offset, axis) in enumerate(ARM_LINKS):
        rpy = [0.0, 0.0, 0.0]
        rpy[axis] = 0.6 * math.sin(0.5 * s + i)
        result.append(Transform.from_rpy(offset, (rpy[0], rpy[1], rpy[2]), stamp, parent, child))
    return result


if __name__ == "__main__":
    main()
