"""``tfx filter`` on bags of every format holding tf and sensor data: per topic, what a MessageFilter did."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rosbags.typesys.store import Typestore

from tests.analysis.test_filter import START, robot
from tests.bags import TfMessage, write_bag
from tests.cli.conftest import Tfx
from tests.sources.bag.test_rosbag2 import convert
from tftools.core.time import NS_PER_S

MS = 1_000_000


def _stamped(store: Typestore, msgtype: str, frame_id: str, stamp: int, **fields: Any) -> Any:
    types = store.types
    sec, nanosec = divmod(stamp, NS_PER_S)
    header = types["std_msgs/msg/Header"](
        seq=0, stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id=frame_id
    )
    return types[msgtype](header=header, **fields)


def scan(store: Typestore, frame_id: str, stamp: int) -> Any:
    """An empty sensor_msgs/LaserScan."""
    empty = np.zeros(0, np.float32)
    return _stamped(store, "sensor_msgs/msg/LaserScan", frame_id, stamp, angle_min=0.0, angle_max=1.0,
                    angle_increment=0.1, time_increment=0.0, scan_time=0.0, range_min=0.0, range_max=1.0,
                    ranges=empty, intensities=empty)  # fmt: skip


def image(store: Typestore, frame_id: str, stamp: int) -> Any:
    """A one-pixel sensor_msgs/Image."""
    return _stamped(store, "sensor_msgs/msg/Image", frame_id, stamp, height=1, width=1, encoding="mono8",
                    is_bigendian=0, step=1, data=np.zeros(1, np.uint8))  # fmt: skip


def _sensor_messages(store: Typestore) -> list[tuple[str, str, int, object]]:
    """(topic, type, record time, message): a laser whose tf comes late, an IMU that is fine, a camera
    whose frame_id is misspelt, and a status topic with a header but no frame_id."""
    types = store.types
    out = []
    for i in range(1, 200):
        stamp = START + i * 50 * MS + 7 * MS
        out.append(("/scan", "sensor_msgs/msg/LaserScan", stamp + 5 * MS, scan(store, "laser", stamp)))
        quaternion = types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)
        vector = types["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
        covariance = np.zeros(9, np.float64)
        imu = _stamped(store, "sensor_msgs/msg/Imu", "imu", stamp, orientation=quaternion,
                       orientation_covariance=covariance, angular_velocity=vector,
                       angular_velocity_covariance=covariance, linear_acceleration=vector,
                       linear_acceleration_covariance=covariance)  # fmt: skip
        out.append(("/imu", "sensor_msgs/msg/Imu", stamp + 25 * MS, imu))
    for i in range(1, 10):
        stamp = START + i * NS_PER_S
        out.append(("/camera/image_raw", "sensor_msgs/msg/Image", stamp + 3 * MS, image(store, "camra", stamp)))
        status = _stamped(store, "diagnostic_msgs/msg/DiagnosticArray", "", stamp, status=[])
        out.append(("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray", stamp + 3 * MS, status))
    return out


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The robot's tf and the sensor data in a ROS1 bag, and its ROS2 copies (.db3 and .mcap)."""
    return sensor_bags(tmp_path_factory.mktemp("filter"), robot(), _sensor_messages)


