"""A ROS 1 robot whose URDF (robot_state_publisher's /tf_static, latched an hour before recording) puts
base_link under base_footprint and the laser at one place, while its driver sends odom -> base_link and a tf1
static_transform_publisher the laser elsewhere on /tf (corpus ros1-neato-urdf-beside-driver-2018-bag: a real
CompRobo Neato, the laser 109.6 mm apart). Times count from the /tf data, base_link's two parents are one cause
with its two topics and the split tree beneath, and the laser's two values are said with how far apart."""

from __future__ import annotations

import re

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START, MS = scenes.START, scenes.MS
LATCHED = START - 3452 * NS_PER_S  # robot_state_publisher started an hour before the recording


def _t(parent: str, child: str, stamp: int, x: float, z: float = 0.0) -> Transform:
    return Transform.from_rpy((x, 0.0, z), (0.0, 0.0, 0.0), stamp, parent, child)


def neato(urdf_at: int = START) -> list[TfMessage]:
    urdf = TfMessage(
        "/tf_static",
        urdf_at,
        [_t("base_footprint", "base_link", LATCHED, 0.0, 0.0102), _t("base_link", "laser", LATCHED, 0.0, 0.13)],
        "/robot_state_publisher",
    )
    driver = scenes.periodic("/neato", 5, lambda t: [_t("odom", "base_link", t, 0.05 * scenes._s(t))], start=0.1)
    laser = scenes.periodic("/laser_to_base", 20, lambda t: [_t("base_link", "laser", t, -0.1016, 0.0889)])
    return sorted([urdf, *driver, *laser], key=lambda m: m.record_time)


def findings() -> list[Finding]:
    return check(scenes.recording(neato(), ros1=True)).findings


def test_times_count_from_the_tf_data_not_from_a_static_latched_an_hour_before() -> None:
    offsets = [float(s) for f in findings() for s in re.findall(r"\(\+(\d+\.\d) s\)", f.message)]
    assert offsets and max(offsets) <= scenes.SECONDS


def test_a_frame_under_the_urdfs_parent_and_the_drivers_is_one_cause() -> None:
    found = findings()
    (parents,) = [f for f in found if f.code == "multiple_parents"]
    beneath = sorted(f.code for f in found if f.cause == parents.key)
    assert parents.key and beneath == ["disconnected", "mixed_static"]
    (laser,) = [f for f in found if f.code == "mixed_static" and f.frames[0] == "laser"]
    assert not laser.cause and "one value on each, 109.6 mm and 0.00° apart" in laser.message


def test_one_transform_is_said_at_its_moment_not_as_a_span() -> None:
    """The real Neato's URDF arrived 0.1 s before the first /tf stamp: its one transform of base_link was said
    "from -0.1 s to -0.1 s"."""
    found = check(scenes.recording(neato(urdf_at=START - 100 * MS), ros1=True)).findings
    (parents,) = [f for f in found if f.code == "multiple_parents"]
    assert "base_footprint (by /robot_state_publisher, 1 transform 0.1 s before the first tf stamp)" in parents.message
    assert re.search(r"odom \(by /neato, \d+ transforms from \+0\.1 s to \+\d+\.\d s\)", parents.message), (
        parents.message
    )
    assert not re.search(r"from (\S+ s) to \1", parents.message)
