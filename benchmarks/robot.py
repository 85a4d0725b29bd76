"""The benchmark robot: sample_bags' mobile manipulator, 860 transforms/s, as serialized tf messages.

Standard library only, so that Debian's interpreter (the real rosbag) and ours import the same
stream. 17 edges over 18 frames::

    map -> odom                      /amcl                        10 Hz
    odom -> base_footprint           /ekf_localization            50 Hz
    base_link -> left_wheel, right_wheel                          /robot_state_publisher       100 Hz
    arm_base -> arm_link1 -> ... -> arm_link6                     /arm/robot_state_publisher   100 Hz
    base_footprint -> base_link, base_link -> laser, imu_link, camera_link, arm_base,
    camera_link -> camera_optical_frame, arm_link6 -> gripper     static, one /tf_static message

300 s make 258,007 transforms. Stamps jitter by up to 0.3 ms, each message is recorded 1-5 ms
after its stamp, and every rotation moves, so lookups interpolate with slerp. With ``images``,
a 640x480 mono camera at 10 Hz makes the bulk of the bag (3 GB an hour).
"""

from __future__ import annotations

import heapq
import math
import struct
from collections.abc import Iterator

NS = 1_000_000_000
START = 1_700_000_000 * NS
ARM = [f"arm_link{i}" for i in range(1, 7)]
#: (callerid, Hz, (parent, child) pairs), each edge turning about one axis.
PUBLISHERS = [
    ("/amcl", 10, [("map", "odom")]),
    ("/ekf_localization", 50, [("odom", "base_footprint")]),
    ("/robot_state_publisher", 100, [("base_link", "left_wheel"), ("base_link", "right_wheel")]),
    ("/arm/robot_state_publisher", 100, list(zip(["arm_base", *ARM[:-1]], ARM, strict=True))),
]
STATIC = [("base_footprint", "base_link"), ("base_link", "laser"), ("base_link", "imu_link"),
          ("base_link", "camera_link"), ("camera_link", "camera_optical_frame"), ("base_link", "arm_base"),
          ("arm_link6", "gripper")]  # fmt: skip
#: The 10-edge chain the lookup benchmarks use: 8 moving edges and 2 static ones.
TARGET, SOURCE = "map", "arm_link6"

IMAGE_TOPIC, IMAGE_HZ, IMAGE_SIZE = "/camera/image_raw", 10, (480, 640)

#: (record time ns, topic, callerid, [(parent, child, stamp ns, tx ty tz qx qy qz qw)]), or for
#: IMAGE_TOPIC (record time, topic, callerid, stamp).
Message = tuple[int, str, str, object]


def transforms_per_second() -> int:
    return sum(hz * len(pairs) for _, hz, pairs in PUBLISHERS)