def sensor_bags(
    folder: Path, tf: list[TfMessage], sensors: Callable[[Any], list[tuple[str, str, int, object]]]
) -> dict[str, Path]:
    """``tf`` and the ``sensors(typestore)`` messages (topic, type, record time, message) in a ROS1 bag,
    and its ROS2 copies (.db3 and .mcap)."""
    from rosbags.rosbag1 import Reader, Writer
    from rosbags.typesys import Stores, get_typestore

    tf_only = write_bag(folder / "tf.bag", tf)
    store = get_typestore(Stores.ROS1_NOETIC)
    ros1 = folder / "robot.bag"
    with Reader(tf_only) as reader, Writer(ros1) as writer:
        added = {}
        rows: list[tuple[int, str, str, Any, Any]] = [
            (t, c.topic, c.msgtype, raw, c) for c, t, raw in reader.messages()
        ]
        rows += [(t, topic, kind, store.serialize_ros1(msg, kind), None) for topic, kind, t, msg in sensors(store)]
        for record, topic, kind, raw, connection in sorted(rows, key=lambda r: r[0]):
            if topic not in added:
                definition = connection.msgdef.data if connection else None
                latching = connection.ext.latching if connection else None  # /tf_static stays latched
                added[topic] = writer.add_connection(topic, kind, typestore=store, msgdef=definition,
                                                     md5sum=connection.digest if connection else None,
                                                     latching=latching)  # fmt: skip
            writer.write(added[topic], record, bytes(raw))
    return {
        "ros1": ros1,
        "db3": convert(ros1, folder / "robot_db3", "sqlite3"),
        "mcap": convert(ros1, folder / "robot_mcap", "mcap"),
    }


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap"])
def test_filter_tells_per_topic_what_a_message_filter_did(tfx: Tfx, bags: dict[str, Path], fmt: str) -> None:
    result = tfx("filter", "-b", bags[fmt], "--target", "odom", "--format", "json")
    assert result.code == 1, result.stderr  # the camera's messages are lost for good
    report = json.loads(result.stdout)
    assert report["target"] == "odom"
    topics = {t["topic"]: t for t in report["topics"]}
    assert set(topics) == {"/scan", "/imu", "/camera/image_raw"} and report["skipped"] == ["/diagnostics"]
    scan, imu, camera = topics["/scan"], topics["/imu"], topics["/camera/image_raw"]
    assert (scan["messages"], scan["on_arrival"], scan["later"], scan["never"]) == (199, 0, 199, 0)
    assert scan["wait_s"]["p50"] == pytest.approx(0.068) and scan["late_edge"] == ["base_link", "laser"]
    assert scan["frame_ids"] == ["laser"] and scan["type"] == "sensor_msgs/msg/LaserScan"
    assert (imu["on_arrival"], imu["later"], imu["never"]) == (199, 0, 0)
    assert camera["never"] == 9 and camera["reasons"] == {"unknown_frame": 9}


def test_a_filter_timeout_and_queue_count_what_they_drop(tfx: Tfx, bags: dict[str, Path]) -> None:
    report = json.loads(
        tfx("filter", "/scan", "-b", bags["ros1"], "--wait", "0.05", "--queue", "1", "-f", "json").stdout
    )
    (scan,) = report["topics"]
    assert report["target"] == "odom" and "REP 105" in report["target_reason"]
    assert scan["dropped_by_wait"] == 199  # each waits 68 ms
    assert scan["queue_needed"] == 2  # a scan comes every 50 ms and waits 68 ms: two wait at once
    assert scan["dropped_by_queue"] == 198  # a queue of one pushes each out but the last
    assert scan["wait_needed_s"] == pytest.approx(0.068)
    roomy = json.loads(tfx("filter", "/scan", "-b", bags["ros1"], "--queue", "2", "-f", "json").stdout)
    assert roomy["topics"][0]["dropped_by_queue"] == 0
    text = tfx("filter", "/scan", "-b", bags["ros1"])
    assert text.code == 0 and "/scan" in text.stdout and "base_link -> laser" in text.stdout


def test_what_keeps_messages_no_timeout_keeps_is_said(tfx: Tfx, bags: dict[str, Path]) -> None:
    """The camera's frame_id is misspelt: 'to keep 99.9%: no timeout can' said what does not help; it says
    what does (a real AUV's DVL, GPS and odometry topics name frames no transform has)."""
    result = tfx("filter", "/camera/image_raw", "-b", bags["ros1"])
    assert result.code == 1
    assert "no timeout can (publish its frame's transform, or fix the frame_id)" in " ".join(result.stdout.split())


def test_a_recording_of_tf_alone_is_no_sensor_data_to_check_not_an_error(tfx: Tfx, bags: dict[str, Path]) -> None:
    """``tfx filter`` on each of a CI's recordings, one of tf alone (a calibration's /tf_static, a tf test bag)
    and one with sensors: the tf one exited 2, "no topic with a Header", as if the command line were wrong. It
    says there is no sensor data to check, the topics there are and what to do if some was expected, and exits
    0; a topic named that is not there stays a usage error (corpus: the Grand Tour's calibration bag)."""
    tf_only = bags["ros1"].parent / "tf.bag"  # sensor_bags' tf, before the sensors were added
    codes = [tfx("filter", "-b", bag).code for bag in (tf_only, bags["ros1"])]
    assert codes == [0, 1]  # the sensors' camera is lost for good
    said = tfx("filter", "-b", tf_only)
    text = " ".join(said.stdout.split())
    assert "No sensor data to check: no topic's messages start with a Header" in text, text
    assert "Topics: /tf (tf2_msgs/TFMessage), /tf_static (tf2_msgs/TFMessage)." in text, text
    assert "If you expected sensor data: record its topics beside /tf and /tf_static" in text and not said.stderr
    report = json.loads(tfx("filter", "-b", tf_only, "-f", "json").stdout)
    assert report["topics"] == [] and report["target"] == "odom"
    assert report["unchecked"]["reasons"] == [] and list(report["unchecked"]["topics"]) == ["/tf", "/tf_static"]
    assert json.loads(tfx("filter", "-b", bags["ros1"], "-f", "json").stdout)["unchecked"] is None
    named = tfx("filter", "/scan", "-b", tf_only)
    assert named.code == 2 and "/scan: not in the recording" in named.stderr and not named.stdout


