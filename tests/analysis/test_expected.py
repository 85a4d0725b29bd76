"""The expected tree: its file, and each difference from it written into a bag of every format."""

from __future__ import annotations

import dataclasses
import io
import math
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.analysis.wtf_scenes import (
    FORMATS,
    SIM_START,
    START,
    _t,
    amcl,
    ekf,
    healthy,
    map_odom,
    odom_base,
    periodic,
    recording,
    statics,
    wheel,
    wheels,
    with_extra,
    write,
)
from tests.bags import BagFormat, TfMessage
from tftools.analysis.differences import Change, compare, describe, rotation_angle_deg
from tftools.analysis.expected import FrameShape, Tolerances, TreeShape, shape_of
from tftools.analysis.findings import Severity
from tftools.analysis.tree_file import TreeFileError, read_tree, write_tree
from tftools.analysis.wtf import CHECKS
from tftools.analysis.wtf.expectations import SHOWN
from tftools.analysis.wtf.fleet import check
from tftools.analysis.wtf.query import CheckQuery
from tftools.analysis.wtf.thresholds import Thresholds
from tftools.core.figures import STOP_FLOOR
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.recording import read_recording


def _sonar(stamp: int) -> list[Transform]:
    return [_t("base_link", "sonar", stamp, (stamp - START) * 1e-10)]


def _odom_wheel(stamp: int) -> list[Transform]:
    return [dataclasses.replace(t, frame_id="odom") for t in wheel(stamp)]


#: Each recording differs from the healthy robot in one way: (the code, the frames it must name, words).
DIFFERENT: dict[str, tuple[Callable[[], list[TfMessage]], str, tuple[str, ...], tuple[str, ...]]] = {
    "missing": (lambda: healthy(wheels=[]), "expect_missing", ("base_link", "wheel"), ("not in this recording",)),
    "new": (
        lambda: with_extra(periodic("/sonar", 10, _sonar, phase=0.01)),
        "expect_new",
        ("base_link", "sonar"),
        ("sonar is in this recording",),
    ),
    "parent": (
        lambda: healthy(wheels=periodic("/rsp", 20, _odom_wheel)),
        "expect_parent",
        ("base_link", "wheel"),
        ("a child of base_link in", "a child of odom in this recording"),
    ),
    "static_moved": (
        lambda: healthy(statics=[statics(laser_x=0.21)]),
        "expect_static",
        ("base_link", "laser"),
        ("moved by 10.0 mm and 0.00°",),
    ),
    "slower": (
        lambda: healthy(amcl=periodic("/amcl", 4, map_odom)),
        "expect_rate",
        ("map", "odom"),
        ("4.0 Hz in this recording, 10.0 Hz in", "(this recording 60% slower)"),
    ),
}


@pytest.fixture(scope="module")
def expected_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``tfx wtf --init``'s file of the healthy robot, from its ROS 1 bag (publishers named)."""
    directory = tmp_path_factory.mktemp("expected")
    bag = write(directory, "healthy", BagFormat.ros1, healthy())
    path = directory / "tree.yaml"
    with path.open("w") as out:
        write_tree(shape_of(read_recording([bag])), out)
    return path


def test_the_file_holds_the_tree_and_reads_back_the_same(expected_file: Path) -> None:
    text = expected_file.read_text()
    assert "odom: {parent: map, rate_hz: 10.0, publishers: [/amcl]}" in text
    assert "laser: {parent: base_link, static: true, translation: [0.2, 0.0, 0.1], rpy_deg: [0.0, 0.0, 0.0]" in text
    tree = read_tree(expected_file)
    assert list(tree.frames) == ["map", "odom", "base_link", "camera", "laser", "wheel"]  # from the root down
    assert tree.frames["map"].parent is None and tree.frames["wheel"].publishers == ("/rsp",)
    assert compare(tree, shape_of(read_recording([expected_file.parent / "healthy.bag"])), Tolerances()) == []


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_healthy_robot_meets_its_expected_tree_in_every_format(
    tmp_path: Path, expected_file: Path, fmt: BagFormat
) -> None:
    bag = write(tmp_path, "again", fmt, healthy())
    assert check(read_recording([bag]), CheckQuery(expected=read_tree(expected_file))).findings == []


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("name", list(DIFFERENT))
def test_each_difference_written_to_a_bag_gives_its_finding(
    tmp_path: Path, expected_file: Path, fmt: BagFormat, name: str
) -> None:
    make, code, frames, words = DIFFERENT[name]
    bag = write(tmp_path, name, fmt, make())
    findings = check(read_recording([bag]), CheckQuery(expected=read_tree(expected_file))).findings
    assert [f.code for f in findings] == [code], findings
    assert findings[0].severity is CHECKS[code].severity
    assert set(frames) <= set(findings[0].frames)
    for word in words:
        assert word in findings[0].message
    assert str(expected_file) in findings[0].message


