"""Odometry's headers are read with the child_frame_id after them, in ROS1's bytes and CDR's alike."""

from __future__ import annotations

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs.decoded import FrameNames, HeaderDecoder
from tftools.sources.codecs.select import HeaderCodec, Wanted, select
from tftools.sources.codecs.wire import HEADER_BYTES


def _odometry(ros2: bool, frame: str, child: str) -> bytes:
    store = get_typestore(Stores.ROS2_HUMBLE if ros2 else Stores.ROS1_NOETIC)
    msgs = store.types
    stamp = msgs["builtin_interfaces/msg/Time"](sec=7, nanosec=5)
    seq = {} if ros2 else {"seq": 3}
    header = msgs["std_msgs/msg/Header"](stamp=stamp, frame_id=frame, **seq)
    odometry = msgs["nav_msgs/msg/Odometry"](
        header=header,
        child_frame_id=child,
        pose=msgs["geometry_msgs/msg/PoseWithCovariance"](
            pose=msgs["geometry_msgs/msg/Pose"](
                position=msgs["geometry_msgs/msg/Point"](x=1.0, y=2.0, z=0.0),
                orientation=msgs["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
            ),
            covariance=np.zeros(36),
        ),
        twist=msgs["geometry_msgs/msg/TwistWithCovariance"](
            twist=msgs["geometry_msgs/msg/Twist"](
                linear=msgs["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                angular=msgs["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
            ),
            covariance=np.zeros(36),
        ),
    )
    kind = "nav_msgs/msg/Odometry"
    return bytes(store.serialize_cdr(odometry, kind) if ros2 else store.serialize_ros1(odometry, kind))


def _read(decode: HeaderDecoder, payloads: list[bytes]) -> tuple[list[str], list[str]]:
    raw = np.frombuffer(b"".join(payloads), np.uint8)
    lengths = np.array([len(p) for p in payloads], np.int64)
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    frames = FrameNames()
    headers = decode(raw, starts, lengths, frames)
    assert not headers.failures
    named = [frames.names[i] for i in headers.frame.tolist()]
    return named, [frames.names[i] if i >= 0 else "?" for i in headers.child.tolist()]


@pytest.mark.parametrize("ros2", [False, True], ids=["ros1", "cdr"])
def test_odometry_s_child_frame_id_is_read_after_its_header(ros2: bool) -> None:
    """A real PR2's /base_odometry/odom (jsk_pr2eus's pr1012_sensors.bag) names 'odom' and an empty child: which
    other odometry places the robot is told by the child where it is given, by the tree where it is empty."""
    decode = cdr.decode_odometry_headers if ros2 else ros1.decode_odometry_headers
    whole = [_odometry(ros2, "odom", "base_footprint"), _odometry(ros2, "odom", "")]
    cut = _odometry(ros2, "odom_combined", "base_link")[: (4 + 8 + 4 + 14 + 2) if ros2 else (4 + 8 + 4 + 13 + 2)]
    frames, children = _read(decode, [*whole, cut])
    assert frames == ["odom", "odom", "odom_combined"]
    assert children == ["base_footprint", "", "?"]  # the last cut off inside its child_frame_id
    plain = cdr.decode_headers if ros2 else ros1.decode_headers
    assert (
        len(
            plain(
                np.frombuffer(whole[0], np.uint8), np.zeros(1, np.int64), np.array([len(whole[0])]), FrameNames()
            ).child
        )
        == 0
    )


@pytest.mark.parametrize(("encoding", "name"), [("ros1", "nav_msgs/Odometry"), ("cdr", "nav_msgs/msg/Odometry")])
def test_odometry_is_read_with_its_child_and_other_stamped_types_without(encoding: str, name: str) -> None:
    wanted = Wanted(headers=())

    def decoder(type_name: str) -> str:
        codec, _ = select("/topic", type_name, encoding, wanted)
        assert isinstance(codec, HeaderCodec)
        return codec.decoder

    assert decoder(name) == f"{encoding}.decode_odometry_headers"
    assert (
        decoder(name.replace("nav_msgs", "sensor_msgs").replace("Odometry", "LaserScan"))
        == f"{encoding}.decode_headers"
    )
    assert HEADER_BYTES > 24 + 2 * 255  # a frame_id and a child_frame_id of usual lengths fit the bytes read
