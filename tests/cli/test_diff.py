"""``tfx diff A B`` and ``tfx wtf --init`` / ``--expect`` as a user runs them, on bags of every format."""

from __future__ import annotations

import dataclasses
import json
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest

from tests.analysis.wtf_scenes import DELAY, FORMATS, MS, START, healthy, map_odom, periodic, statics, wheels, write
from tests.bags import BagFormat, TfMessage
from tests.cli.conftest import Tfx
from tests.cli.test_filter import scan, sensor_bags
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A healthy run (ROS 1), the same run again in each format, and a run whose laser moved 10 mm
    and whose localization slowed to 4 Hz, in each format."""
    directory = tmp_path_factory.mktemp("runs")
    made = {"good": write(directory, "good", BagFormat.ros1, healthy())}
    for fmt in FORMATS:
        made[f"same_{fmt.value}"] = write(directory, "same", fmt, healthy())
        changed = healthy(statics=[statics(laser_x=0.21)], amcl=periodic("/amcl", 4, map_odom))
        made[f"changed_{fmt.value}"] = write(directory, "changed", fmt, changed)
    return made


@pytest.mark.parametrize("fmt", FORMATS)
def test_diff_of_the_same_run_in_another_format_is_empty_and_exits_0(
    tfx: Tfx, runs: dict[str, Path], fmt: BagFormat
) -> None:
    result = tfx("diff", runs["good"], runs[f"same_{fmt.value}"])
    assert result.code == 0, result.stderr
    assert "no differences beyond the tolerances (1 mm, 0.1°, rates 20%)" in result.stdout


@pytest.mark.parametrize("fmt", FORMATS)
def test_diff_says_how_far_a_static_edge_moved_and_how_a_rate_fell(
    tfx: Tfx, runs: dict[str, Path], fmt: BagFormat
) -> None:
    result = tfx("diff", runs["good"], runs[f"changed_{fmt.value}"])
    assert result.code == 1
    assert "moved       base_link -> laser (static) moved by 10.0 mm and 0.00°" in result.stdout
    assert "rate        map -> odom at 4.0 Hz in B, 10.0 Hz in A (B 60% slower)" in result.stdout
    assert "2 differences beyond the tolerances" in result.stdout
    loose = tfx("diff", runs["good"], runs[f"changed_{fmt.value}"], "--tolerance-mm", "11", "--tolerance-rate", "70")
    assert loose.code == 0, loose.stdout


def test_diff_json_lists_each_difference_with_its_figures(tfx: Tfx, runs: dict[str, Path]) -> None:
    result = tfx("diff", runs["good"], runs["changed_rosbag2-mcap"], "--format", "json")
    document = json.loads(result.stdout)
    assert result.code == document["exit_code"] == 1 and document["differ"]
    by_change = {d["change"]: d for d in document["differences"]}
    assert set(by_change) == {"moved", "rate"}
    assert by_change["moved"]["translation_mm"] == pytest.approx(10.0)
    assert by_change["moved"]["a"]["translation"] == pytest.approx([0.2, 0.0, 0.1])
    assert by_change["moved"]["b"]["translation"] == pytest.approx([0.21, 0.0, 0.1])
    assert by_change["rate"]["rate_change"] == pytest.approx(-0.6, abs=0.01)


def _mount_on_tf(laser_y: float) -> list[TfMessage]:
    """A healthy run whose laser mount is sent on /tf at 50 Hz, never changing (robot_state_publisher's fixed
    joints before /tf_static, the real 2014 Guardian's), at y = ``laser_y``; its wheel turns."""

    def mount(stamp: int) -> list[Transform]:
        return [Transform.from_rpy((0.018, laser_y, 0.06), (0.0, 0.0, 0.0), stamp, "base_link", "front_laser")]

    return healthy(wheels=[*periodic("/rsp", 20, _turning_wheel), *periodic("/rsp", 50, mount)])


def _turning_wheel(stamp: int) -> list[Transform]:
    return [
        Transform.from_rpy((0.0, 0.3, 0.0), (0.0, 0.05 * (stamp - START) / MS / 1000, 0.0), stamp, "base_link", "wheel")
    ]


def test_diff_says_how_far_a_mount_sent_on_tf_moved_never_changing_in_either(tfx: Tfx, tmp_path: Path) -> None:
    """The real Guardian of September and December 2014 (ros1-robotnik-guardian-...-2014-bag beside its
    guardian_3.bag): its front laser's fixed joint, on /tf at 50 Hz, sat 40 mm apart and diff said nothing, as it
    compared the values of /tf_static's edges only. A turning joint is no value to compare."""
    before = write(tmp_path, "september", BagFormat.ros1, _mount_on_tf(0.0))
    after = write(tmp_path, "december", BagFormat.ros1, _mount_on_tf(0.04))
    result = tfx("diff", before, after)
    assert result.code == 1, result.stdout
    assert "base_link -> front_laser (on /tf, never changing in either) moved by 40.0 mm and 0.00°" in result.stdout
    assert "1 difference beyond the tolerances" in result.stdout, result.stdout
    assert tfx("diff", before, write(tmp_path, "again", BagFormat.ros1, _mount_on_tf(0.0))).code == 0


def _tf1_robot(torso_z: float, camera_x: float) -> list[TfMessage]:
    """A healthy run whose /rsp sends its joints in one message at 25 Hz (the wheel turning, the torso and the arm
    held still) and its fixed transforms in another at 50 Hz (tf1's robot_state_publisher, the real PR2's)."""

    def joints(stamp: int) -> list[Transform]:
        return [
            *_turning_wheel(stamp),
            Transform.from_rpy((-0.05, 0.0, torso_z), (0.0, 0.0, 0.0), stamp, "base_link", "torso"),
            Transform.from_rpy((0.0, 0.19, 0.0), (0.0, 0.0, 0.4), stamp, "torso", "arm"),
        ]

    def fixed(stamp: int) -> list[Transform]:
        return [
            Transform.from_rpy((0.2, 0.0, 0.3), (0.0, 0.0, 0.0), stamp, "base_link", "laser_mount"),
            Transform.from_rpy((camera_x, 0.06, 0.04), (0.0, 0.0, 0.0), stamp, "torso", "head_camera"),
        ]

    return healthy(wheels=[*periodic("/rsp", 25, joints), *periodic("/rsp", 50, fixed, phase=0.003)])


def test_diff_tells_a_joint_held_elsewhere_from_a_calibration(tfx: Tfx, tmp_path: Path) -> None:
    """The real PR2 of JSK in October and January 2012 (tf1: every edge on /tf, the robot still): its torso held
    98 mm lower and its stereo camera's mount 23 mm apart were both 'moved (on /tf, never changing in either)'.
    An edge that came with the joints that move is a joint held elsewhere, one that came with the fixed
    transforms a calibration; the frames beneath are not differences of their own."""
    before = write(tmp_path, "october", BagFormat.ros1, _tf1_robot(0.85, 0.035))
    after = write(tmp_path, "january", BagFormat.ros1, _tf1_robot(0.75, 0.057))
    result = tfx("diff", before, after, "--format", "json")
    found = {d["frame"]: d for d in json.loads(result.stdout)["differences"]}
    assert sorted(found) == ["head_camera", "torso"], found
    torso, camera = found["torso"], found["head_camera"]
    assert (torso["part"], torso["beneath"], round(torso["translation_mm"], 1)) == ("joint", 2, 100.0)
    assert torso["message"] == (
        "base_link -> torso, a joint (it came with the joints that move), held at positions 100.0 mm and 0.00° "
        "apart: xyz [-0.0500, 0.0000, 0.8500] m rpy [0.00, 0.00, 0.00]° in A, xyz [-0.0500, 0.0000, 0.7500] m rpy "
        "[0.00, 0.00, 0.00]° in B; the 2 frames beneath it moved with it"
    )
    assert (camera["part"], camera["beneath"], round(camera["translation_mm"], 1)) == ("fixed", 0, 22.0)
    assert camera["message"].startswith(
        "torso -> head_camera, a fixed part (it came with the fixed transforms, apart from the joints), set 22.0 mm "
        "and 0.00° apart (a calibration, or another description of the robot): xyz [0.0350, 0.0600, 0.0400] m"
    ), camera["message"]
    assert result.code == 1


def _laser_held_on_tf(laser_x: float) -> list[TfMessage]:
    """A healthy run whose simulator sends the laser mount on /tf at 50 Hz, never changing, at x = ``laser_x``
    (the camera stays on /tf_static, the wheel turns about the healthy run's origin)."""
    camera = Transform.from_rpy((0.1, 0.0, 0.1), (0.0, 0.0, 0.0), START, "base_link", "camera")

    def laser(stamp: int) -> list[Transform]:
        return [Transform.from_rpy((laser_x, 0.0, 0.1), (0.0, 0.0, 0.0), stamp, "base_link", "laser")]

    statics_of_the_camera = [TfMessage("/tf_static", START + DELAY, [camera], "/rsp")]
    return healthy(statics=statics_of_the_camera, wheels=[*wheels(), *periodic("/sim", 50, laser)])


def test_diff_says_how_far_a_mount_moved_static_in_one_held_on_tf_in_the_other(tfx: Tfx, tmp_path: Path) -> None:
    """MIT's real RSS racecar (static_transform_publisher: laser at (0.285, 0, 0.127)) beside the course's
    racecar_simulator (the laser on /tf at 50 Hz at (0.275, 0, 0)): diff said the edge was static in one and
    moving in the other, not that the mount sat 127 mm apart. Within the tolerance it says only the former."""
    real = write(tmp_path, "real", BagFormat.ros1, healthy())  # the laser on /tf_static at x = 0.2
    result = tfx("diff", real, write(tmp_path, "sim", BagFormat.ros1, _laser_held_on_tf(0.26)))
    assert result.code == 1, result.stdout
    assert "static      base_link -> laser is static in A, moving at 50.0 Hz in B" in result.stdout, result.stdout
    assert (
        "moved       base_link -> laser moved by 60.0 mm and 0.00°: xyz [0.2000, 0.0000, 0.1000] m rpy [0.00, 0.00, "
        "0.00]° in A (static), xyz [0.2600, 0.0000, 0.1000] m rpy [0.00, 0.00, 0.00]° in B (on /tf, never changing)"
    ) in result.stdout, result.stdout
    same_place = tfx("diff", real, write(tmp_path, "sim_same", BagFormat.ros1, _laser_held_on_tf(0.2)))
    assert "moved" not in same_place.stdout and "is static in A" in same_place.stdout, same_place.stdout


def _two_localizers(amcl_hz: float, second_from: float) -> list[TfMessage]:
    """A healthy run whose map -> odom comes from /amcl at ``amcl_hz`` and from /slam at 10 Hz from ``second_from``
    s on (okoslam's odom -> base_link: a bridge's 20 Hz beside cartographer's 198 Hz from +3.7 s)."""
    slam = periodic("/slam", 10, map_odom, start=second_from, phase=0.003)
    return healthy(amcl=sorted(periodic("/amcl", amcl_hz, map_odom) + slam, key=lambda m: m.record_time))


def test_diff_compares_an_edges_two_publishers_each_on_its_own(tfx: Tfx, tmp_path: Path) -> None:
    """okoslam's cartographer bags: two publishers of one edge, one starting late in one recording, were "A 31%
    slower" (their sum over spans that differ) though each kept its rate. Each publisher's rate is compared, and
    the JSON says whose (``source``)."""
    late = write(tmp_path, "late", BagFormat.ros1, _two_localizers(10, 4.0))
    whole = write(tmp_path, "whole", BagFormat.ros1, _two_localizers(10, 0.0))
    assert tfx("diff", late, whole).code == 0
    slow = write(tmp_path, "slow", BagFormat.ros1, _two_localizers(4, 0.0))
    result = tfx("diff", whole, slow, "--format", "json")
    (rate,) = json.loads(result.stdout)["differences"]
    assert (rate["change"], rate["source"], round(rate["rate_change"], 2)) == ("rate", "/amcl", -0.6)
    assert rate["message"] == "map -> odom from /amcl at 4.0 Hz in B, 10.0 Hz in A (B 60% slower)"
    assert [(r["source"], round(r["rate_hz"], 1)) for r in rate["a"]["rates"]] == [("/amcl", 10.0), ("/slam", 10.0)]
    assert result.code == 1


def _two_static_publishers(laser_first: bool) -> list[TfMessage]:
    """A healthy run whose /tf_static also carries a driver's laser-only message at x = 0.3 m beside
    robot_state_publisher's 0.2 m, 4 ms apart: the driver's first (tf2 keeps 0.2) or last (tf2 keeps 0.3)."""
    laser = Transform.from_rpy((0.3, 0.0, 0.1), (0.0, 0.0, 0.0), START, "base_link", "laser")
    driver = TfMessage("/tf_static", START + DELAY, [laser], "/driver")
    urdf = statics(record=START + DELAY)
    first, second = (driver, urdf) if laser_first else (urdf, driver)
    return healthy(statics=[first, dataclasses.replace(second, record_time=START + DELAY + 4 * MS)])


@pytest.mark.parametrize("fmt", [BagFormat.ros1, BagFormat.rosbag2_sqlite3])
def test_diff_of_the_same_two_static_values_in_another_order_says_so_not_that_the_edge_moved(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat
) -> None:
    """The real Neatos (person_marker_2025, static_conflict_urdf_first_2025): the same two laser values in both,
    only their order differs, so tf2 keeps another one in each."""
    a = write(tmp_path, "a", fmt, _two_static_publishers(laser_first=True))
    b = write(tmp_path, "b", fmt, _two_static_publishers(laser_first=False))
    result = tfx("diff", a, b)
    assert result.code == 1
    line = next(line for line in result.stdout.splitlines() if "laser" in line)
    assert line.split()[0] == "reordered" and "moved" not in line
    assert "A and B each received the same 2 values of it on /tf_static, in another order" in line
    assert "A xyz [0.3000, 0.0000, 0.1000] m rpy [0.00, 0.00, 0.00]° (at 0.000 s) then xyz [0.2000," in line
    assert "B xyz [0.2000, 0.0000, 0.1000] m rpy [0.00, 0.00, 0.00]° (at 0.000 s) then xyz [0.3000," in line
    assert "(at 0.004 s)" in line
    assert line.endswith("the order alone makes the kept values 100.0 mm and 0.00° apart")
    document = json.loads(tfx("diff", a, b, "--format", "json").stdout)
    (laser,) = document["differences"]
    assert laser["change"] == "reordered" and laser["translation_mm"] == pytest.approx(100.0)
    assert [v["translation"][0] for v in laser["a"]["received"]] == pytest.approx([0.3, 0.2])


def test_diff_of_a_static_edge_moved_names_the_values_one_side_received(
    tfx: Tfx, runs: dict[str, Path], tmp_path: Path
) -> None:
    """Where only one side received several values, the kept one moved, and which values came is said."""
    a = write(tmp_path, "a", BagFormat.rosbag2_sqlite3, _two_static_publishers(laser_first=False))
    result = tfx("diff", a, runs["good"])
    line = next(line for line in result.stdout.splitlines() if "laser" in line)
    assert line.startswith("  moved       base_link -> laser (static) moved by 100.0 mm")
    assert line.endswith(
        "; A received 2 values of it on /tf_static (xyz [0.2000, 0.0000, 0.1000] m rpy [0.00, 0.00, 0.00]° "
        "(at 0.000 s) then xyz [0.3000, 0.0000, 0.1000] m rpy [0.00, 0.00, 0.00]° (at 0.004 s)), tf2 keeps the last"
    )


def test_diff_of_a_tree_file_and_a_recording_uses_the_files_tolerances(
    tfx: Tfx, runs: dict[str, Path], tmp_path: Path
) -> None:
    init = tfx("wtf", "--init", runs["good"])
    assert init.code == 0, init.stderr
    tree = tmp_path / "tree.yaml"
    tree.write_text(init.stdout.replace("translation_mm: 1.0", "translation_mm: 15.0"))
    result = tfx("diff", tree, runs["changed_rosbag2-sqlite3"])
    assert result.code == 1
    assert [line.split()[0] for line in result.stdout.splitlines()[2:-1]] == ["rate"]  # the laser's 10 mm: within
    assert "(15 mm, 0.1°, rates 20%)" in result.stdout


def test_diff_of_unusable_input_exits_2_with_one_line(tfx: Tfx, runs: dict[str, Path], tmp_path: Path) -> None:
    missing = tfx("diff", runs["good"], tmp_path / "nope.bag")
    assert missing.code == 2 and missing.stderr.count("\n") == 1 and "nope.bag" in missing.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text("frames: {a: {parnet: b}}\n")
    broken = tfx("diff", bad, runs["good"])
    assert broken.code == 2 and "unknown key 'parnet'" in broken.stderr and "Traceback" not in broken.stderr
    negative = tfx("diff", runs["good"], runs["good"], "--tolerance-mm", "-1")
    assert negative.code == 2 and "translation_mm" in negative.stderr


@pytest.mark.parametrize("fmt", FORMATS)
def test_wtf_expect_reports_what_differs_from_the_init_file(
    tfx: Tfx, runs: dict[str, Path], tmp_path: Path, fmt: BagFormat
) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text(tfx("wtf", "--init", runs["good"]).stdout)
    assert tfx("wtf", "--expect", tree, runs[f"same_{fmt.value}"]).code == 0
    result = tfx("wtf", "--expect", tree, runs[f"changed_{fmt.value}"], "--format", "json")
    assert result.code == 1
    findings = json.loads(result.stdout)["bags"][0]["findings"]
    assert [(f["code"], f["severity"]) for f in findings] == [("expect_static", "error"), ("expect_rate", "warning")]
    loose = tfx("wtf", "--expect", tree, runs[f"changed_{fmt.value}"], "--tolerance-mm", "11", "--strict")
    assert loose.code == 1 and "expect_static" not in loose.stdout and "expect_rate" in loose.stdout


def test_wtf_expect_findings_reach_junit_and_can_be_ignored(tfx: Tfx, runs: dict[str, Path], tmp_path: Path) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text(tfx("wtf", "--init", runs["good"]).stdout)
    junit = ET.fromstring(tfx("wtf", "--expect", tree, runs["changed_ros1"], "--format", "junit").stdout)
    failed = {case.get("name") for case in junit.iter("testcase") if case.find("failure") is not None}
    assert "expect_static" in failed
    ignored = tfx("wtf", "--expect", tree, runs["changed_ros1"], "--ignore", "expect_static")
    assert ignored.code == 0 and "expect_rate" in ignored.stdout


def test_wtf_init_and_tolerances_refuse_what_cannot_work(tfx: Tfx, runs: dict[str, Path]) -> None:
    two = tfx("wtf", "--init", runs["good"], runs["same_ros1"])
    assert two.code == 2 and "one recording" in two.stderr
    assert tfx("wtf", runs["good"], "--tolerance-mm", "2").code == 2
    missing = tfx("wtf", "--expect", "nope.yaml", runs["good"])
    assert missing.code == 2 and "nope.yaml: no such file" in missing.stderr


def test_a_recording_without_transforms_is_an_empty_tree_not_unusable(
    tfx: Tfx, runs: dict[str, Path], tmp_path: Path
) -> None:
    """`tfx diff A A` of a recording holding no transforms (the corpus's nine no-tf recordings) exited 2 'no
    transforms': no differences, exit 0; against a recording with tf, every frame of that one differs. Transforms
    on a topic not read (an /odom_tf of tf2_msgs) are still an error, with the --topic that reads them."""
    bag = sensor_bags(tmp_path, [], _scans)["db3"]
    itself = tfx("diff", bag, bag)
    assert itself.code == 0, itself.stderr
    assert f"A: {bag} (0 frames: no transforms on /tf, /tf_static)" in itself.stdout
    assert "no differences beyond the tolerances" in itself.stdout
    init = tfx("wtf", "--init", bag)  # its tree file: no frames, said so
    assert init.code == 0 and "frames: {}" in init.stdout and "the tree file has no frames" in init.stderr
    (tmp_path / "tree.yaml").write_text(init.stdout)
    assert tfx("diff", bag, tmp_path / "tree.yaml").code == tfx("diff", tmp_path / "tree.yaml", bag).code == 0
    against = json.loads(tfx("diff", runs["good"], bag, "--format", "json").stdout)
    assert against["exit_code"] == 1 and {d["change"] for d in against["differences"]} == {"lost"}
    assert against["b_empty"] == "no transforms on /tf, /tf_static" and against["a_empty"] is None, against
    elsewhere = [TfMessage("/odom_tf", START + i, [], "/x") for i in range(3)]
    other = write(tmp_path, "odom_only", BagFormat.rosbag2_sqlite3, elsewhere)
    refused = tfx("diff", other, other)
    assert refused.code == 2 and "read with --topic /odom_tf" in refused.stderr, refused.stderr


def _scans(store: Any) -> list[tuple[str, str, int, object]]:
    """Three laser scans, a second apart: a recording without tf."""
    return [
        ("/scan", "sensor_msgs/msg/LaserScan", t, scan(store, "laser", t))
        for t in (START + NS_PER_S * i for i in (1, 2, 3))
    ]