def test_other_publishers_are_a_note_where_both_name_them(tmp_path: Path, expected_file: Path) -> None:
    renamed = periodic("/amcl_new", 10, map_odom)
    expected = read_tree(expected_file)
    ros1 = write(tmp_path, "ros1", BagFormat.ros1, healthy(amcl=renamed))
    findings = check(read_recording([ros1]), CheckQuery(expected=expected)).findings
    assert [(f.code, f.severity, f.authorities) for f in findings] == [
        ("expect_publishers", Severity.info, ("/amcl_new",))
    ]
    ros2 = write(tmp_path, "ros2", BagFormat.rosbag2_mcap, healthy(amcl=renamed))  # names topics, not nodes
    assert check(read_recording([ros2]), CheckQuery(expected=expected)).findings == []


def test_a_faster_edge_is_a_note(tmp_path: Path, expected_file: Path) -> None:
    bag = write(tmp_path, "fast", BagFormat.ros1, healthy(amcl=periodic("/amcl", 20, map_odom)))
    findings = check(read_recording([bag]), CheckQuery(expected=read_tree(expected_file))).findings
    assert [(f.code, f.severity) for f in findings] == [("expect_rate", Severity.info)]


def test_tolerances_decide_what_differs(tmp_path: Path, expected_file: Path) -> None:
    bag = write(tmp_path, "moved", BagFormat.ros1, healthy(statics=[statics(laser_x=0.21)], ekf=ekf()))
    moved = shape_of(read_recording([bag]))
    expected = read_tree(expected_file)
    assert [d.change for d in compare(expected, moved, Tolerances(translation_mm=9.9))] == [Change.moved]
    assert compare(expected, moved, Tolerances(translation_mm=10.1)) == []
    wide = dataclasses.replace(expected, tolerances=Tolerances(translation_mm=20))
    assert check(read_recording([bag]), CheckQuery(expected=wide)).findings == []


def test_a_move_of_exactly_the_tolerance_is_not_beyond_it() -> None:
    """Two TurtleBot 3 URDFs put base_scan at z 0.121 and 0.122 m: 1.0000000000000009 mm in floats, which
    tfx diff listed as 'moved by 1.0 mm' beyond its 1 mm tolerance. Exactly the tolerance is within it."""
    identity = (0.0, 0.0, 0.0, 1.0)

    def tree(z: float) -> TreeShape:
        laser = FrameShape("base_scan", "base_link", static=True, translation=(-0.064, 0.0, z), rotation=identity)
        return TreeShape({"base_link": FrameShape("base_link", None), "base_scan": laser}, "tree")

    assert 1000 * (0.122 - 0.121) > 1.0  # the float rounding this is about
    assert compare(tree(0.121), tree(0.122), Tolerances(translation_mm=1.0)) == []
    (moved,) = compare(tree(0.121), tree(0.1221), Tolerances(translation_mm=1.0))
    assert moved.change is Change.moved and moved.translation_mm == pytest.approx(1.1)