@pytest.mark.parametrize("named", [("/scan",), ("/scan", "/odom"), ("/tf",), ("/diagnostics",)])
def test_the_hint_for_named_topics_is_not_the_command_just_run(
    tfx: Tfx, bags: dict[str, Path], named: tuple[str, ...]
) -> None:
    """``tfx filter /scan`` where /scan holds nothing to check answered 'e.g. tfx filter /scan -b BAG': the
    command just run. Topics were named, so the way on is other names or none (every topic with a Header)."""
    tf_only = bags["ros1"].parent / "tf.bag"
    said = tfx("filter", *named, "-b", bags["ros1"] if named == ("/diagnostics",) else tf_only)
    assert said.code == 2 and len(said.stderr.strip().splitlines()) == 1
    assert "e.g. tfx filter" not in said.stderr and "e.g. /scan" not in said.stderr
    assert "or none: tfx filter -b BAG checks every such topic" in said.stderr


def test_filter_refuses_what_it_cannot_use(tfx: Tfx, bags: dict[str, Path]) -> None:
    nothing = tfx("filter", "/nothing", "-b", bags["ros1"])
    assert nothing.code == 2 and "no topic with a Header" in nothing.stderr
    assert "/nothing: not in the recording" in nothing.stderr
    # a topic that is there, without a header: its type said (a TurtleBot3's /cmd_vel was 'not in the
    # recording, or its messages have no header')
    headless = tfx("filter", "/tf", "-b", bags["ros1"])
    assert headless.code == 2 and "/tf: tf2_msgs/TFMessage messages have no header" in headless.stderr
    # Only headers without a frame_id (a turtlesim bag's /rosout): said so, not an empty table with exit 0.
    unframed = tfx("filter", "/diagnostics", "-b", bags["ros1"])
    assert unframed.code == 2 and not unframed.stdout
    assert "only /diagnostics, whose header has no frame_id (not tied to tf)" in unframed.stderr
    assert len(unframed.stderr.strip().splitlines()) == 1
    unknown = tfx("filter", "-b", bags["ros1"], "--target", "nowhere")
    assert unknown.code == 2 and "frame 'nowhere' does not exist" in unknown.stderr


