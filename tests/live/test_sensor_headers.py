"""Sensor headers heard live: the ROS 1 listener against hostile publishers and masters (fake ones on
127.0.0.1), the definitions it reads a Header from, the bounded store, and the ROS 2 reader types."""

from __future__ import annotations

import socket
import struct
import threading
import time
from collections.abc import Callable

import pytest

from tests.live.fake_ros1 import fake_master, fake_publisher, ros_reply, silence
from tests.live.test_ros1_hostile import finishes
from tftools.core.time import NS_PER_S, WallClock
from tftools.sources.codecs.types import MessageType, definition_starts_with_header, ros1_message_type
from tftools.sources.contents import StampedRead
from tftools.sources.live.errors import LiveError
from tftools.sources.live.header_store import HeaderStore
from tftools.sources.live.ros1 import subscriber, tcpros
from tftools.sources.live.ros1.headers import Ros1HeaderListener

SCAN = ros1_message_type("sensor_msgs/msg/LaserScan")
STRING = ros1_message_type("std_msgs/msg/String")
PUBLISHED = ros_reply([["/scan", "sensor_msgs/LaserScan"], ["/tf", "tf2_msgs/TFMessage"]])


@pytest.fixture(autouse=True)
def loopback_only(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_HOSTNAME", "127.0.0.1")
    monkeypatch.delenv("ROS_IP", raising=False)


def scan_message(frame_id: bytes = b"laser", sec: int = 5) -> bytes:
    """A serialized sensor_msgs/LaserScan (header, then a few of its fields)."""
    header = struct.pack("<III", 0, sec, 7) + struct.pack("<I", len(frame_id)) + frame_id
    return header + struct.pack("<7f", -1, 1, 0.5, 0, 0, 0, 10) + struct.pack("<I", 0) * 2


def connection_header(msg_type: MessageType = SCAN, callerid: str = "/driver") -> bytes:
    fields = {"callerid": callerid, "md5sum": msg_type.md5sum, "type": msg_type.name}
    return tcpros.encode_header({**fields, "message_definition": msg_type.definition})


def sending(
    *messages: bytes, msg_type: MessageType = SCAN, callerid: str = "/driver"
) -> Callable[[socket.socket], None]:
    """A publisher that sends its header, then ``messages`` over and over, ten a second."""

    def behave(sock: socket.socket) -> None:
        sock.sendall(connection_header(msg_type, callerid))
        while True:
            for message in messages:
                sock.sendall(tcpros.frame(message))
                time.sleep(0.1)

    return behave


def huge_connection_header(sock: socket.socket) -> None:
    sock.sendall(struct.pack("<I", tcpros.MAX_HEADER + 1) + b"\0" * 1024)
    silence(sock)


def huge_message(sock: socket.socket) -> None:
    sock.sendall(connection_header() + struct.pack("<I", tcpros.MAX_MESSAGE + 1))
    silence(sock)


def listen(
    publishers: list[Callable[[socket.socket], None]], topics: list[str] | None = None, seconds: float = 1.5
) -> tuple[StampedRead, list[str]]:
    """What a listener hears of ``publishers`` (each a publisher of every topic) in ``seconds``."""
    notices: list[str] = []
    with (
        fake_publisher(publishers[0]) as first,
        fake_publisher(publishers[-1]) as last,
        fake_master([first, last] if len(publishers) > 1 else [first], getPublishedTopics=PUBLISHED) as master,
    ):
        store = HeaderStore(WallClock(), topics, notices.append)
        listener = Ros1HeaderListener(master.uri, store)
        listener.start()
        time.sleep(seconds)
        assert finishes(listener.close, within=4) is None
        return store.read(), notices


@pytest.fixture
def thread_deaths(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    deaths: list[str] = []
    monkeypatch.setattr(threading, "excepthook", lambda a: deaths.append(f"{a.exc_type.__name__}: {a.exc_value}"))
    monkeypatch.setattr(tcpros, "HEADER_TIMEOUT", 0.5)
    monkeypatch.setattr(subscriber, "RETRY_MAX", 0.2)
    return deaths


def test_every_advertised_topic_with_a_header_is_heard_and_tf_is_not(thread_deaths: list[str]) -> None:
    stamped, notices = listen([sending(scan_message(b"laser"), scan_message(b"laser_2", sec=6))])
    (scan,) = stamped.streams
    assert (scan.topic, scan.type, list(scan.frame_ids)) == ("/scan", "sensor_msgs/msg/LaserScan", ["laser", "laser_2"])
    assert len(scan) >= 8 and set(scan.stamp.tolist()) == {5 * NS_PER_S + 7, 6 * NS_PER_S + 7}
    assert (scan.record_time[1:] >= scan.record_time[:-1]).all()
    assert abs(int(scan.record_time[-1]) - time.time_ns()) < 5 * NS_PER_S  # arrival times on the wall clock
    assert stamped.problems == [] and notices == [] and not thread_deaths


HOSTILE = {
    "huge-connection-header": (huge_connection_header, "above tfx's limit"),
    "huge-message": (huge_message, "above tfx's limit"),
    "garbage-bodies": (sending(b"\x01\x02\x03", b"\xff" * 15 + b"\x7f"), ""),
}


@pytest.mark.parametrize(("behave", "said"), HOSTILE.values(), ids=HOSTILE.keys())
def test_a_hostile_publisher_is_dropped_or_counted_and_the_good_one_heard(
    behave: Callable[[socket.socket], None], said: str, thread_deaths: list[str]
) -> None:
    stamped, notices = listen([behave, sending(scan_message(), callerid="/good")], seconds=2.0)
    (scan,) = stamped.streams
    assert len(scan) >= 8 and list(scan.frame_ids) == ["laser"]
    if said:
        assert len([n for n in notices if said in n]) == 1, notices
    else:  # messages too short for a header (or with a frame_id longer than its message) are counted
        assert any(p.startswith("/scan: ") and "too short for a header" in p for p in stamped.problems)
    assert all("\n" not in n and "\x1b" not in n for n in notices) and not thread_deaths


def test_a_topic_named_whose_messages_have_no_header_is_said_once(thread_deaths: list[str]) -> None:
    stamped, notices = listen([sending(b"\x05\0\0\0hello", msg_type=STRING)], ["/chatter"])
    assert stamped.streams == [] and notices == []
    assert stamped.problems == ["/chatter: std_msgs/msg/String messages have no header"] and not thread_deaths


@pytest.mark.parametrize("answer", [ros_reply("not a list"), ros_reply([["/scan"]]), ros_reply([[1, 2]])])
def test_a_master_listing_junk_topics_is_a_one_line_error(answer: bytes) -> None:
    with fake_master(getPublishedTopics=answer) as master:
        listener = Ros1HeaderListener(master.uri, HeaderStore(WallClock()))
        with pytest.raises(LiveError, match="getPublishedTopics with something tfx cannot use"):
            listener.start()
        listener.close()


DEFINITIONS = {
    "sensor_msgs/LaserScan": (SCAN.definition, True),
    "std_msgs/String": (STRING.definition, False),
    "comments and constants first": ("# a comment\n\nuint8 KIND=1  # Header header\nstd_msgs/Header header\n", True),
    "a header later": ("float64 x\nHeader header\n", False),
    "a header only nested": ("geometry_msgs/Pose pose\n" + "=" * 80 + "\nMSG: std_msgs/Header\n", False),
    "empty": ("", False),
    "not a definition": ("uint8[ broken\n", False),
}


@pytest.mark.parametrize(("definition", "header"), DEFINITIONS.values(), ids=DEFINITIONS.keys())
def test_a_definition_starts_with_a_header_or_not(definition: str, header: bool) -> None:
    assert definition_starts_with_header("tfx_test/msg/Custom", definition) is header


def test_the_store_keeps_a_bounded_number_of_headers_a_topic_and_says_so_once() -> None:
    notices: list[str] = []
    store = HeaderStore(WallClock(), on_notice=notices.append, limit=3)
    for stamp in range(5):
        store.heard("/imu", "sensor_msgs/msg/Imu", (stamp, "imu"))
    store.heard("/imu", "sensor_msgs/msg/Imu", None)
    stamped = store.read()
    (imu,) = stamped.streams
    assert imu.stamp.tolist() == [0, 1, 2] and len(notices) == 1 and "limit per topic" in notices[0]
    assert stamped.problems == [
        "/imu: 1 message too short for a header, skipped",
        "/imu: 2 messages after the first 3 (tfx's limit per topic) not checked",
    ]
    assert store.wants("/imu") and not store.wants("/tf") and not store.wants("/clock")


def test_joint_states_heard_live_are_sensor_data_only_when_asked_for() -> None:
    """One rule with a recording's (``placed_nowhere``): /joint_states' header places nothing in space."""
    for topics, kept in ((None, ["/imu"]), (["/imu", "/joint_states"], ["/imu", "/joint_states"])):
        store = HeaderStore(WallClock(), topics)
        store.heard("/imu", "sensor_msgs/msg/Imu", (1, "imu"))
        store.heard("/joint_states", "sensor_msgs/msg/JointState", (1, "base_link"))
        assert sorted(s.topic for s in store.read().streams) == kept


def test_ros2_sensor_topics_are_read_with_their_types_whole_layout() -> None:
    from tests.live.ros2_processes import require_cyclonedds

    require_cyclonedds()
    from tftools.sources.live.ros2.headers import sensor_type

    scan = sensor_type("sensor_msgs::msg::dds_::LaserScan_")
    assert scan is not None and scan.__idl_typename__ == "sensor_msgs::msg::dds_::LaserScan_"
    assert list(scan.__annotations__) == ["header", "angle_min", "angle_max", "angle_increment", "time_increment",
                                          "scan_time", "range_min", "range_max", "ranges", "intensities"]  # fmt: skip
    assert sensor_type("std_msgs::msg::dds_::String_") is None
    assert sensor_type("std_msgs::msg::dds_::String_", unknown_too=True) is None  # known: it has no header
    assert sensor_type("my_msgs::msg::dds_::Custom_") is None
    custom = sensor_type("my_msgs::msg::dds_::Custom_", unknown_too=True)
    assert custom is not None and list(custom.__annotations__) == ["header"]