def test_a_rate_differs_the_same_whichever_tree_comes_first() -> None:
    """tfx diff measured a rate change against A alone (B / A - 1): 10 and 12.1 Hz were +21%, flagged at 20%, one
    way and -17%, not flagged, the other; neato_real_two_static_publishers_2024 against neato_real_person_marker_2025
    (odom at 4.7 and 5.5 Hz) were +18% and -15%, one flagged at --tolerance-rate 16. The slower's shortfall from the
    faster decides, either way round, worded with both rates and which is slower; a fall from an expected tree's
    rate is measured as before (4 Hz against 10: 60%)."""

    for rate, tolerance, differs in [(12.1, 20.0, False), (12.1, 17.0, True), (5.5 / 4.7 * 10, 16.0, False)]:
        ab, ba = (
            compare(_rate_tree(10.0), _rate_tree(rate), Tolerances(rate_percent=tolerance)),
            compare(_rate_tree(rate), _rate_tree(10.0), Tolerances(rate_percent=tolerance)),
        )
        assert (bool(ab), bool(ba)) == (differs, differs), (rate, tolerance)
    (faster,) = compare(_rate_tree(10.0), _rate_tree(12.1), Tolerances(rate_percent=17.0))
    (slower,) = compare(_rate_tree(12.1), _rate_tree(10.0), Tolerances(rate_percent=17.0))
    assert describe(faster) == "odom -> base at 12.1 Hz in B, 10.0 Hz in A (A 17% slower)"
    assert describe(slower) == "odom -> base at 10.0 Hz in B, 12.1 Hz in A (B 17% slower)"
    assert faster.rate_change == pytest.approx(0.21) and slower.rate_change == pytest.approx(-0.1736, abs=1e-4)
    (fell,) = compare(_rate_tree(10.0), _rate_tree(4.0), Tolerances())
    assert (
        describe(fell).endswith("(B 60% slower)")
        and compare(_rate_tree(10.0), _rate_tree(4.0), Tolerances(rate_percent=60)) == []
    )
    assert compare(_rate_tree(10.0), _rate_tree(None), Tolerances()) == []  # a rate left out of a tree file: any


def _rate_tree(hz: float | None) -> TreeShape:
    return TreeShape({"odom": FrameShape("odom", None), "base": FrameShape("base", "odom", rate_hz=hz)}, "tree")


def test_an_edge_seen_once_differs_from_a_rate_expected_not_from_any_rate() -> None:
    """A tree file's left-out ``rate_hz`` and a single sample's rate were both 0, "any rate": an edge seen once
    passed a tree expecting 10 Hz. No rate expected (None) accepts it; a rate unknown (0) differs from 10 Hz."""
    (once,) = compare(_rate_tree(10.0), _rate_tree(0.0), Tolerances())
    assert once.change is Change.rate and once.rate_change == -1.0
    assert describe(once) == "odom -> base at no rate (one sample, or none stamped apart) in B, 10.0 Hz in A"
    (back,) = compare(_rate_tree(0.0), _rate_tree(10.0), Tolerances())
    assert back.rate_change is None  # no B / A - 1 from no rate
    assert (
        compare(_rate_tree(None), _rate_tree(0.0), Tolerances()) == []
        and compare(_rate_tree(0.0), _rate_tree(0.0), Tolerances()) == []
    )


def test_a_static_edge_that_turned_is_measured_in_degrees(tmp_path: Path, expected_file: Path) -> None:
    turned = TfMessage("/tf_static", START + 1, [_t("base_link", "laser", START, 0.2, yaw=math.radians(2.0))], "/rsp")
    camera = TfMessage("/tf_static", START + 2, [_t("base_link", "camera", START, 0.1)], "/rsp")
    bag = write(tmp_path, "turned", BagFormat.rosbag2_sqlite3, healthy(statics=[turned, camera]))
    (d,) = compare(read_tree(expected_file), shape_of(read_recording([bag])), Tolerances())
    assert d.change is Change.moved and d.translation_mm == pytest.approx(0, abs=1e-9)
    assert d.rotation_deg == pytest.approx(2.0)


def test_a_frame_that_became_static_differs(tmp_path: Path, expected_file: Path) -> None:
    fixed = [TfMessage("/tf_static", START + 3, wheel(START), "/rsp")]
    bag = write(tmp_path, "fixed", BagFormat.ros1, healthy(wheels=[], amcl=amcl(), statics=[statics(), *fixed]))
    findings = check(read_recording([bag]), CheckQuery(expected=read_tree(expected_file))).findings
    assert [f.code for f in findings] == ["expect_static"]
    assert "is moving at 20.0 Hz in" in findings[0].message and "static in this recording" in findings[0].message