@pytest.fixture(scope="module")
def unrecorded_scan(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The robot's tf and /imu, and a /scan the recording lists without a message (a real TurtleBot3's
    metadata v4 bag: its /scan, a best-effort topic, listed with 0 messages and no QoS profile), as a ROS1
    bag and its .db3 copy."""
    from rosbags.rosbag1 import Reader, Writer
    from rosbags.typesys import Stores, get_typestore

    folder = tmp_path_factory.mktemp("unrecorded")
    source = sensor_bags(folder, robot(), lambda store: [m for m in _sensor_messages(store) if m[0] == "/imu"])
    ros1 = folder / "empty_scan.bag"
    with Reader(source["ros1"]) as reader, Writer(ros1) as writer:
        connections = {
            c.id: writer.add_connection(
                c.topic, c.msgtype, msgdef=c.msgdef.data, md5sum=c.digest, latching=getattr(c.ext, "latching", None)
            )
            for c in reader.connections
        }
        writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=get_typestore(Stores.ROS1_NOETIC))
        for connection, record, raw in reader.messages():
            writer.write(connections[connection.id], record, raw)
    return {"ros1": ros1, "db3": convert(ros1, folder / "empty_scan_db3", "sqlite3")}


@pytest.mark.parametrize("fmt", ["ros1", "db3"])
def test_a_topic_recorded_without_a_message_is_said_so(tfx: Tfx, unrecorded_scan: dict[str, Path], fmt: str) -> None:
    """``tfx filter /scan`` on a recording whose /scan holds no message answered 'name topics of stamped
    messages, e.g. tfx filter /scan -b BAG': the command just run. It says the topic is there without a message
    and what to look at (the recorder); named beside a topic that has messages, it is not left out unsaid."""
    alone = tfx("filter", "/scan", "-b", unrecorded_scan[fmt])
    assert alone.code == 2 and not alone.stdout and len(alone.stderr.strip().splitlines()) == 1
    assert "/scan: in the recording without a message" in alone.stderr
    assert "the recorder received none of its messages" in alone.stderr and "e.g. tfx filter /scan" not in alone.stderr
    beside = tfx("filter", "/scan", "/imu", "-b", unrecorded_scan[fmt], "-f", "json")
    assert beside.code == 0 and [t["topic"] for t in json.loads(beside.stdout)["topics"]] == ["/imu"]
    assert "tfx: warning: /scan: in the recording without a message" in beside.stderr
    every = tfx("filter", "-b", unrecorded_scan[fmt])  # not asked for by name: no warning
    assert every.code == 0 and "/imu" in every.stdout and "without a message" not in every.stderr


def test_wtf_reports_the_sensor_data_that_tf_lets_down(tfx: Tfx, bags: dict[str, Path]) -> None:
    (report,) = json.loads(tfx("wtf", bags["mcap"], "--format", "json").stdout)["bags"]
    codes = {f["code"]: f for f in report["findings"]}
    assert codes["sensor_frame"]["severity"] == "error" and "'camra'" in codes["sensor_frame"]["message"]
    assert "did you mean 'camera'?" in codes["sensor_frame"]["message"]
    waiting = codes["sensor_wait"]  # each scan waits 68 ms for the laser's next transform: a note
    assert waiting["severity"] == "info" and "/scan" in waiting["message"] and "odom" in waiting["message"]


def test_wtf_says_which_frame_sensor_data_was_checked_in(tfx: Tfx, bags: dict[str, Path]) -> None:
    (usual,) = json.loads(tfx("wtf", bags["ros1"], "-f", "json").stdout)["bags"]
    assert usual["sensor_data"] == {
        "topics": ["/camera/image_raw", "/imu", "/scan"],  # /diagnostics names no frame: not tf's business
        "target": "odom",
        "target_reason": "REP 105's odom frame",
    }
    text = tfx("wtf", bags["ros1"])
    assert "3 topics of sensor data checked in odom (REP 105's odom frame)" in text.stdout

    (laser,) = json.loads(tfx("wtf", bags["ros1"], "--target", "/laser", "-f", "json").stdout)["bags"]
    assert (laser["sensor_data"]["target"], laser["sensor_data"]["target_reason"]) == ("laser", "asked for")
    waits = {f["message"].split(":")[0] for f in laser["findings"] if f["code"] == "sensor_wait"}
    assert "/imu" in waits  # in the laser's frame the IMU waits for base_link -> laser, 30 ms late

    (scan,) = json.loads(tfx("wtf", bags["db3"], "--sensor", "/scan", "-f", "json").stdout)["bags"]
    assert scan["sensor_data"]["topics"] == ["/scan"] and "sensor_frame" not in {f["code"] for f in scan["findings"]}

    (elsewhere,) = json.loads(tfx("wtf", bags["ros1"], "--target", "nowhere", "-f", "json").stdout)["bags"]
    assert elsewhere["sensor_data"]["target"] == "odom"  # a fleet's robots may lack the frame: the usual one
    assert "'nowhere', asked for, is not a frame of this recording" in elsewhere["sensor_data"]["target_reason"]


def test_a_sensor_whose_few_messages_waited_long_is_a_note_with_the_wait_that_keeps_them(
    tfx: Tfx, tmp_path: Path
) -> None:
    """Issue 39, the real boat (stinger, /imu/data: 97% of its messages wait 18 ms, one 0.318 s): the wait
    suggested keeps 99.9% of the messages, but the finding is loud only where the p99 wait is long."""
    bag = sensor_bags(tmp_path, robot(), _scans_two_waiting_long)["db3"]
    (scan,) = json.loads(tfx("filter", "/scan", "-b", bag, "--target", "odom", "-f", "json").stdout)["topics"]
    assert scan["wait_s"]["p99"] < 0.2 < scan["wait_needed_s"]
    (report,) = json.loads(tfx("wtf", bag, "--sensor", "/scan", "-f", "json").stdout)["bags"]
    (waiting,) = [f for f in report["findings"] if f["code"] == "sensor_wait"]
    assert waiting["severity"] == "info"
    # 99.9% of 199 messages is all of them, said so (a real TurtleBot 4's 116 scans read "99.9% within 0.115 s")
    assert f"a timeout of at least {scan['wait_needed_s']:.3f} s (it keeps all of them)" in waiting["hint"]


def _scans_two_waiting_long(store: Typestore) -> list[tuple[str, str, int, object]]:
    """/scan at 20 Hz waiting 68 ms for the laser's transform, but two of 199 stamped 250 ms ahead of their
    arrival, which wait ~0.32 s (p99 68 ms; keeping 99.9% takes the long wait)."""
    out: list[tuple[str, str, int, object]] = []
    for i in range(1, 200):
        ahead = 250 * MS if i in (50, 150) else 0
        stamp = START + i * 50 * MS + 7 * MS
        out.append(("/scan", "sensor_msgs/msg/LaserScan", stamp + 5 * MS, scan(store, "laser", stamp + ahead)))
    return out


def _scans_two_waiting_longer(store: Typestore) -> list[tuple[str, str, int, object]]:
    """/scan at 20 Hz: each waits 68 ms for the laser's next transform, but two of 199, stamped 1 ms into
    the laser's period and arriving 1 ms later, wait 78 ms (p99 68.2 ms; keeping 99.9% takes 78)."""
    out: list[tuple[str, str, int, object]] = []
    for i in range(1, 200):
        early = i in (50, 150)
        stamp = START + i * 50 * MS + (1 if early else 7) * MS
        out.append(
            ("/scan", "sensor_msgs/msg/LaserScan", stamp + (1 if early else 5) * MS, scan(store, "laser", stamp))
        )
    return out


