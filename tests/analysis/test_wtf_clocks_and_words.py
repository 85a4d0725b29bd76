"""Issue 39: one time base per question, ROS 2's words on ROS 2 data, each check's severity as listed."""

from __future__ import annotations

import dataclasses
import io
import re
from pathlib import Path

import numpy as np
import pytest
from rich.console import Console

from tests.analysis.wtf_scenes import (
    DELAY,
    MS,
    PROBLEMS,
    SECONDS,
    SIM_START,
    START,
    _s,
    _t,
    amcl,
    ekf,
    healthy,
    map_odom,
    periodic,
    recording,
    sensor,
    sim,
    sim_clock,
    simulated,
    statics,
    wheels,
    with_extra,
    write,
)
from tests.bags import BagFormat, TfMessage
from tftools.analysis.description import Robot
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.graph import view_frames
from tftools.analysis.monitor import MonitorQuery, chain_span, monitor
from tftools.analysis.times import parse_time_spec
from tftools.analysis.wtf import CHECKS, Scene, findings_of
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.filter import as_dict as filter_dict
from tftools.render.filter import renderable as filter_text
from tftools.sources import read_recording
from tftools.sources.contents import ClockSamples, StampedMessages
from tftools.sources.recording import Recording
from tftools.sources.urdf import parse_urdf


def _codes(findings: list[Finding]) -> list[tuple[str, Severity]]:
    return [(f.code, f.severity) for f in findings]


@pytest.mark.parametrize("with_reference", [False, True], ids=["sim-on-wall", "wall"])
def test_a_stamp_frozen_in_the_past_is_stale_not_a_second_clock(with_reference: bool) -> None:
    """map -> odom re-sent 1,000 times with one stamp 91 s old, on the other frames' clock: stale (its stamp
    stood still, which says nothing of its clock), said with how often it was sent and ROS 2's command."""
    make = (lambda **kw: with_extra(**kw)) if with_reference else simulated
    frozen = (START if with_reference else sim(START)) - 91 * NS_PER_S
    findings = check(
        recording(make(amcl=periodic("/amcl", 100, map_odom, stamp=lambda t: frozen)), ros1=False)
    ).findings
    assert ("clock", Severity.error) not in _codes(findings)
    (stale,) = [f for f in findings if f.code == "stale"]
    assert stale.frames == ("map", "odom")
    assert "sent 1,000 times on /tf, always stamped" in stale.message and "on /tf on /tf" not in stale.message
    assert "ros2 run tf2_ros static_transform_publisher" in stale.hint


def test_one_stamp_on_another_time_base_is_still_another_clock() -> None:
    """The stood-still exception is for an old stamp on the others' clock: one in epoch time among frames on
    simulated time is a second clock."""
    wall = periodic("/cam", 100, lambda t: [_t("base_link", "camera", START)])
    findings = check(recording(simulated(amcl=[]) + wall, ros1=False)).findings
    assert ("clock", Severity.error) in _codes(findings)


def test_a_real_second_clock_is_still_two_clocks() -> None:
    """ros2_db3_ur5_topic_tf_two_clocks' shape: an arm on simulated time beside detections on wall time."""
    arm = periodic("/arm", 20, lambda t: [_t("base_link", "arm", t, (t - SIM_START) / NS_PER_S)], stamp=sim)
    detections = periodic("/det", 2, lambda t: [_t("base_link", "tag", t)])
    findings = check(recording(sorted(arm + detections, key=lambda m: m.record_time), ros1=False)).findings
    (clock,) = [f for f in findings if f.code == "clock" and f.severity is Severity.error]
    assert clock.frames == ("base_link", "arm")
    assert "rosbag" not in clock.hint and "ros::Time" not in clock.hint


def test_a_transform_sent_once_is_said_once() -> None:
    once = TfMessage("/tf", START + 3_000_000, [_t("base_link", "sonar", START)], "/tf")
    (stale,) = [f for f in check(recording(with_extra([once]), ros1=False)).findings if f.code == "stale"]
    assert "sonar was sent once on /tf, stamped" in stale.message


def _boat(stamp: int) -> list[Transform]:
    """odom -> base_link of a boat at 0.5 m/s whose odometry fuses a GPS fix each second: after each, a step
    of 0.05 to 0.20 m (the fix's correction)."""
    s = (stamp - START) / NS_PER_S
    corrections = np.cumsum([0.05 + 0.05 * (i % 4) for i in range(int(SECONDS) + 1)])
    return [_t("odom", "base_link", stamp, 0.5 * s + float(corrections[int(s)]))]