def test_a_static_edge_at_a_pitch_of_90_degrees_reads_back_the_same(tmp_path: Path) -> None:
    """A tree file's rpy_deg at gimbal lock: tf2's angles for the UR flange's (-0.5, -0.5, -0.5, 0.5) were
    (0, -90, 0), read back 90 degrees away, so that diff said a recording moved against its own tree file."""
    flange = FrameShape("ur_flange", "ur_wrist_3_link", True, None, None, (0.0, 0.0, 0.0), (-0.5, -0.5, -0.5, 0.5))
    tree = TreeShape({"ur_wrist_3_link": FrameShape("ur_wrist_3_link", None), "ur_flange": flange}, "ur")
    path = tmp_path / "tree.yaml"
    with path.open("w") as out:
        write_tree(tree, out)
    back = read_tree(path)
    assert "rpy_deg: [-90.0, -90.0, 0.0]" in path.read_text()
    rotation = back.frames["ur_flange"].rotation
    assert rotation is not None and rotation_angle_deg(rotation, (-0.5, -0.5, -0.5, 0.5)) < 1e-6
    assert compare(tree, back, back.tolerances) == [] and compare(back, tree, back.tolerances) == []


def test_a_hand_written_file_with_its_own_tolerances_and_quaternions(tmp_path: Path) -> None:
    path = tmp_path / "tree.yaml"
    path.write_text(
        "tolerances: {translation_mm: 5, rate_percent: 50}\n"
        "frames:\n"
        "  map:\n"
        "  odom: {parent: map}\n"
        "  laser: {parent: odom, static: true, translation: [1, 2, 3], rotation: [0, 0, 1, 0]}\n"
        "  camera: {parent: odom, static: true}\n"
    )
    tree = read_tree(path)
    assert tree.tolerances == Tolerances(translation_mm=5.0, rotation_deg=0.1, rate_percent=50.0)
    assert tree.frames["map"].parent is None and tree.frames["odom"].rate_hz is None  # any rate
    assert tree.frames["laser"].rotation == (0.0, 0.0, 1.0, 0.0)
    assert tree.frames["camera"].translation is None  # any value


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("frames: [a, b]\n", "no 'frames:' mapping"),
        ("frames: {a: {parnet: b}}\n", "unknown key 'parnet'"),
        ("frames: {a: {parent: b, rate_hz: fast}}\n", "'fast' is not a number"),
        ("frames: {a: {parent: b, rate_hz: -1}}\n", "below 0"),
        ("frames: {a: {parent: b, translation: [1, 2, 3]}}\n", "static: true"),
        ("frames: {a: {parent: b, static: true, translation: [1, 2]}}\n", "list of 3 numbers"),
        ("tolerances: {translation_mm: -1}\nframes: {}\n", "translation_mm"),
        ("frames: {a: [\n", "cannot be read"),
        ("frames: {a: {parent: b, static: true, rotation: [0, 0, 0, 0]}}\n", "not a unit quaternion (length 0)"),
        ("frames: {a: {parent: b, static: true, rotation: [0, 0, 0, 2]}}\n", "not a unit quaternion (length 2)"),
        ("frames: {a: {parent: b, static: true, rotation: [1e308, 1e308, 0, 0]}}\n", "not a unit quaternion"),
    ],
)
def test_a_bad_file_is_one_error_naming_the_problem(tmp_path: Path, text: str, words: str) -> None:
    path = tmp_path / "tree.yaml"
    path.write_text(text)
    with pytest.raises(TreeFileError, match=r"tree\.yaml") as raised:
        read_tree(path)
    assert words in str(raised.value)


def test_names_that_look_like_other_yaml_types_stay_names(tmp_path: Path) -> None:
    odd = ["null", "true", "1.5", "a: b", "#x", "'q'", "line\nbreak", "\x1b[31m"]
    messages = [TfMessage("/tf_static", START + i, [_t("map", name, START)], "/p") for i, name in enumerate(odd, 1)]
    shape = shape_of(read_recording([write(tmp_path, "odd", BagFormat.ros1, [*messages, *wheels()])]))
    text = io.StringIO()
    write_tree(shape, text)
    path = tmp_path / "odd.yaml"
    path.write_text(text.getvalue())
    assert set(odd) <= set(read_tree(path).frames)
    assert compare(shape, read_tree(path), Tolerances()) == []


def test_the_angle_between_rotations_is_sign_blind() -> None:
    q = Transform.from_rpy((0, 0, 0), (0.1, 0.2, 0.3)).rotation
    assert rotation_angle_deg(q, tuple(-v for v in q)) == pytest.approx(0, abs=1e-6)  # type: ignore[arg-type]  # 4 values
    assert rotation_angle_deg((0, 0, 0, 1), (0, 0, math.sin(0.5), math.cos(0.5))) == pytest.approx(math.degrees(1))