def test_wtf_and_filter_suggest_one_wait_for_a_sensor(tfx: Tfx, tmp_path: Path) -> None:
    """Issue 39: on create3 /scan ``wtf`` suggested a timeout of at least 0.286 s (the waits' p99) while ``filter``
    said "wait 0.413 s" to keep 99.9% of the messages: one figure (``figures.wait_keeping``), both say it."""
    bag = sensor_bags(tmp_path, robot(), _scans_two_waiting_longer)["db3"]
    (scan,) = json.loads(tfx("filter", "/scan", "-b", bag, "--target", "odom", "-f", "json").stdout)["topics"]
    assert scan["wait_needed_s"] == pytest.approx(0.078) and scan["wait_s"]["p99"] == pytest.approx(0.0682)
    (report,) = json.loads(tfx("wtf", bag, "--sensor", "/scan", "-f", "json").stdout)["bags"]
    (waiting,) = [f for f in report["findings"] if f["code"] == "sensor_wait"]
    assert "(all within 0.078 s)" in waiting["message"]  # 99.9% of 199 messages is every one
    assert "a timeout of at least 0.078 s (it keeps all of them)" in waiting["hint"]
    table = tfx("filter", "/scan", "-b", bag, "--target", "odom").stdout
    assert "wait 0.078 s" in table


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap"])
def test_a_sensor_topic_given_as_tf_is_named_with_its_type_by_wtf_as_by_echo(
    tfx: Tfx, bags: dict[str, Path], fmt: str
) -> None:
    """Issue 39, ros2_db3_kth_robp_scan_statics_2024: ``wtf --topic /scan`` said "no transforms on /scan" where
    ``echo --topic /scan`` said /scan is a LaserScan, not a transform message (wtf reads /scan's headers, so
    the topic was not counted as skipped): both say so now, in one line, and name the topics that carry tf."""
    kind = "sensor_msgs/LaserScan" if fmt == "ros1" else "sensor_msgs/msg/LaserScan"
    line = f"/scan: {kind} ({'ros1' if fmt == 'ros1' else 'cdr'}) is not a transform message tftools reads, skipped"
    wtf = tfx("wtf", "-b", bags[fmt], "--topic", "/scan", "-f", "json")
    (report,) = json.loads(wtf.stdout)["bags"]
    (no_tf,) = [f for f in report["findings"] if f["code"] == "no_tf"]
    assert no_tf["message"] == f"no transforms read in {bags[fmt]}: {line}"
    assert no_tf["hint"] == "/tf and /tf_static carry transforms: leave out --topic"  # every command's hint
    echo = tfx("echo", "odom", "base_link", "-b", bags[fmt], "--topic", "/scan")
    assert echo.code == 2 and f"no transforms read: {line}" in echo.stderr
    assert "carry transforms: leave out --topic" in echo.stderr