def messages(seconds: int, images: bool = False) -> Iterator[Message]:
    """The robot's tf messages (and camera images) over ``seconds``, in record order."""
    static = [(p, c, START, (0.1 * i, 0.0, 0.2, *_axis_quat(i % 3, 0.1 * i))) for i, (p, c) in enumerate(STATIC)]
    first: Message = (START + 1_000_000, "/tf_static", "/robot_state_publisher", static)
    streams = [_periodic(seconds, *publisher) for publisher in PUBLISHERS]
    if images:
        period = NS // IMAGE_HZ
        stamps = range(START + period // 2, START + seconds * NS, period)
        streams.append((stamp + 20_000_000, IMAGE_TOPIC, "/camera", stamp) for stamp in stamps)
    return heapq.merge(iter([first]), *streams, key=lambda m: m[0])


def dynamic_transforms(seconds: int, count: int) -> list[tuple[str, str, int, tuple[float, ...], str]]:
    """The first ``count`` moving transforms of ``messages``, in record order, as one
    ``set_transform`` call each takes them: (parent, child, stamp, tx ty tz qx qy qz qw, callerid)."""
    out = []
    for _record, topic, callerid, content in messages(seconds):
        if topic == "/tf":
            rows: list = content  # type: ignore[assignment]
            out += [(parent, child, stamp, values, callerid) for parent, child, stamp, values in rows]
            if len(out) >= count:
                return out[:count]
    return out


def _periodic(seconds: int, callerid: str, hz: int, pairs: list[tuple[str, str]]) -> Iterator[Message]:
    period = NS // hz
    for k in range(seconds * hz):
        stamp = START + period // 3 + k * period + (k * 7919) % 600_000 - 300_000
        record = stamp + 1_000_000 + (k * 104_729) % 4_000_000
        s = (stamp - START) / NS
        rows = []
        for i, (parent, child) in enumerate(pairs):
            angle = 0.6 * math.sin(0.5 * s + i + hz)
            rows.append((parent, child, stamp, (0.1 * i + 0.01 * s, 0.02 * i, 0.05, *_axis_quat(i % 3, angle))))
        yield record, "/tf", callerid, rows


def _axis_quat(axis: int, angle: float) -> tuple[float, float, float, float]:
    q = [0.0, 0.0, 0.0, math.cos(angle / 2)]
    q[axis] = math.sin(angle / 2)
    return q[0], q[1], q[2], q[3]


# --- serialization ------------------------------------------------------------------------------


def ros1_payload(topic: str, content: object) -> bytes:
    """A ROS1 tf2_msgs/TFMessage, or a sensor_msgs/Image on IMAGE_TOPIC."""
    if topic == IMAGE_TOPIC:
        sec, nsec = divmod(content, NS)  # type: ignore[call-overload]
        height, width = IMAGE_SIZE
        frame, encoding = b"camera_optical_frame", b"mono8"
        head = struct.pack("<IIII", 0, sec, nsec, len(frame)) + frame
        head += struct.pack("<III", height, width, len(encoding)) + encoding
        return head + struct.pack("<BII", 0, width, height * width) + bytes(height * width)
    rows: list = content  # type: ignore[assignment]
    parts = [struct.pack("<I", len(rows))]
    for parent, child, stamp, values in rows:
        sec, nsec = divmod(stamp, NS)
        parts.append(struct.pack("<III", 0, sec, nsec))
        for name in (parent, child):
            parts.append(struct.pack("<I", len(name)) + name.encode())
        parts.append(struct.pack("<7d", *values))
    return b"".join(parts)


def cdr_payload(topic: str, content: object) -> bytes:
    """A ROS2 tf2_msgs/msg/TFMessage (or sensor_msgs/msg/Image) in little-endian CDR, alignment
    counted after the 4-byte encapsulation header."""
    if topic == IMAGE_TOPIC:
        sec, nsec = divmod(content, NS)  # type: ignore[call-overload]
        height, width = IMAGE_SIZE
        image = bytearray(struct.pack("<iII", sec, nsec, 21) + b"camera_optical_frame\0")
        _align(image, 4)
        image += struct.pack("<III", height, width, 6) + b"mono8\0" + b"\0"  # encoding, is_bigendian
        _align(image, 4)
        image += struct.pack("<II", width, height * width) + bytes(height * width)
        return b"\x00\x01\x00\x00" + bytes(image)
    rows: list = content  # type: ignore[assignment]
    body = bytearray(struct.pack("<I", len(rows)))
    for parent, child, stamp, values in rows:
        sec, nsec = divmod(stamp, NS)
        _align(body, 4)
        body += struct.pack("<iI", sec, nsec)
        for name in (parent, child):
            _align(body, 4)
            body += struct.pack("<I", len(name) + 1) + name.encode() + b"\0"
        _align(body, 8)
        body += struct.pack("<7d", *values)
    return b"\x00\x01\x00\x00" + bytes(body)


def _align(body: bytearray, size: int) -> None:
    body += b"\0" * (-len(body) % size)