def test_a_topic_standing_in_for_an_unnamed_publisher_is_no_publisher_change() -> None:
    """A ROS 1 bag without callerids gives the topic as each transform's authority: not a node to compare
    (29 of the 59 differences tfx diff counted between two GrandTour calibration bags)."""
    named = shape_of(recording(healthy()))
    unnamed = shape_of(recording([TfMessage(m.topic, m.record_time, m.transforms, m.topic) for m in healthy()]))
    assert named.frames["laser"].publishers == ("/rsp",) and unnamed.frames["laser"].publishers is None
    assert compare(named, unnamed, Tolerances()) == [] == compare(unnamed, named, Tolerances())
    renamed = shape_of(recording(healthy(amcl=periodic("/amcl_new", 10, map_odom))))
    assert [(d.change, d.frame) for d in compare(named, renamed, Tolerances())] == [(Change.publishers, "odom")]


def test_an_edges_publishers_are_those_that_sent_it_under_its_latest_parent() -> None:
    """Issue 39 (ros1-neato-urdf-beside-driver-2018-bag): the URDF's /robot_state_publisher latched base_footprint ->
    base_link, the driver sends odom -> base_link: tfx diff named /robot_state_publisher a publisher of odom ->
    base_link, which it never sent."""
    urdf = TfMessage("/tf_static", START, [_t("base_footprint", "base_link", START)], "/rsp")
    beside = shape_of(recording(healthy(statics=[urdf, statics()])))
    assert beside.frames["base_link"].parent == "odom"
    assert beside.frames["base_link"].publishers == ("/ekf",)
    assert beside.frames["laser"].publishers == ("/rsp",)
    differences = compare(beside, shape_of(recording(healthy())), Tolerances())
    (static,) = [d for d in differences if d.frame == "base_link"]  # ROS 1's tf2 keeps it static
    assert describe(static) == (
        "odom -> base_link is static to tf2 though sent at 50.0 Hz on /tf (base_link's first transform came on "
        "/tf_static: ROS 1's tf2 keeps the frame static, each transform replacing its value for every time) in A, "
        "moving at 50.0 Hz in B"
    )
    ros2 = shape_of(recording(healthy(statics=[urdf, statics()]), ros1=False)).frames["base_link"]
    assert not ros2.static and ros2.on_tf_hz == 0.0  # ROS 2's tf2 made a new, moving cache
    two = healthy(ekf=sorted(ekf() + periodic("/ekf2", 50, odom_base, phase=0.01), key=lambda m: m.record_time))
    assert shape_of(recording(two)).frames["base_link"].publishers == ("/ekf", "/ekf2")  # both sent the edge


def test_an_edge_stamped_on_two_clocks_in_one_recording_only_differs(tmp_path: Path) -> None:
    """ros1-raspimouse-replay-beside-live-gmapping-2018-bag against the same robot's own run: map -> odom at 20 Hz
    in both, but in the replay half its stamps are 7 days old (the replay's beside a live gmapping's): diff said no
    difference."""
    week = 7 * 86_400 * NS_PER_S
    replayed = periodic("/replay", 10, map_odom, phase=0.05, stamp=lambda t: t - week)
    two = shape_of(recording(healthy(amcl=sorted(amcl() + replayed, key=lambda m: m.record_time))))
    one = shape_of(recording(healthy()))
    assert (two.frames["odom"].clocks, one.frames["odom"].clocks) == (2, 1)
    clocks, publishers = compare(one, two, Tolerances())  # /amcl's rate is the same in both: no rate difference
    assert (clocks.change, clocks.frame, publishers.change) == (Change.clocks, "odom", Change.publishers)
    assert describe(clocks).startswith("map -> odom is stamped on 2 clocks in B, on one clock in A (stamps further")
    assert describe(publishers) == "map -> odom published by /amcl (10.0 Hz), /replay (10.0 Hz) in B, by /amcl in A"
    assert compare(two, two, Tolerances()) == []
    written = io.StringIO()
    write_tree(two, written)  # a tree file does not say on how many clocks: no difference from it
    file = tmp_path / "tree.yaml"
    file.write_text(written.getvalue())
    assert compare(read_tree(file), two, Tolerances()) == [] == compare(two, read_tree(file), Tolerances())