def test_joint_states_are_sensor_data_to_filter_as_to_wtf_only_when_named(tfx: Tfx, tmp_path: Path) -> None:
    """The Webots e-puck (ros2_db3_webots_epuck): filter checked /joint_states (frame base_link) of its 20 topics
    where wtf said "19 topics of sensor data" (it read /joint_states whole). Joint positions place nothing in space
    (robot_state_publisher turns them into tf): one rule for both, and a topic named is checked all the same."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    from tests.sources.ros2_helpers import Tf, tf_cdr

    store, bag = get_typestore(Stores.ROS2_HUMBLE), tmp_path / "joints"
    types = {"/joint_states": "sensor_msgs/msg/JointState", "/imu": "sensor_msgs/msg/Imu"}
    with Writer(bag, version=8) as writer:
        tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=store)
        sensors = {topic: writer.add_connection(topic, kind, typestore=store) for topic, kind in types.items()}
        for i in range(20):
            stamp = START + i * NS_PER_S // 10
            sec, nanosec = divmod(stamp, NS_PER_S)
            writer.write(tf, stamp + MS, tf_cdr([Tf("odom", "base_link", sec, nanosec, (0.01 * i, 0, 0))]))
            header = store.types["std_msgs/msg/Header"](
                stamp=store.types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id="base_link"
            )
            t = store.types
            vector, zeros = t["geometry_msgs/msg/Vector3"](0.0, 0.0, 0.0), np.zeros(9)
            messages = {
                "/joint_states": t["sensor_msgs/msg/JointState"](header, ["wheel"], *([np.array([0.1 * i])] * 3)),
                "/imu": t["sensor_msgs/msg/Imu"](
                    header, t["geometry_msgs/msg/Quaternion"](0.0, 0.0, 0.0, 1.0), zeros, vector, zeros, vector, zeros
                ),
            }
            for topic, message in messages.items():
                writer.write(sensors[topic], stamp + 2 * MS, store.serialize_cdr(message, types[topic]))
    checked = json.loads(tfx("filter", "-b", bag, "--format", "json").stdout)
    assert [t["topic"] for t in checked["topics"]] == ["/imu"]
    assert "1 topic of sensor data checked" in tfx("wtf", bag).stdout
    named = json.loads(tfx("filter", "/joint_states", "/imu", "-b", bag, "--format", "json").stdout)
    assert sorted(t["topic"] for t in named["topics"]) == ["/imu", "/joint_states"]


def test_a_recording_whose_only_header_is_a_gamepad_s_says_so(tfx: Tfx, tmp_path: Path) -> None:
    """A gamepad's sensor_msgs/Joy (joy_node stamps it in 'joy'; the KTH arm's /joy, corpus
    ros2_mcap_kth_robp_arm_joy_no_tf_2025) is no sensor data: where it is the only topic with a header, filter said
    "no topic with a Header to check" alone. It says what the recording holds, and that the topic is checked when
    named (and, as of a recording of tf alone, that there is nothing to check is no error)."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    from tests.sources.ros2_helpers import Tf, tf_cdr

    store, bag = get_typestore(Stores.ROS2_HUMBLE), tmp_path / "joy"
    with Writer(bag, version=8) as writer:
        tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=store)
        joy = writer.add_connection("/joy", "sensor_msgs/msg/Joy", typestore=store)
        for i in range(20):
            stamp = START + i * NS_PER_S // 10
            writer.write(tf, stamp + MS, tf_cdr([Tf("odom", "base_link", *divmod(stamp, NS_PER_S), (0.01 * i, 0, 0))]))
            sec, nanosec = divmod(stamp, NS_PER_S)
            header = store.types["std_msgs/msg/Header"](
                stamp=store.types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec), frame_id="joy"
            )
            pad = store.types["sensor_msgs/msg/Joy"](
                header=header, axes=np.zeros(2, np.float32), buttons=np.zeros(4, np.int32)
            )
            writer.write(joy, stamp + 2 * MS, store.serialize_cdr(pad, "sensor_msgs/msg/Joy"))
    said = tfx("filter", "-b", bag)
    text = " ".join(said.stdout.split())
    assert said.code == 0 and "No sensor data to check: /joy is sensor_msgs/msg/Joy, a gamepad's" in text, text
    assert "its frame_id places nothing in space, so nothing ties it to tf" in text
    named = tfx("filter", "/joy", "-b", bag)  # asked for: checked, its frame unknown to tf
    assert named.code == 1 and "/joy" in named.stdout and "unknown frame" in named.stdout