def test_odometry_stepping_after_each_gps_fix_is_a_warning_and_lookups_work() -> None:
    """Issue 39's boat: jump on odom -> base_link was raised to an error (wtf and view-frames exit 1) while
    ``--list-checks`` said warning and every lookup worked."""
    rec = recording(healthy(ekf=periodic("/ekf", 50, _boat)), ros1=False)
    findings = check(rec).findings
    assert _codes(findings) == [("jump", Severity.warning)]
    assert "REP 105" in findings[0].hint and "GPS" in findings[0].hint
    times = np.arange(START + NS_PER_S // 10, START + 9 * NS_PER_S, NS_PER_S // 50)
    assert rec.buffer.lookup_many("map", "base_link", times).valid.all()


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_no_check_reports_more_than_its_listed_severity(ros1: bool) -> None:
    """The rule: a check's registered severity (``--list-checks``) is the most it reports, but as a root cause
    (as severe as the worst finding beneath it); a finding may be milder (``sensor_wait``'s short waits,
    ``no_tf``'s static-only recording are notes)."""
    for name, problem in PROBLEMS.items():
        clock = problem.clock() if problem.clock else None
        streams = problem.streams() if problem.streams else ()
        found = findings_of(Scene(recording(problem.make(), problem.topics, ros1=ros1, clock=clock), streams=streams))
        for f in found:
            beneath = [g.severity for g in found if f.key and g.cause == f.key]  # a root cause: as severe as they
            assert f.severity.rank >= min(s.rank for s in [CHECKS[f.code].severity, *beneath]), (name, f)


@pytest.mark.parametrize("tf", ["not recorded", "recorded empty", "recorded"])
def test_sensor_data_in_a_frame_no_transform_names_is_told_what_is_missing(tf: str) -> None:
    """Issue 39: ros1_tb3_waffle_static (no /tf recorded) was told to set the driver's frame_id; what is
    missing there is /tf; where /tf was recorded empty (ros2_db3_tb3_webots_no_tf), its publishers' output;
    where tf moves but nothing names odom, odometry's transform."""
    messages = [statics()]
    if tf == "recorded empty":
        messages.append(TfMessage("/tf", START + NS_PER_S, [], "/tf"))
    elif tf == "recorded":
        messages += wheels()
    rec = recording(sorted(messages, key=lambda m: m.record_time), ros1=False)
    (found,) = [
        f for f in findings_of(Scene(rec, streams=[sensor("/odom", "odom", 10, 5_000_000)])) if f.code == "sensor_frame"
    ]
    said = {
        "not recorded": "this recording holds no /tf (no such topic in it): the moving transforms",
        "recorded empty": "/tf was recorded but holds no transform",
        "recorded": "odometry's odom -> base_link",
    }[tf]
    assert said in found.hint and "frame_id" not in found.hint.split(":")[0]
    if tf == "not recorded":  # cut away or never published: the bag cannot tell, so both, each with its remedy
        assert "were not recorded, or nothing published them" in found.hint
        assert "ros2 bag record /tf /tf_static" in found.hint and "or run their publisher if none ran" in found.hint


def test_a_mount_missing_from_a_bag_without_tf_static_may_never_have_been_published() -> None:
    """A real Pioneer 3-DX (murillo-teixeira/monte-carlo-localization's test1.bag): odometry on /tf, /scan in
    'laser', no /tf_static in the bag, recorded with `rosbag record -a`: nothing published base_link -> laser (its
    authors add it when they replay). A bag without the topic cannot tell that from a recorder not asked for it:
    the hint says both, each with its remedy, not that the mount "was not recorded"."""
    scene = Scene(recording(ekf(), ros1=True), streams=[sensor("/scan", "laser", 10, 5_000_000)])
    (found,) = [f for f in findings_of(scene) if f.code == "sensor_frame"]
    assert found.hint.startswith("this recording holds no /tf_static (no such topic in it): the sensors' mounts")
    assert "were not recorded, or nothing published them" in found.hint
    assert "rosbag record /tf /tf_static" in found.hint and "or run their publisher if none ran" in found.hint


def test_data_in_map_without_tf_static_is_told_localization_not_a_mount() -> None:
    """A real Guardian under a navigation controller (dynamic_robot_localization_tests' guardian_controller_2.bag):
    odometry on /tf, no /tf_static in the bag, two goals in 'map' and no map -> odom. 'map' is no mount: the hint
    names localization's transform, as `tfx filter` does, not the unrecorded /tf_static. A mount frame in the
    same bag keeps the mounts' words."""
    goals = sensor("/pose_goal", "map", 1, 5_000_000)
    scene = Scene(recording(ekf(), ros1=True), streams=[goals, sensor("/scan", "laser", 10, 5_000_000)])
    found = {f.frames: f for f in findings_of(scene) if f.code == "sensor_frame"}
    (map_goal, mount) = found[("map",)], found[("laser",)]
    assert map_goal.severity == Severity.error
    assert "'map' is localization's frame (REP 105)" in map_goal.hint and "map -> odom" in map_goal.hint
    assert "mounts" not in map_goal.hint and "/tf_static" not in map_goal.hint, map_goal.hint
    assert (stream := next(s for s in scene.sensors.streams if s.topic == "/pose_goal")).unplaced
    assert map_goal.hint.startswith(stream.unplaced)  # filter's words and wtf's are one
    assert mount.hint.startswith("this recording holds no /tf_static (no such topic in it): the sensors' mounts")


def test_a_mount_missing_from_a_tf1_recording_was_never_published() -> None:
    """A real tilting laser and Xsens IMU of 2012 (PlotJuggler's tilt_laser.bag): /tf of tf1's tf/tfMessage, its
    mounts on /tf from tf's static_transform_publisher, the IMU's data in base_imu, which nothing names. /tf_static
    did not exist then: recording it helps nothing; the missing mount was never sent. With tf2's TFMessage on /tf,
    the bag cannot tell the two apart (the Pioneer's case): both remedies."""
    rec = recording(ekf(), ros1=True)
    (info,) = rec.contents.files
    scene = Scene(rec, streams=[sensor("/imu_data", "base_imu", 20, 5_000_000)])
    info.topics["/tf"] = "tf/tfMessage"
    (found,) = [f for f in findings_of(scene) if f.code == "sensor_frame"]
    assert found.hint.startswith("this recording's /tf is tf1's (tf/tfMessage), from before /tf_static")
    assert "nothing published the missing ones; run their publisher" in found.hint
    assert "rosbag record" not in found.hint and "not recorded" not in found.hint
    info.topics["/tf"] = "tf2_msgs/TFMessage"
    (found,) = [f for f in findings_of(scene) if f.code == "sensor_frame"]
    assert "rosbag record /tf /tf_static" in found.hint and "or run their publisher if none ran" in found.hint


@pytest.mark.parametrize("tf_static", ["not recorded", "recorded empty"])
def test_sensor_data_in_a_mount_frame_without_tf_static_is_told_what_is_missing(tf_static: str) -> None:
    """A TurtleBot3 under AMCL (PabloMatilla/IR2121@25fabcf rosbag2_2023_10_21-21_16_22): map -> odom ->
    base_footprint on /tf, /tf_static recorded with 0 messages, /scan in base_scan. Missing is /tf_static's
    content, not the driver's frame_id."""
    messages = [*amcl(), *ekf()]
    if tf_static == "recorded empty":
        messages.append(TfMessage("/tf_static", START + NS_PER_S, [], "/tf_static"))
    rec = recording(sorted(messages, key=lambda m: m.record_time), ros1=False)
    (found,) = [
        f
        for f in findings_of(Scene(rec, streams=[sensor("/scan", "base_scan", 10, 5_000_000)]))
        if f.code == "sensor_frame"
    ]
    said = {
        "not recorded": "this recording holds no /tf_static (no such topic in it): the sensors' mounts",
        "recorded empty": "/tf_static was recorded but holds no transform",
    }[tf_static]
    assert found.hint.startswith(said)  # what the recording shows first
    assert "typo" not in found.hint  # 'base_scan' shares base_link's prefix, but is the TurtleBot3's lidar frame


def test_topics_in_one_missing_map_frame_are_one_finding_pointing_at_localization() -> None:
    """ruvu/mcl's MiR bag (the input of a localization under test): /initialpose and /landmark_list in map,
    no map -> odom recorded. One cause, so one finding naming both topics, whose hint is localization's (not
    odometry's odom -> base_link); a frame missing for another reason stays its own finding."""
    rec = recording(sorted([statics(), *ekf(), *wheels()], key=lambda m: m.record_time), ros1=True)
    streams = [
        sensor("/initialpose", "map", 1, 5_000_000),
        sensor("/landmark_list", "map", 2, 5_000_000),
        sensor("/scan", "laser", 10, 5_000_000),
        sensor("/image", "kamera", 5, 5_000_000),
    ]
    found = [f for f in findings_of(Scene(rec, streams=streams)) if f.code == "sensor_frame"]
    assert [f.frames for f in found] == [("map",), ("kamera",)]
    in_map = found[0]
    assert in_map.message.startswith("/initialpose (10 of 10 messages), /landmark_list (20 of 20 messages) are")
    assert in_map.count == 30
    assert "'map' is localization's frame" in in_map.hint and "odom -> base_link" not in in_map.hint
    assert found[1].message.startswith("/image: 50 of 50 messages are in frame 'kamera' (did you mean 'camera'?)")


def test_a_frame_sharing_a_prefix_with_one_of_the_tree_is_no_misspelling() -> None:
    """okoslam's cartographer bags: /scan in a TurtleBot3-style 'base_scan' (the lidar's own frame, no /tf_static
    recorded) was asked "did you mean 'base_link'?", and the hint offered a typo's remedy; 'camra' still is one."""
    rec = recording(sorted([statics(), *ekf(), *wheels()], key=lambda m: m.record_time), ros1=True)
    streams = [sensor("/scan", "base_scan", 10, 5_000_000), sensor("/image", "camra", 5, 5_000_000)]
    found = {f.frames: f for f in findings_of(Scene(rec, streams=streams)) if f.code == "sensor_frame"}
    scan, image = found[("base_scan",)], found[("camra",)]
    assert scan.message == "/scan: 100 of 100 messages are in frame 'base_scan', which no transform names"
    assert "typo" not in scan.hint
    assert "(did you mean 'camera'?)" in image.message and "typo" in image.hint


def _mounts(*children: str) -> TfMessage:
    return TfMessage("/tf_static", START + DELAY, [_t("base_link", c, START, 0.1) for c in children], "/mounts")


def test_data_in_a_frame_whose_mount_the_tree_names_otherwise_is_told_the_two_names() -> None:
    """A real mapping robot of 2018 (alexbk22/robo_lape, 2018-09-20-19-57-08.bag): /scan in 'laser', /imu/data in
    '/imu', its static publishers mounting 'base_laser' and 'base_imu', no /tf recorded. Told to record /tf, where
    its next bag shows the fix: both sides renamed laser_frame and imu_frame. The hint names the tree's frame named
    like the data's, in wtf and filter alike; with no /tf, odometry's own frame keeps its hint."""
    rec = recording([_mounts("base_laser", "base_imu")], ros1=True)
    streams = [sensor("/scan", "laser", 10, 5_000_000), sensor("/imu/data", "/imu", 20, 5_000_000)]
    scene = Scene(rec, streams=streams)
    found = {f.frames: f for f in findings_of(scene) if f.code == "sensor_frame"}
    scan, imu = found[("laser",)], found[("/imu",)]
    assert scan.hint.startswith("the tree has 'base_laser' (base_link -> base_laser) for 'laser', a frame named like")
    assert imu.hint.startswith("the tree has 'base_imu' (base_link -> base_imu) for '/imu'")
    assert "rosbag record" not in scan.hint and "rosbag record" not in imu.hint
    reports = {r.topic: r for r in scene.sensors.streams}
    assert reports["/scan"].namesakes == (("laser", "base_laser", "base_link"),)
    console = Console(width=1000, record=True, file=io.StringIO())
    console.print(filter_text(scene.sensors))
    said = console.export_text()
    assert "no timeout can (the tree has 'base_laser' (base_link -> base_laser) for 'laser'" in said, said
    topics = {t["topic"]: t for t in filter_dict(scene.sensors)["topics"]}
    assert topics["/scan"]["namesakes"] == [{"frame_id": "laser", "tree_frame": "base_laser", "parent": "base_link"}]


@pytest.mark.parametrize(
    ("mounts", "data"),
    [
        (("front_laser", "rear_laser"), ()),  # two frames named like it: no guess
        (("base_laser",), ("base_laser",)),  # the one named like it holds data of its own: another sensor's
        (("laser_link",), ()),  # a control: the one frame named like it, unused
    ],
)
def test_a_namesake_is_said_only_where_one_unused_frame_fits(mounts: tuple[str, ...], data: tuple[str, ...]) -> None:
    rec = recording([_mounts(*mounts)], ros1=True)
    streams = [sensor("/scan", "laser", 10, 5_000_000), *(sensor(f"/{d}_data", d, 10, 5_000_000) for d in data)]
    (found,) = [f for f in findings_of(Scene(rec, streams=streams)) if f.code == "sensor_frame"]
    assert found.hint.startswith("the tree has 'laser_link'") is (mounts == ("laser_link",)), found.hint
    assert ("rosbag record /tf /tf_static" in found.hint) is (mounts != ("laser_link",)), found.hint


def test_data_in_map_beside_a_tree_without_odom_is_told_the_trees_fixed_frame_not_localization() -> None:
    """CyberShip Voyager's motion capture (corpus ros2-cybership-voyager-mocap-basin-2025-mcap): the ship's pose
    on tf as world -> base_link, mocap4r2's /markers in map, no odom anywhere. No localization is missing: 'map'
    is the capture's name for what tf calls 'world'."""
    pose = periodic("/mocap", 10, lambda stamp: [_t("world", "base_link", stamp, _s(stamp))])
    rec = recording(sorted([statics(), *pose], key=lambda m: m.record_time), ros1=False)
    markers = [sensor("/markers", "map", 10, 5_000_000)]
    (found,) = [f for f in findings_of(Scene(rec, streams=markers)) if f.code == "sensor_frame"]
    assert found.frames == ("map",)
    assert "tree's fixed frame is 'world'" in found.hint and "frame_id parameter to 'world'" in found.hint
    assert "amcl" not in found.hint and "localization's (REP 105) here" in found.hint


def test_odometry_in_a_frame_no_transform_names_is_told_its_tf_is_not_published() -> None:
    """frand08/ramon_slam's cartographer bag: /odom_enc (nav_msgs/Odometry) in odom_enc, nothing on tf names it.
    The missing part is the odometry's own transform, not a sensor mount nor a driver's frame_id."""
    rec = recording(sorted([statics(), *ekf(), *wheels()], key=lambda m: m.record_time), ros1=True)
    odometry = dataclasses.replace(sensor("/odom_enc", "odom_enc", 20, 5_000_000), type="nav_msgs/Odometry")
    odometry = _stating(odometry, ("base_footprint",))  # the bag's child: placed by no other
    sonar = sensor("/range", "sonar_mount", 10, 5_000_000)  # a mount that is missing: the mount's hint
    found = {f.frames: f for f in findings_of(Scene(rec, streams=[odometry, sonar])) if f.code == "sensor_frame"}
    hint = found[("odom_enc",)].hint
    assert "'odom_enc' is the frame of odometry" in hint and "enable_odom_tf" in hint
    assert "frame_id parameter" not in hint and "mount" not in hint
    assert "publish the sensor's mount" in found[("sonar_mount",)].hint


def _stating(stream: StampedMessages, children: tuple[str, ...]) -> StampedMessages:
    """``stream`` as odometry whose every message states a transform to ``children``' first (as the codec reads
    nav_msgs/Odometry's child_frame_id), its value not read; ``()``: an empty child_frame_id."""
    n = len(stream)
    return dataclasses.replace(
        stream, child=np.zeros(n, np.int32), pose=np.full((n, 7), np.nan), child_ids=children[:1] or ("",)
    )


def _pr2(child: str = "base_footprint") -> Recording:
    """A PR2 as jsk_pr2eus's pr1012_sensors.bag (2012) has it: amcl's map -> odom_combined, robot_pose_ekf's
    odom_combined -> ``child``, the base's mounts below."""
    mounts = TfMessage("/tf_static", START + DELAY, [_t(child, "base_link", START), _t("base_link", "laser", START)])
    fused = periodic("/robot_pose_ekf", 30, lambda stamp: [_t("odom_combined", child, stamp, 0.1 * _s(stamp))])
    located = periodic("/amcl", 20, lambda stamp: [_t("map", "odom_combined", stamp)])
    return recording(sorted([mounts, *fused, *located], key=lambda m: m.record_time), ros1=True)


@pytest.mark.parametrize("children", [(), ("base_footprint",)])
def test_odometry_another_odometry_places_the_robot_beside_is_a_note_not_an_error(children: tuple[str, ...]) -> None:
    """A real PR2 (jsk_pr2eus's pr1012_sensors.bag): /base_odometry/odom in 'odom', its child_frame_id empty,
    while robot_pose_ekf sends odom_combined -> base_footprint. An error told to turn the odometry's tf on, which
    would give base_footprint a second parent: the odometry is the estimate's input, its frame needed by nothing.
    Its child named and placed from another frame says the same."""
    odometry = dataclasses.replace(sensor("/base_odometry/odom", "odom", 20, 5_000_000), type="nav_msgs/Odometry")
    odometry = _stating(odometry, children)
    (found,) = [f for f in findings_of(Scene(_pr2(), streams=[odometry])) if f.code == "sensor_frame"]
    assert found.severity is Severity.info and found.frames == ("odom",)
    assert re.fullmatch(
        r"/base_odometry/odom: (\d+) of \1 messages are in frame 'odom', which no transform names", found.message
    )
    assert "odom_combined -> base_footprint from /robot_pose_ekf" in found.hint, found.hint
    assert "second parent" in found.hint and "enable_odom_tf" not in found.hint


def test_odometry_whose_child_no_other_odometry_places_is_still_an_error() -> None:
    """The same tree, the odometry's child another frame than the one robot_pose_ekf places (a second robot's
    base, say): nothing fuses it, its own tf is missing, as before."""
    odometry = dataclasses.replace(sensor("/odom", "odom", 20, 5_000_000), type="nav_msgs/Odometry")
    odometry = _stating(odometry, ("robot2/base_link",))
    (found,) = [f for f in findings_of(Scene(_pr2(), streams=[odometry])) if f.code == "sensor_frame"]
    assert found.severity is Severity.error and "enable_odom_tf" in found.hint


def test_a_ground_truth_pose_in_map_is_told_it_is_a_pose_in_the_world_not_an_odometry_tf() -> None:
    """corpus33's Guardian in Gazebo: /base_pose_ground_truth (nav_msgs/Odometry from Gazebo's p3d plugin, 1 kHz)
    in 'map' with an empty child_frame_id, no transform naming map. The hint said "turn on the odometry node's
    tf": a pose in the world has none; a lookup into map needs map -> odom (a localizer's)."""
    rec = recording(sorted([statics(), *ekf(), *wheels()], key=lambda m: m.record_time), ros1=True)
    truth = dataclasses.replace(sensor("/base_pose_ground_truth", "map", 20, 5_000_000), type="nav_msgs/Odometry")
    (found,) = [f for f in findings_of(Scene(rec, streams=[truth])) if f.code == "sensor_frame"]
    assert "'map' is a world frame (REP 105)" in found.hint and "ground truth (Gazebo's p3d plugin" in found.hint
    assert "needs map -> odom" in found.hint and "enable_odom_tf" not in found.hint


def test_every_sample_seconds_late_is_told_the_publisher_s_clock_is_behind() -> None:
    """A hobby robot of 2016 (qjones81/johnny5's data.bag): three publishers' edges all recorded 5.6-6.2 s after
    their stamps, none sooner: the robot's clock ~5.7 s behind the recorder's, as ``future`` says of one ahead. A
    node half a second late on every sample is not told of clocks."""
    behind = recording(healthy(ekf=ekf(delay=5 * NS_PER_S + 700 * MS)))
    (late,) = [f for f in findings_of(Scene(behind)) if f.code == "delay"]
    assert "none arrived sooner than 5.7 s" in late.hint and "clock runs behind the recorder's" in late.hint
    (slow,) = [f for f in findings_of(Scene(recording(healthy(ekf=ekf(delay=500 * MS))))) if f.code == "delay"]
    assert "clock" not in slow.hint and "a busy publisher, a slow link" in slow.hint


def test_data_in_a_frame_no_transform_names_is_told_both_remedies_in_a_tf1_recording() -> None:
    """A real robot of 2013 (Ansrala/Delta_Project_3's teleop.bag): tf1's /tf, its laser mounted as 'laser' by a
    static_transform_publisher, its scans in base_laser. The missing mount's publisher is one remedy, the driver's
    frame_id the other (here the right one), as `tfx filter` says both. Where /tf_static was not recorded (tf2's
    /tf) the hint is that, as before."""
    rec = recording(ekf(), ros1=True)
    (info,) = rec.contents.files
    info.topics["/tf"] = "tf2_msgs/TFMessage"
    (unrecorded,) = [
        f
        for f in findings_of(Scene(rec, streams=[sensor("/scan", "base_laser", 10, 5_000_000)]))
        if f.code == "sensor_frame"
    ]
    assert "frame_id" not in unrecorded.hint and "were not recorded, or nothing published them" in unrecorded.hint
    info.topics["/tf"] = "tf/tfMessage"
    (found,) = [
        f
        for f in findings_of(Scene(rec, streams=[sensor("/scan", "base_laser", 10, 5_000_000)]))
        if f.code == "sensor_frame"
    ]
    assert "run their publisher" in found.hint and "or set the driver's frame_id parameter" in found.hint
    assert "did you mean" not in found.message


@pytest.mark.parametrize("tf_type", ["tf/tfMessage", "tf2_msgs/TFMessage"], ids=["tf1", "tf2"])
def test_odometry_in_a_frame_no_transform_names_is_told_so_where_no_tf_static_was_recorded(tf_type: str) -> None:
    """A real Clearpath Husky of 2013 (ros-planning/navigation's robot_pose_ekf gps_data.bag): tf1's /tf, no
    /tf_static topic, /encoder (nav_msgs/Odometry) in odom_combined, robot_pose_ekf's frame, and /fix in gps. The
    odometry's own transform is what is missing, whatever became of /tf_static; the GPS's mount is what the
    statics' words are for."""
    rec = recording(ekf(), ros1=True)
    (info,) = rec.contents.files
    info.topics["/tf"] = tf_type
    odometry = dataclasses.replace(sensor("/encoder", "odom_combined", 10, 5_000_000), type="nav_msgs/Odometry")
    odometry = _stating(odometry, ("base_footprint",))  # the bag's, which nothing places
    fix = dataclasses.replace(sensor("/fix", "gps", 2, 5_000_000), type="sensor_msgs/NavSatFix")
    found = {f.frames: f for f in findings_of(Scene(rec, streams=[odometry, fix])) if f.code == "sensor_frame"}
    hint = found[("odom_combined",)].hint
    assert "'odom_combined' is the frame of odometry" in hint and "enable_odom_tf" in hint
    assert "mount" not in hint and "/tf_static" not in hint
    mount = found[("gps",)].hint
    assert "mounts" in mount and "'odom_combined'" not in mount


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_a_mount_under_one_parent_on_tf_static_and_another_on_tf_is_two_descriptions(ros1: bool) -> None:
    """frand08/ramon_slam's cartographer bag: each laser under laser_link on /tf_static and under base_link from a
    static_transform_publisher on /tf (10 Hz). Two descriptions of one mount, not an object picked up; what tf2
    keeps is said in the words of the recording's ROS."""
    mount = TfMessage("/tf_static", START + DELAY, [_t("base_link", "laser_mount", START, 0.0)], "/rsp")
    laser = TfMessage("/tf_static", START + DELAY, [_t("laser_mount", "laser_front", START, 0.3)], "/rsp")
    again = periodic("/laser_tf", 10, lambda t: [_t("base_link", "laser_front", t, 0.3)])
    rec = recording(sorted([mount, laser, *again, *ekf()], key=lambda m: m.record_time), ros1=ros1)
    (parents,) = [f for f in findings_of(Scene(rec)) if f.code == "multiple_parents"]
    assert parents.hint.startswith("laser_front is under laser_mount on /tf_static and under base_link on /tf")
    assert "picked up" not in parents.hint
    kept = "ROS 1's tf2 keeps it a static frame" if ros1 else "ROS 2's tf2 replaces the frame's cache"
    assert kept in parents.hint


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_odometry_ending_at_a_link_the_description_puts_elsewhere_is_not_a_mount(ros1: bool) -> None:
    """A real Neato (ros1_neato_urdf_beside_driver_2018): the URDF's base_footprint -> base_link on /tf_static, the
    driver's moving odom -> base_link on /tf. Not two descriptions of one mount ("keep one" would drop the
    odometry or the description): the moving transform should end at the description's root, base_footprint."""
    urdf = TfMessage("/tf_static", START + DELAY, [_t("base_footprint", "base_link", START, 0.0)], "/rsp")
    rec = recording(sorted([urdf, *ekf()], key=lambda m: m.record_time), ros1=ros1)
    (parents,) = [f for f in findings_of(Scene(rec)) if f.code == "multiple_parents"]
    assert parents.hint.startswith("base_link is under base_footprint on /tf_static (a fixed joint of the robot")
    assert "moves under odom on /tf" in parents.hint and "(odom -> base_footprint:" in parents.hint
    assert "one mount" not in parents.hint and "picked up" not in parents.hint
    kept = "ROS 1's tf2 keeps it a static frame" if ros1 else "ROS 2's tf2 replaces the frame's cache"
    assert kept in parents.hint


def test_a_frame_on_tf_static_and_constant_on_tf_under_one_publisher_name_is_only_mixed_static() -> None:
    """frand08/ramon_slam's cartographer bag, re-recorded through rosbag play (one callerid for all): base_footprint ->
    base_link on /tf_static and, constant, on /tf at 10 Hz. mixed_static says it; static_on_dynamic's advice (put it
    on /tf_static) is already done, so it is not said, as where two publishers are named."""
    mount = TfMessage("/tf_static", START + DELAY, [_t("base_footprint", "base_link", START)], "/play")
    again = periodic("/play", 10, lambda t: [_t("base_footprint", "base_link", t)])
    odometry = periodic(
        "/play", 50, lambda t: [_t("odom", "base_footprint", t, 0.4 * (t - START) / NS_PER_S)], phase=0.007
    )  # in messages of its own: not a joint at rest among moving ones
    rec = recording(sorted([mount, *again, *odometry], key=lambda m: m.record_time), ros1=True)
    codes = [f.code for f in findings_of(Scene(rec))]
    assert "mixed_static" in codes and "static_on_dynamic" not in codes


def _ignition(delays_ms: tuple[float, float]) -> Recording:
    """A simulation whose /clock ticks every 3 ms (333 Hz), odometry arriving ``delays_ms`` (from, to) after
    its stamps, cycling; recorded on wall time."""
    low, high = delays_ms

    def late(t: int) -> int:
        phase = ((t - START) // (20 * 1_000_000)) % 12 / 11  # 0 .. 1 over 12 messages
        return sim(t) - round((low + (high - low) * phase) * 1_000_000)

    return recording(simulated(ekf=ekf(stamp=late)), clock=sim_clock(hz=333), ros1=False)


def test_delays_of_several_ticks_of_a_coarse_clock_are_measured_to_a_tick() -> None:
    """Issue 39: an Ignition run with /clock at 333 Hz showed no delay ('delays shorter than 3 ms cannot be
    measured') although its delays of -12 to +21 ms are measurable to a tick; tf well within a tick of
    /clock (rosbag play's 100 Hz, ros2_db3_webots_epuck's 50 Hz) still is not."""
    measurable = _ignition((-12, 21))
    assert 2_900_000 <= measurable.timeline.resolution <= 3_100_000
    assert measurable.timeline.delays_measured and measurable.timeline.delays_unavailable == ""
    report = monitor(measurable, MonitorQuery())
    odom = next(e for e in report.edges if e.key == ("odom", "base_link"))
    assert 0.018 * NS_PER_S <= odom.delay_max <= 0.024 * NS_PER_S  # the largest, +21 ms, to a tick of 3 ms
    within_a_tick = _ignition((0.5, 1.5))
    assert not within_a_tick.timeline.delays_measured
    assert "cannot be measured" in within_a_tick.timeline.delays_unavailable


def test_trees_apart_for_want_of_tf_static_in_a_file_are_told_how_to_read_it_with_them(tmp_path: Path) -> None:
    """e-Yantra's Krishi Bot (a scout's, 2026-12-02): 4 trees, /tf_static not recorded; told to record it, which a
    recording made cannot, and not that tfx static adds a mount to a copy of it (the scout joined them so)."""
    arm = periodic("/rsp", 20, lambda stamp: [_t("arm_base", "arm_link", stamp, _s(stamp))])
    bag = write(tmp_path, "apart", BagFormat.ros1, sorted([*ekf(), *arm], key=lambda m: m.record_time))
    (apart,) = [f for f in check(read_recording([bag])).findings if f.code == "disconnected"]
    assert "rosbag record /tf /tf_static" in apart.hint, apart.hint
    assert f"tfx static X Y Z YAW PITCH ROLL PARENT CHILD -b {bag} -o COPY adds one to a copy" in apart.hint


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_empty_tf_messages_are_counted_where_they_are_read(tmp_path: Path, fmt: BagFormat) -> None:
    """Issue 39: a fifth of /tf empty went unmentioned where no metadata.yaml counts the topic (a ROS 1 bag, a
    bare .db3 or .mcap): the reader counts them, and a note says how many (a warning past half)."""
    messages = healthy()
    empty = [TfMessage("/tf", m.record_time + 1, [], m.publisher) for m in messages if m.topic == "/tf"][::4]
    bag = write(tmp_path, "bag", fmt, sorted(messages + empty, key=lambda m: m.record_time))
    given = bag if fmt is BagFormat.ros1 else next(p for p in bag.iterdir() if p.suffix in (".db3", ".mcap"))
    for path in {bag, given}:
        (found,) = [f for f in check(read_recording([path])).findings if f.code == "silent_tf"]
        tf = sum(m.topic == "/tf" for m in messages) + len(empty)
        assert found.severity is Severity.info and f"{len(empty):,} of {tf:,} messages on /tf carry no transform" in (
            found.message
        )


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_empty_tf_messages_are_said_whose_where_the_bag_names_their_sender(tmp_path: Path, fmt: BagFormat) -> None:
    """A real PR2 (jsk_pr2eus's pr1012_sensors.bag): 13 empty /tf messages, all /dynamic_tf_publisher's, which the
    ROS 1 bag names: the hint said 'rostopic info /tf names them'. A ROS 2 bag names no sender: that hint stays."""
    messages = healthy()
    empty = [TfMessage("/tf", START + k * NS_PER_S + 7, [], "/dynamic_tf_publisher") for k in range(3)]
    empty.append(TfMessage("/tf", START + 5 * NS_PER_S + 7, [], "/amcl"))
    bag = write(tmp_path, "bag", fmt, sorted(messages + empty, key=lambda m: m.record_time))
    (found,) = [f for f in check(read_recording([bag])).findings if f.code == "silent_tf"]
    if fmt is BagFormat.ros1:
        assert found.hint.startswith("/dynamic_tf_publisher sent 3, /amcl sent 1:"), found.hint
    else:
        assert "names them" in found.hint and "/dynamic_tf_publisher" not in found.hint, found.hint


def _clock_recorded_from(seconds: float) -> ClockSamples:
    """The simulator's /clock, its first ``seconds`` not recorded (the recorder subscribed to it late)."""
    clock = sim_clock()
    late = clock.record_time >= START + round(seconds * NS_PER_S)
    return ClockSamples(clock.topic, clock.record_time[late], clock.clock[late])


def test_tf_on_simulated_time_before_the_first_recorded_clock_is_no_finding() -> None:
    """A TurtleBot3 in Gazebo (PabloMatilla/IR2121 rosbag2_2023_10_21-19_09_03): tf from the first second,
    stamped 319.7 s on; /clock first recorded 2.3 s later at 320.9 s. The stamps say the nodes had simulated
    time: the recorder only got /clock late, and nothing is wrong."""
    findings = check(recording(simulated(), clock=_clock_recorded_from(2.5), ros1=False)).findings
    assert "sim_clock" not in [f.code for f in findings]


def test_tf_stamped_zero_before_the_first_clock_is_a_note() -> None:
    """Stamped ROS time 0 before /clock began: the nodes with use_sim_time had no time yet."""
    zero_until = START + round(2.5 * NS_PER_S)
    early = ekf(stamp=lambda t: sim(t) if t >= zero_until else 0)
    findings = check(recording(simulated(ekf=early), clock=_clock_recorded_from(2.5), ros1=False)).findings
    (note,) = [f for f in findings if f.code == "sim_clock"]
    assert note.severity is Severity.info
    assert "before the first /clock" in note.message and "stamped no later than 0.000 s" in note.message


def _no_record_clock() -> list[TfMessage]:
    """An arm on simulated time (3 joints at 100 Hz) and two box detections on wall time, 14 s apart in their
    stamps, written with record times of whole seconds read as nanoseconds (0 to 10 ns)."""
    joints = (("base_link_inertia", "shoulder"), ("shoulder", "forearm"), ("forearm", "wrist"))
    arm = periodic("/arm", 100, lambda t: [_t(p, c, t, (t - START) / NS_PER_S) for p, c in joints], stamp=sim)
    early = periodic("/det", 15, lambda t: [_t("base_link", "box_1", t)], end=4.0)
    late = periodic("/det", 15, lambda t: [_t("base_link", "box_6", t)], start=6.0)  # 14 s later: no second clock
    return [
        TfMessage(m.topic, (m.record_time - START) // NS_PER_S, m.transforms, m.publisher)  # seconds, as ns
        for m in sorted(arm + early + late, key=lambda m: m.record_time)
    ]


def test_detections_on_one_clock_without_a_record_clock_are_aged_from_its_one_end() -> None:
    """Two detections on wall time, seen 9.5 s apart, beside an arm on simulated time, with record times that time
    nothing: view-frames grouped their clocks by record time minus stamp (the stamps themselves), so each was
    aged from its own newest stamp, both '0.000 s old' (the Logistic coBot's obj_12 and obj_6). One clock, one
    end: the newest stamp on it."""
    joints = (("base_link_inertia", "shoulder"), ("shoulder", "forearm"))
    arm = periodic("/arm", 100, lambda t: [_t(p, c, t, (t - START) / NS_PER_S) for p, c in joints], stamp=sim)
    early = periodic("/det", 15, lambda t: [_t("base_link", "box_1", t)], start=1.0, end=3.0)  # recorded at 1 ns
    late = periodic("/det", 15, lambda t: [_t("base_link", "box_6", t)], start=12.5, end=14.0)  # medians 11 s apart
    messages = [
        TfMessage(m.topic, (m.record_time - START) // NS_PER_S, m.transforms, m.publisher)  # seconds, as ns
        for m in sorted(arm + early + late, key=lambda m: m.record_time)
    ]
    graph = view_frames(recording(messages, ros1=False))
    ages = {e.child: graph.age_of(e) for e in graph.edges if e.child.startswith("box")}
    newest = {e.child: e.stats.last_stamp for e in graph.edges if e.stats is not None and e.child.startswith("box")}
    assert ages == {"box_1": newest["box_6"] - newest["box_1"], "box_6": 0}, ages


def test_record_times_that_are_no_clock_time_nothing() -> None:
    """e-Yantra 2024-25 Logistic coBot (ros2_db3_logistic_cobot_pymoveit2_zero_record_times_2024): a
    pymoveit2 script's rosbag2_py writer gave 8,351 messages record times of 0 to 74 ns, while the arm and
    the eBot are stamped on simulated time (46-74 s) and box detections on wall time. The sim-time frames
    'agreed' with that record clock (both before the epoch floor) and were 8 `future` errors, 'stamped up to
    73.9 s after they arrived'; the detections' two episodes were two clocks. Record times within 1 ms of
    one another while the stamps span seconds time nothing: a note saying so, no future, delay or stale,
    and the detections on wall time one other clock."""
    findings = check(recording(_no_record_clock(), ros1=False)).findings
    codes = _codes(findings)
    assert not {"future", "delay", "stale"} & {code for code, _ in codes}
    (note,) = [f for f in findings if f.code == "clock" and f.severity is Severity.info]
    assert "the record times are no clock" in note.message and "rosbag2_py" in note.hint
    (two,) = [f for f in findings if f.code == "clock" and f.severity is Severity.error]
    assert set(two.frames) == {"base_link", "box_1", "box_6"}
    # two time bases seen in the stamps, and no record clock to say which clock a publisher keeps: not told to set
    # use_sim_time as a node that forgot it, nor said to be "in one tree" with frames of a tree apart
    assert "(epoch time) while" in two.message and "(counting from zero): two time bases" in two.message, two.message
    assert "no record clock to tell which clock each keeps" in two.message and "one tree" not in two.message
    assert "set use_sim_time true for it too" not in two.hint, two.hint
    assert "the bytes do not tell which clock each publisher keeps" in two.hint, two.hint
    assert "record with ros2 bag record, which stores when each message arrived, and /clock" in two.hint, two.hint
    # nor given how long after their stamps they arrived: its JSON said arrival_minus_stamp_s -1731467407.96
    assert "arrival_minus_stamp_s" not in two.figures, two.figures


def test_wtfs_header_gives_the_stamps_span_where_the_record_times_are_no_clock(tmp_path: Path) -> None:
    """The Logistic coBot's header said "0.0 s recorded" (its record times span 28 ns): where they are no clock,
    the header gives tf's stamps' span and says so, the JSON its ``stamped`` (null where the record times are one,
    whose header is the record span as before), and a --resume reads it back."""
    import io

    from rich.console import Console

    from tftools.analysis.wtf import Thresholds
    from tftools.render import wtf as render
    from tftools.render.wtf_lines import read_report, write_recording

    read = recording(_no_record_clock(), ros1=False)
    void = check(read)
    first, last = read.timeline.tf_start, read.timeline.tf_end  # the arm's, as monitor's "tf stamped over"
    assert void.stamped == (first, last) and last - first > 8 * NS_PER_S > read.end - read.start, void.stamped
    healthy_report = check(recording(healthy(), ros1=False))
    assert healthy_report.stamped is None
    out = io.StringIO()
    render.write_text([void, healthy_report], Console(file=out, width=400, no_color=True))
    headers = [line for line in out.getvalue().splitlines() if "transforms," in line]
    assert f"tf stamped over {(last - first) / NS_PER_S:.1f} s (the record times are no clock)," in headers[0], headers
    assert "s recorded" not in headers[0]
    recorded = (healthy_report.end - healthy_report.start) / NS_PER_S
    assert f", {recorded:.1f} s recorded," in headers[1] and "stamped" not in headers[1], headers
    (bag,) = render.as_dict([void], False, Thresholds(), 0)["bags"]
    assert bag["stamped"] == {"start": first / NS_PER_S, "end": last / NS_PER_S}
    assert render.as_dict([healthy_report], False, Thresholds(), 0)["bags"][0]["stamped"] is None
    lines = io.StringIO()
    write_recording(void, lines, strict=False)
    (resumed,) = read_report(io.BytesIO(lines.getvalue().encode()), "run.jsonl").reports
    assert resumed.stamped == void.stamped


def test_view_frames_and_report_give_the_stamps_span_where_the_record_times_are_no_clock() -> None:
    """The Logistic coBot's view-frames legend said "Recorded at time: 0.000 to 0.000 (0.000 s)" and its report's
    "Recorded" the same: where the record times are no clock, both give the span wtf's header gives (its
    ``stamped``), in monitor's words, said to be tf's stamps' (report's "tf stamps" row, the same span, goes);
    where the record times are a clock, the record span and tf's stamps' as before."""
    from tftools.analysis.report import recording_facts
    from tftools.render.graph import recording_legend

    read = recording(_no_record_clock(), ros1=False)
    stamped = check(read).stamped
    assert stamped is not None
    first, last = stamped
    seconds = f"{(last - first) / NS_PER_S:.3f} s from {first / NS_PER_S:.3f} to {last / NS_PER_S:.3f}"
    over = f"tf stamped over {seconds} (the record times are no clock)"
    assert recording_legend(read)[0] == over, recording_legend(read)
    facts = dict(recording_facts(read))
    assert facts["Recorded"] == over and "tf stamps" not in facts, facts
    clocked = recording(healthy(), ros1=False)
    span = (clocked.end - clocked.start) / NS_PER_S
    assert recording_legend(clocked)[0] == (
        f"Recorded at time: {clocked.start / NS_PER_S:.3f} to {clocked.end / NS_PER_S:.3f} ({span:.3f} s)"
    )
    facts = dict(recording_facts(clocked))
    assert facts["Recorded"].endswith(f"({span:.3f} s, record clock)") and "tf stamps" in facts, facts


def test_a_silence_timed_by_no_clock_is_unknown_wherever_it_is_shown(tmp_path: Path) -> None:
    """monitor -f json on that recording said "silent_s": 0.0 for every edge, though its record times time nothing
    (RWR's last stamp is 4.75 s before FWL's): unknown, null in JSON, "unknown" in a /diagnostics status, and no
    "silent for the last" line, as ``figures.silence`` defines it for all of them."""
    from tftools.analysis.wtf.health import edge_name, statuses
    from tftools.core.figures import silence_in_words
    from tftools.render.monitor import as_dict

    bag = write(tmp_path, "no_record_clock", BagFormat.rosbag2_sqlite3, _no_record_clock())
    recording = read_recording([str(bag)])
    report = monitor(recording, MonitorQuery())
    moving = [e for e in report.edges if not e.static]
    assert moving and all(e.silent_for is None for e in moving)
    assert all(not silence_in_words(e.silent_for, e.rate_hz) for e in moving)
    assert {e["silent_s"] for e in as_dict(report)["edges"]} == {None}
    said = {s.name: dict(s.values) for s in statuses(check(recording), moving, recording.timeline.record_end)}
    assert {said[edge_name(*e.key)]["silent for the last (s)"] for e in moving} == {"unknown"}


def test_a_replay_paced_by_no_clock_is_refused_in_one_line(tmp_path: Path) -> None:
    """monitor --play on that recording played every message within 28 ns: '7974 messages at
    284750000000.00 Hz'. It says why it cannot replay, and how to read the recording instead."""
    from tftools.sources.stream import stream_recording

    bag = write(tmp_path, "no_record_clock", BagFormat.rosbag2_sqlite3, _no_record_clock())
    assert "the record times are no clock" in stream_recording([str(bag)]).unplayable
    healthy_bag = write(tmp_path, "healthy", BagFormat.rosbag2_sqlite3, healthy())
    assert stream_recording([str(healthy_bag)]).unplayable == ""


def test_a_topics_rate_timed_by_stamps_on_two_time_bases_counts_each_on_its_own(tmp_path: Path) -> None:
    """The logistic coBot's /tf (monitor on ros2_db3_logistic_cobot_pymoveit2_zero_record_times_2024): no clock
    gives the arrivals, so messages are timed by their stamps, the arm's on simulated time and the detections'
    on wall time; one span over both is 55 years: '7974 messages, 0.00 Hz'. Each time base counted over its own
    stamps: the arm's 100 Hz and the detections' 120 messages over 9.93 s, summed."""
    bag = write(tmp_path, "no_record_clock", BagFormat.rosbag2_sqlite3, _no_record_clock())
    (tf,) = monitor(read_recording([str(bag)]), MonitorQuery()).authorities
    assert tf.authority == "/tf" and tf.messages == 1000 + 120
    assert tf.rate_hz == pytest.approx(999 / 9.99 + 119 / (9.0 + 14 / 15), rel=1e-6)


@pytest.mark.parametrize(
    ("problem", "said"),
    [
        (
            "clock",
            r"on a clock counting from zero \(a simulation's time or time since boot: no /clock was recorded to "
            r"tell which\), while the recording's clock \(which ",
        ),
        ("clock_replay", r"stamped 3\.0 days behind the recording's clock \(which "),
    ],
)
def test_the_frames_on_the_reference_clock_are_said_to_follow_it(problem: str, said: str) -> None:
    """The raspimouse replay read 'stamped 7.0 days behind the recording's clock and odom: another clock', the
    UR5 'while the recording's clock and cam_49, obj_49 ... read': as if those frames were more clocks."""
    (found,) = [f for f in check(recording(PROBLEMS[problem].make())).findings if f.code == "clock"]
    assert re.search(said + r"[\w, ]+ follows?\)", found.message), found.message
    assert "clock and " not in found.message


@pytest.mark.parametrize("apart", [False, True], ids=["one-tree", "trees-apart"])
def test_the_clock_hint_says_what_lookups_do_where_the_other_clock_is_a_tree_apart(apart: bool) -> None:
    """ros2_db3_ias0220_gazebo_diff_cont_2025's shape: a robot on simulated time beside a device on wall time in a
    tree of its own. No lookup combines the two trees, so "lookups combining these with other frames fail" would
    be untrue there: the hint says lookups within each tree work. Joined to the robot's tree, they do fail."""
    arm = periodic("/arm", 20, lambda t: [_t("base_link", "arm", t, (t - SIM_START) / NS_PER_S)], stamp=sim)
    root = "imu_link" if apart else "base_link"
    device = periodic("/imu", 10, lambda t: [_t(root, "sonar", t, yaw=(t - START) / NS_PER_S)])
    findings = check(recording(sorted(arm + device, key=lambda m: m.record_time), ros1=False)).findings
    (clock,) = [f for f in findings if f.code == "clock" and f.severity is Severity.error]
    assert clock.frames == ("base_link", "arm")  # the record clock is the device's: the arm is on another
    assert ("lookups within each tree work" in clock.hint) is apart, clock.hint
    assert ("lookups combining these with other frames fail" in clock.hint) is not apart, clock.hint


@pytest.mark.parametrize("first_on_tf_static", [True, False], ids=["kept-static", "dynamic"])
def test_a_stamp_back_on_tf_of_a_frame_ros1_keeps_static_is_no_time_backwards(first_on_tf_static: bool) -> None:
    """frand08/ramon_slam's cartographer bag: front_laser_link on /tf_static, then at 10 Hz on /tf with one stamp
    0.1 s back. ROS 1's tf2 keeps the frame static (each /tf sample replaces its value for every time, no
    TF_OLD_DATA: checked with Debian's tf2_py), so the order of its stamps matters to no lookup: no finding. The
    same /tf samples of a dynamic frame (never on /tf_static) go into its time cache: the warning stands."""
    mount = TfMessage("/tf_static", START + DELAY, [_t("base_link", "laser", START, 0.3)], "/rsp")
    again = periodic("/laser_tf", 10, lambda t: [_t("base_link", "laser", t, 0.3)])
    back = again[20]
    earlier = back.transforms[0].stamp - 2 * NS_PER_S // 10
    again[20] = TfMessage(back.topic, back.record_time, [_t("base_link", "laser", earlier, 0.3)], back.publisher)
    messages = [mount, *again] if first_on_tf_static else again
    rec = recording(sorted([*messages, *ekf()], key=lambda m: m.record_time), ros1=True)
    backwards = [f for f in findings_of(Scene(rec)) if f.code == "time_backwards"]
    assert [f.frames for f in backwards] == ([] if first_on_tf_static else [("base_link", "laser")]), backwards


@pytest.mark.parametrize("apart", [False, True], ids=["joined", "device-apart"])
def test_a_device_on_the_wall_clock_beside_a_simulation_is_not_told_to_use_sim_time(apart: bool) -> None:
    """ros2_db3_ias0220_gazebo_diff_cont_2025's shape with its /clock: a robot on simulated time beside a device
    whose stamps keep time with the record clock, in a tree of its own. That is a device stamping wall-clock time
    on purpose: the finding says what was observed (its stamps arrive 2 ms after them by the record clock, a tree
    of its own) and the hint what a user can do (one clock for both, or two trees), not "set use_sim_time true for
    it too". Joined to the robot's tree (no IAS0220 recording joins it; the UR5's wall-clock detections hang from
    its simulated arm), the bytes do not tell a node that forgot use_sim_time from a real device's driver: the
    finding says which frames are on the wall clock, in which tree, and the hint gives what to do for either (the
    node on use_sim_time; the device restamped on the simulation's time through a bridge, or a tree of its own)."""
    arm = periodic("/arm", 20, lambda t: [_t("base_link", "arm", t, (t - SIM_START) / NS_PER_S)], stamp=sim)
    root = "imu_link" if apart else "base_link"
    device = periodic("/imu", 10, lambda t: [_t(root, "sonar", t, yaw=(t - START) / NS_PER_S)])
    messages = sorted(arm + device, key=lambda m: m.record_time)
    findings = check(recording(messages, ros1=False, clock=sim_clock())).findings
    (clock,) = [f for f in findings if f.code == "clock" and f.severity is Severity.error]
    assert clock.frames == (root, "sonar")  # /clock is the arm's: the device is on another clock
    assert ("set use_sim_time true for it too" in clock.hint) is not apart, clock.hint
    assert ("a tree of their own: a device on the wall clock" in clock.message) is apart, clock.message
    assert "arriving 2.0 ms after their stamps by the record clock" in clock.message, clock.message
    if not apart:
        said = "in one tree with them (under base_link): a publisher on the wall clock (a node without use_sim_time"
        assert said in clock.message, clock.message
        assert "a bridge node restamping them" in clock.hint and "a tree of their own" in clock.hint, clock.hint
        assert "fail with extrapolation errors" in clock.hint, clock.hint
    if apart:
        assert "arriving 2.0 ms after their stamps by the record clock" in clock.message, clock.message
        assert "lookups within each tree work" in clock.hint and "put both on one clock" in clock.hint, clock.hint


@pytest.mark.parametrize("clock_recorded", [False, True], ids=["no-clock", "clock-recorded"])
def test_a_simulation_beside_a_device_without_its_clock_is_not_said_to_count_from_boot(clock_recorded: bool) -> None:
    """ros2_db3_ias0220_gazebo_bumbaluk_2025's shape: a simulated robot stamped from the simulation's start
    (1418-1500 s) beside a device on the wall clock, no /clock recorded: the device's clock is the reference and the
    robot's frames were said to be on "a clock counting from boot", with the hint to stamp with the node's clock or
    that it "runs with use_sim_time while nothing publishes /clock" (then it would stamp 0). The bytes do not tell a
    simulation from a clock since boot (a real Neato's driver stamps time since boot too): said so, with what to do
    for each. Where a /clock was recorded that those frames do not follow, it is not the simulation's."""
    arm = periodic("/arm", 20, lambda t: [_t("base_link", "arm", t, (t - SIM_START) / NS_PER_S)], stamp=sim)
    device = periodic("/imu", 10, lambda t: [_t("imu_link", "sonar", t, yaw=(t - START) / NS_PER_S)])
    messages = sorted(arm + device, key=lambda m: m.record_time)
    other = ClockSamples("/clock", np.array([START + MS]), np.array([5000 * NS_PER_S]))
    findings = check(recording(messages, ros1=False, clock=other if clock_recorded else None)).findings
    (clock,) = [f for f in findings if f.code == "clock" and f.severity is Severity.error]
    assert clock.frames == ("base_link", "arm"), clock
    unrecorded = "a simulation's time or time since boot: no /clock was recorded to tell which"
    assert (unrecorded in clock.message) is not clock_recorded, clock.message
    assert "runs with use_sim_time while nothing publishes /clock" not in clock.hint or clock_recorded, clock.hint
    if not clock_recorded:
        assert "record /clock with them (ros2 bag record /clock ...)" in clock.hint, clock.hint
        assert "lookups within each tree work" in clock.hint, clock.hint


def test_monitor_of_a_chain_on_its_own_clock_counts_on_it_and_says_why_it_has_no_delay() -> None:
    """ros2_db3_ias0220_gazebo_bumbaluk_2025's shape: a simulated arm stamped from 100 s, no /clock recorded, beside
    a device on the wall clock (the record clock's). ``monitor base_link arm`` said the device's wall-clock span in
    its header and "-" for the arm's delays, with no word why: its span is the arm's own stamps', and its delays
    are not measurable (stamped on another clock than the record clock that timed their arrival), said once for
    the report and per edge. The device's chain keeps the tf span and its measured delays."""
    from tftools.render.monitor import as_dict, own_clock_stamps
    from tftools.sources.timeline import OTHER_CLOCK

    arm = periodic("/arm", 20, lambda t: [_t("base_link", "arm", t, (t - START) / NS_PER_S)], stamp=sim)
    device = periodic("/imu", 10, lambda t: [_t("imu_link", "sonar", t, yaw=(t - START) / NS_PER_S)])
    made = recording(sorted(arm + device, key=lambda m: m.record_time), ros1=False)
    stamps = made.buffer.history("arm")
    assert stamps is not None
    asked = MonitorQuery(target="base_link", source="arm")
    assert chain_span(made, asked) == (int(stamps.stamps.min()), int(stamps.stamps.max()))
    report = monitor(made, asked)
    assert report.other_clock == ("arm",) and report.chain is not None and np.isnan(report.chain.delay_mean)
    assert report.other_clock_why.startswith("those of arm cannot be measured: stamped on another clock than the "
                                             "record clock"), report.other_clock_why  # fmt: skip
    newest = f"{int(stamps.stamps.max()) / NS_PER_S:.3f}"
    assert own_clock_stamps(report) == f"base_link to arm stamped up to {newest}, on a clock of its own"
    said = as_dict(report)
    assert said["chain"]["edges"][0]["delay_unmeasurable"] == OTHER_CLOCK
    assert said["delays_other_clock"] == report.other_clock_why and said["delays_unavailable"] is None
    windowed = MonitorQuery(target="base_link", source="arm", start=parse_time_spec("+2", "start"))
    assert chain_span(made, windowed) == (int(stamps.stamps.min()) + 2 * NS_PER_S, int(stamps.stamps.max()))
    sensed = MonitorQuery(target="imu_link", source="sonar")
    measured = monitor(made, sensed)
    assert chain_span(made, sensed) is None and measured.other_clock == () and measured.other_clock_why == ""
    assert own_clock_stamps(measured) == ""
    assert measured.chain is not None and measured.chain.edges[0].delay_mean == DELAY
    assert monitor(made, MonitorQuery()).other_clock == ("arm",)  # every edge: the arm's said, not the device's


def test_the_descriptions_joints_on_the_wall_clock_are_robot_state_publisher_not_a_device() -> None:
    """ros2_db3_eyrc_hologlyph_hb_bot_gazebo_two_trees_two_clocks_2023: robot_state_publisher without use_sim_time
    sends the wheels on the wall clock beside Gazebo's odom on /clock, a tree apart; wtf called them 'a device on
    the wall clock beside the simulation' and told to put 'the device's driver on use_sim_time'. The recorded
    /robot_description names those joints: robot_state_publisher is the node to set use_sim_time for."""
    urdf = '<robot name="bot"><link name="imu_link"/><link name="sonar"/><joint name="j" type="continuous">'
    urdf += '<parent link="imu_link"/><child link="sonar"/><axis xyz="0 0 1"/></joint></robot>'
    arm = periodic("/arm", 20, lambda t: [_t("base_link", "arm", t, (t - SIM_START) / NS_PER_S)], stamp=sim)
    wheel = periodic("/imu", 10, lambda t: [_t("imu_link", "sonar", t, yaw=(t - START) / NS_PER_S)])
    rec = recording(sorted(arm + wheel, key=lambda m: m.record_time), ros1=False, clock=sim_clock())
    for robot in (Robot(parse_urdf(urdf, "bot.urdf")), None):
        (clock,) = [
            f for f in findings_of(Scene(rec, robot=robot)) if f.code == "clock" and f.severity is Severity.error
        ]
        assert ("joints of bot.urdf, robot_state_publisher's" in clock.message) is bool(robot), clock.message
        assert ("a device on the wall clock" in clock.message) is (robot is None), clock.message
        assert ("robot_state_publisher (and the joint states it follows) runs without use_sim_time" in clock.hint) is (
            bool(robot)
        )


@pytest.mark.parametrize("paused", [True, False], ids=["simulation-paused", "simulation-ran-on"])
def test_tf_that_stopped_with_the_simulation_is_not_stale_on_its_time(paused: bool) -> None:
    """The TurtleBot 4 simulator (ros2_db3_turtlebot4_gz_sim_paused_at_end_2025): tf stops 2.2 s of wall time before
    the recording ends, but /clock all but stops with it (12 ms of sim time): on the simulation's time, which a
    listener with use_sim_time runs on, tf is fresh to the end. tfx said stale (3 errors, '2.2 s before the
    recording ends', the record clock's). A simulation that ran on without tf is stale, by its own seconds."""
    stop = START + 7 * NS_PER_S  # tf's last arrival; the recording (and /clock) go on for 3 s of wall time
    end = TfMessage("/scan", START + round(SECONDS * NS_PER_S), [], "/lidar")  # the recording goes on (not tf)
    messages = [*(m for m in simulated() if m.record_time <= stop), end]
    clock = sim_clock()
    if paused:
        clock = ClockSamples(clock.topic, clock.record_time, np.minimum(clock.clock, sim(stop)))
    findings = check(recording(messages, ros1=False, clock=clock)).findings
    stale = [f for f in findings if f.code == "stale"]
    if paused:
        assert not stale, stale
    else:
        (odom,) = [f for f in stale if f.frames == ("odom", "base_link")]
        assert odom.message.endswith("stopped at 106.980 (+7.0 s), 3.0 s before the recording ends"), odom.message