def _held_wheel(y: float) -> Callable[[int], list[Transform]]:
    return lambda stamp: [Transform.from_rpy((0.0, y, 0.0), (0.0, math.pi, 0.0), stamp, "base_link", "wheel")]


def test_a_wheel_held_still_in_one_recording_and_turning_in_the_other_is_compared_by_its_origin() -> None:
    """The INESC Guardian's pallet run (corpus33) against its author's 2015 rewrite: its four wheels turning about
    (+-0.3, +-0.265, 0) in one, held still at (+-0.3, +-0.33, 0) in the other, and diff said no difference. What
    stays fixed in both, the wheel's origin, is compared as a held value is; a wheel held where the other turns
    is none, nor an odometry at rest against one driving (nothing of it stays fixed)."""
    turning = shape_of(recording(healthy()))
    moved = shape_of(recording(healthy(wheels=periodic("/rsp", 20, _held_wheel(0.265)))))
    (d,) = compare(turning, moved, Tolerances())
    assert (d.change, d.frame) == (Change.moved, "wheel")
    assert d.translation_mm == pytest.approx(65.0) and d.rotation_deg == 0.0
    said = describe(d)
    assert said.startswith(
        "base_link -> wheel (on /tf) moved by 65.0 mm (its translation, fixed in both): at xyz [0.0000, 0.2000, "
        "0.0000] m, turning by up to 1"
    )
    assert said.endswith("° in A, held at xyz [0.0000, 0.2650, 0.0000] m rpy [180.00, 0.00, 180.00]° in B"), said
    (back,) = compare(moved, turning, Tolerances())
    assert back.translation_mm == d.translation_mm
    in_place = shape_of(recording(healthy(wheels=periodic("/rsp", 20, _held_wheel(0.2)))))
    assert compare(turning, in_place, Tolerances()) == [] == compare(in_place, turning, Tolerances())
    resting = shape_of(recording(healthy(ekf=periodic("/ekf", 50, lambda t: [_t("odom", "base_link", t, 3.0)]))))
    assert resting.frames["base_link"].held is not None and turning.frames["base_link"].motion is not None
    assert compare(turning, resting, Tolerances()) == []


def test_an_edge_of_two_publishers_is_compared_publisher_by_publisher(tmp_path: Path) -> None:
    """okoslam's cartographer bags: odom -> base_link from /odometry_bridge (20 Hz) and /cartographer_node
    (198 Hz), cartographer starting 3.7 s into one of them: their sum, 149.8 against 218.6 Hz, was "A 31%
    slower" of two recordings in which each publisher kept its rate. Each publisher's rate is compared; a
    tree file, which keeps the edge's rate (the sum, as frames and monitor show it), still matches."""
    bridge = periodic("/bridge", 20, odom_base, phase=0.003)
    late = shape_of(recording(healthy(ekf=sorted(ekf(start=4.0) + bridge, key=lambda m: m.record_time))))
    whole = shape_of(recording(healthy(ekf=sorted(ekf() + bridge, key=lambda m: m.record_time))))
    assert [(r.source, round(r.rate_hz, 1)) for r in whole.frames["base_link"].rates] == [
        ("/bridge", 20.0),
        ("/ekf", 50.0),
    ]
    sums = late.frames["base_link"].rate_hz or 0.0, whole.frames["base_link"].rate_hz or 0.0
    assert 0 < sums[0] < 0.75 * sums[1]  # the sums are apart
    assert compare(late, whole, Tolerances()) == [] == compare(whole, late, Tolerances())
    slow = shape_of(
        recording(healthy(ekf=sorted(periodic("/ekf", 25, odom_base) + bridge, key=lambda m: m.record_time)))
    )
    (d,) = compare(whole, slow, Tolerances())
    assert (d.change, d.source) == (Change.rate, "/ekf") and d.rate_change == pytest.approx(-0.5)
    assert describe(d) == "odom -> base_link from /ekf at 25.0 Hz in B, 50.0 Hz in A (B 50% slower)"
    written = io.StringIO()
    write_tree(late, written)
    file = tmp_path / "tree.yaml"
    file.write_text(written.getvalue())
    assert compare(read_tree(file), late, Tolerances()) == [] == compare(late, read_tree(file), Tolerances())
    (summed,) = compare(read_tree(file), whole, Tolerances())  # the file knows the sum only: the sums compared
    assert describe(summed).endswith("; B's is the sum of its 2 sources' (/bridge 20.0 Hz, /ekf 50.0 Hz)")


