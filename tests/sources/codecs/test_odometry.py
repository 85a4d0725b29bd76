"""nav_msgs/Odometry read by the one header decoder of each encoding (ROS 1, CDR): its header, and the transform
it states beside it, from the header's frame to its child_frame_id (the pose's position and orientation)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from tftools.core.time import WallClock
from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs.decoded import FrameNames, message_header
from tftools.sources.codecs.select import Wanted, header_decoder, select
from tftools.sources.codecs.types import typestore
from tftools.sources.codecs.wire import HEADER_BYTES
from tftools.sources.live.header_store import HeaderStore

ODOMETRY = "nav_msgs/msg/Odometry"
POSE = (1.5, -2.25, 0.125, 0.0, 0.0, 0.6, 0.8)


def _odometry(store: Any, frame: str, child: str) -> Any:
    types = store.types
    stamp = types["builtin_interfaces/msg/Time"](1_700_000_000, 250)
    ros1_header = next(name for name, _ in store.fielddefs["std_msgs/msg/Header"][1]) == "seq"
    header = types["std_msgs/msg/Header"](*([7] if ros1_header else []), stamp, frame)
    point = types["geometry_msgs/msg/Point"](*POSE[:3])
    orientation = types["geometry_msgs/msg/Quaternion"](*POSE[3:])
    pose = types["geometry_msgs/msg/PoseWithCovariance"](
        types["geometry_msgs/msg/Pose"](point, orientation), np.arange(36, dtype=np.float64)
    )
    linear = types["geometry_msgs/msg/Vector3"](0.1, 0.0, 0.0)
    twist = types["geometry_msgs/msg/TwistWithCovariance"](
        types["geometry_msgs/msg/Twist"](linear, linear), np.zeros(36)
    )
    return types[ODOMETRY](header, child, pose, twist)


def _payloads(encoding: str, messages: list[tuple[str, str]]) -> list[bytes]:
    if encoding == "ros1":
        store = typestore("ros1_noetic")
        return [bytes(store.serialize_ros1(_odometry(store, f, c), ODOMETRY)) for f, c in messages]
    store = typestore("ros2_humble")
    return [bytes(store.serialize_cdr(_odometry(store, f, c), ODOMETRY)) for f, c in messages]


def _decode(encoding: str, payloads: list[bytes], cut: int | None = None) -> tuple[Any, FrameNames]:
    raw = np.frombuffer(b"".join(payloads), np.uint8)
    lengths = np.array([len(p) for p in payloads], np.int64)
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    frames = FrameNames()
    decode = ros1.decode_odometry if encoding == "ros1" else cdr.decode_odometry
    return decode(raw, starts, np.minimum(lengths, cut) if cut else lengths, frames), frames


@pytest.mark.parametrize("encoding", ["ros1", "cdr"])
def test_each_odometry_states_its_child_frame_and_pose(encoding: str) -> None:
    headers, frames = _decode(encoding, _payloads(encoding, [("odom", "base_footprint"), ("odom", "base_link")]))
    assert headers.failures == []
    assert headers.stamp.tolist() == [1_700_000_000 * 10**9 + 250] * 2
    assert [frames.names[i] for i in headers.frame.tolist()] == ["odom", "odom"]
    assert [frames.names[i] for i in headers.child.tolist()] == ["base_footprint", "base_link"]
    assert headers.pose.tolist() == [list(POSE)] * 2


@pytest.mark.parametrize("encoding", ["ros1", "cdr"])
def test_an_odometry_given_cut_short_keeps_its_header_alone(encoding: str) -> None:
    """Bag readers give a header decoder the first ``HEADER_BYTES`` of a message: a frame_id long enough leaves
    no room for the child's name or the pose, which are then unknown, not damage."""
    long_frame = "o" * (HEADER_BYTES - 40)
    headers, frames = _decode(encoding, _payloads(encoding, [(long_frame, "base_link")]), cut=HEADER_BYTES)
    assert headers.failures == [] and frames.names[int(headers.frame[0])] == long_frame
    assert headers.child.tolist() == [-1] and np.isnan(headers.pose).all()


@pytest.mark.parametrize("encoding", ["ros1", "cdr"])
def test_an_empty_child_is_read_as_empty_and_one_cut_inside_it_as_unknown(encoding: str) -> None:
    """A real PR2's /base_odometry/odom (jsk_pr2eus's pr1012_sensors.bag) names an empty child_frame_id: read
    as "", which ``targets.fused_edge`` tells from a child it names; a message ending inside its child_frame_id
    states none (-1); the plain header decoder reads no child at all."""
    whole = _payloads(encoding, [("odom", "base_footprint"), ("odom", "")])
    (cut,) = _payloads(encoding, [("odom_combined", "base_link")])
    child_at = (4 + 8 + 4 + 14 + 2) if encoding == "cdr" else (4 + 8 + 4 + 13 + 2)  # inside "base_link"
    raw = np.frombuffer(b"".join([*whole, cut[:child_at]]), np.uint8)
    lengths = np.array([len(whole[0]), len(whole[1]), child_at], np.int64)
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    frames = FrameNames()
    headers = (ros1.decode_odometry if encoding == "ros1" else cdr.decode_odometry)(raw, starts, lengths, frames)
    assert headers.failures == []
    assert [frames.names[i] for i in headers.frame.tolist()] == ["odom", "odom", "odom_combined"]
    assert [frames.names[i] if i >= 0 else "?" for i in headers.child.tolist()] == ["base_footprint", "", "?"]
    plain = (ros1.decode_headers if encoding == "ros1" else cdr.decode_headers)(raw, starts, lengths, FrameNames())
    assert plain.failures == [] and len(plain.child) == 0


@pytest.mark.parametrize("encoding", ["ros1", "cdr"])
def test_odometry_topics_are_read_by_the_odometry_decoder(encoding: str) -> None:
    codec, _ = select("/odom", "nav_msgs/Odometry" if encoding == "ros1" else ODOMETRY, encoding, Wanted(headers=()))
    assert codec is not None and getattr(codec, "decoder", "") == f"{encoding}.decode_odometry"
    imu, _ = select("/imu", "sensor_msgs/msg/Imu", encoding, Wanted(headers=()))
    assert imu is not None and getattr(imu, "decoder", "") == f"{encoding}.decode_headers"


@pytest.mark.parametrize("encoding", ["ros1", "cdr"])
def test_odometry_heard_live_keeps_the_transform_it_states(encoding: str) -> None:
    """A live listener decodes each message alone (``message_header``) with the same decoder a bag's read uses
    (``header_decoder``): an Odometry's child and pose are kept beside its header; an IMU's have none."""
    store = HeaderStore(WallClock())
    for payload in _payloads(encoding, [("odom", "base_link"), ("odom", "base_footprint")]):
        store.heard("/odom", ODOMETRY, *message_header(header_decoder(ODOMETRY, encoding), payload))
    store.heard("/imu", "sensor_msgs/msg/Imu", (5, "imu"))
    imu, odom = store.read().streams
    assert odom.states_transforms and not imu.states_transforms
    assert [odom.child_ids[c] for c in odom.child.tolist()] == ["base_link", "base_footprint"]
    assert odom.pose.tolist() == [list(POSE)] * 2