def test_rates_on_a_slow_simulations_clock_and_a_wall_clock_are_not_compared() -> None:
    """The JetAcker pair (ros2-jetacker-gazebo-slam-toolbox-static-map-2025-db3 against its real robot):
    odom -> base_footprint at 33.3 Hz of a simulation advancing 0.066 s a second against 3.9 Hz of a wall clock
    was "B 88% slower". Those are seconds of different lengths: said so, with the rate on the recording's clock;
    a simulation at real time is compared with the wall clock as before."""
    real = shape_of(recording(healthy()))
    slow = shape_of(recording(healthy(ekf=ekf(stamp=lambda t: SIM_START + (t - START) // 15))))
    assert real.frames["base_link"].epoch and slow.frames["base_link"].epoch is False
    assert slow.frames["base_link"].pace == pytest.approx(1 / 15, rel=0.01)
    (d,) = compare(slow, real, Tolerances())
    assert (d.change, d.frame) == (Change.clocks, "base_link")
    assert describe(d) == (
        "odom -> base_link is stamped on a wall clock (from the epoch) in B, on a clock from a start (simulated "
        "time, or a boot's) advancing 0.067 s a second of its recording in A: 50.0 Hz in B and 750.0 Hz of A's "
        "clock (50.0 Hz of its recording's) in A count seconds of different lengths, not compared as rates"
    )
    at_real_time = shape_of(
        recording(healthy(ekf=periodic("/ekf", 25, odom_base, stamp=lambda t: SIM_START + t - START)))
    )
    (rate,) = compare(real, at_real_time, Tolerances())
    assert rate.change is Change.rate and describe(rate).endswith("(B 50% slower)")


def test_many_differences_of_a_kind_are_said_a_few_then_counted(tmp_path: Path, expected_file: Path) -> None:
    """A tree file of 100,000 frames against another recording made a finding a frame: 20 MB of output."""
    path = tmp_path / "big.yaml"
    extra = "".join(f"  x{k}: {{parent: map}}\n" for k in range(40))
    path.write_text(expected_file.read_text() + extra)
    findings = check(
        read_recording([expected_file.parent / "healthy.bag"]), CheckQuery(expected=read_tree(path))
    ).findings
    missing = [f for f in findings if f.code == "expect_missing"]
    assert len(missing) == SHOWN + 1
    assert all("x" + str(k) + " is in" in f.message for k, f in enumerate(missing[:SHOWN]))
    last = missing[-1]
    assert last.message == (
        f"{40 - SHOWN} more frames as above (a frame of the expected tree is missing): "
        f"x{SHOWN}, x{SHOWN + 1}, x{SHOWN + 2}, x{SHOWN + 3}, x{SHOWN + 4}, and {40 - SHOWN - 5} others"
    )
    assert last.severity is Severity.error and last.frames == tuple(f"x{SHOWN + k}" for k in range(5))


def test_an_edge_that_stopped_early_in_one_recording_only_is_said_once_with_its_figures() -> None:
    """The CSCE 452 disc robot's simulator (corpus: world -> base_link sent for 0.5 s of 10.7 s in one run, to the
    end in another): diff said nothing of it. An edge that stops (``figures.stopped``) in one recording and is sent
    to the end in the other differs, once, with when it last arrived against its recording's length; not where
    both stop, nor where a recording simply ends sooner (every edge sent to its end)."""
    whole = shape_of(recording(healthy()))
    stops = shape_of(recording(healthy(ekf=ekf(end=4.0), statics=[statics()], wheels=wheels())))
    (d,) = compare(whole, stops, Tolerances())
    assert (d.change, d.frame) == (Change.stopped, "base_link")
    assert describe(d).startswith("odom -> base_link stopped early in B: its last sample (stamped 1700000003.980) ")
    assert describe(d).endswith(
        "arrived 4.0 s into B's 9.9 s, silent for its last 6.0 s; in A it was sent to the end (10.0 s of 10.0 s)"
    ), describe(d)
    (back,) = compare(stops, whole, Tolerances())
    assert describe(back).startswith("odom -> base_link stopped early in A: ")
    assert compare(stops, stops, Tolerances()) == []
    shorter = shape_of(recording(healthy(amcl=amcl(end=4.0), ekf=ekf(end=4.0), wheels=wheels(end=4.0))))
    assert not [d for d in compare(whole, shorter, Tolerances()) if d.change is Change.stopped]
    assert Thresholds().stale_after * NS_PER_S == STOP_FLOOR  # a stop is the same to diff as to wtf's stale


def test_an_edge_that_stopped_in_both_recordings_at_points_far_apart_is_said_with_each_point() -> None:
    """Two runs whose odometry both stopped: in one at 4 s of 9.9, in the other at 8 s. diff compared only whether
    it stopped, not where: nothing said. Points further apart than the edge's own rate explains (10 periods at 50 Hz,
    at least ``STOP_FLOOR``) differ, with each last arrival against its recording's length; points 0.5 s apart
    do not, nor an edge stopped at one point in both."""
    early = shape_of(recording(healthy(ekf=ekf(end=4.0))))
    late = shape_of(recording(healthy(ekf=ekf(end=8.0))))
    (d,) = compare(early, late, Tolerances())
    assert (d.change, d.frame) == (Change.stopped, "base_link")
    assert describe(d) == (
        "odom -> base_link stopped early in both, at points 4.0 s apart (more than its 50.0 Hz explains: 1.0 s): "
        "in A its last sample (stamped 1700000003.980) arrived 4.0 s into A's 9.9 s, silent for its last 6.0 s; "
        "in B (stamped 1700000007.980) arrived 8.0 s into B's 9.9 s, silent for its last 2.0 s"
    ), describe(d)
    near = shape_of(recording(healthy(ekf=ekf(end=4.5))))
    assert compare(early, near, Tolerances()) == []
    assert compare(late, late, Tolerances()) == []


def _jittered(y: float, noise: float) -> Callable[[int], list[Transform]]:
    """A wheel held at (0, y, 0) whose every sample differs from the last at float rounding (``noise`` m and rad)."""
    return lambda stamp: [
        Transform.from_rpy(
            (0.0, y + noise * (stamp % 3), 0.0), (noise * (stamp % 5), math.pi, 0.0), stamp, "base_link", "wheel"
        )
    ]


def test_a_held_edge_jittering_at_float_rounding_is_held_and_compared_whole() -> None:
    """The UR5 of ros2-ur5-two-clocks-topic-tf-2023-db3: its arm's joints held still on /tf for the whole
    recording, each sample apart from the first by 1e-15 m. Exact equality called them moving, so diff compared
    their translation only ("turning by up to 0.00°") and missed their rotations, 115° apart from another UR5's.
    Within ``figures.HELD_M`` and ``HELD_DEG`` a value is held; beyond, it moves."""
    rounding = shape_of(recording(healthy(wheels=periodic("/rsp", 20, _jittered(0.265, 1e-12)))))
    assert rounding.frames["wheel"].held is not None and rounding.frames["wheel"].motion is None
    exact = shape_of(recording(healthy(wheels=periodic("/rsp", 20, _held_wheel(0.265)))))
    assert compare(rounding, exact, Tolerances()) == []
    creeping = shape_of(recording(healthy(wheels=periodic("/rsp", 20, _jittered(0.265, 1e-4)))))
    assert creeping.frames["wheel"].held is None and creeping.frames["wheel"].motion is not None


def test_a_static_re_published_with_tiny_noise_is_one_value() -> None:
    """A static edge sent again on /tf_static with values apart at float rounding is one value (no "received 2
    values", no reordering to tell), and to wtf no changing transform on /tf_static."""
    first = statics()
    noisy = dataclasses.replace(
        statics(record=START + 5 * NS_PER_S),
        transforms=[
            dataclasses.replace(t, translation=(t.translation[0] + 1e-10, t.translation[1], t.translation[2] - 1e-10))
            for t in first.transforms
        ],
    )
    shape = shape_of(recording(healthy(statics=[first, noisy])))
    assert shape.frames["laser"].static and shape.frames["laser"].received == ()
    report = check(recording(healthy(statics=[first, noisy])), CheckQuery())
    assert "dynamic_on_static" not in {f.code for f in report.findings}
