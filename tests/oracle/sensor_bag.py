"""A robot's tf and sensor data in a ROS1 bag written by the real rosbag, and what the real tf2 makes
of it; executed by Debian's /usr/bin/python3.

    sensor_bag.py write BAG                  the bag (see ``write``)
    sensor_bag.py replay BAG TARGET CACHE_S  {topic: [ready record ns or null, per message]}: the bag
                                             read by rosbag, its /tf and /tf_static fed to a tf2
                                             BufferCore in record order, each stamped message asked
                                             as a MessageFilter asks (filter_harness.ready_times)
"""

import json
import sys
from collections.abc import Callable
from typing import Any

import genpy
import rosbag
from filter_harness import ready_times
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import Image, Imu, LaserScan, PointCloud2
from tf2_msgs.msg import TFMessage

START = 1_700_000_000 * 10**9  # every stamp a whole microsecond: tf2_py's doubles keep their order
MS = 10**6
SECONDS = 30

# The ROS modules have no type information: their messages and times are Any here.


def _time(ns: int) -> Any:
    return genpy.Time(ns // 10**9, ns % 10**9)


def _transform(parent: str, child: str, stamp: int, x: float) -> Any:
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id, t.header.stamp = parent, child, _time(stamp)
    t.transform.translation.x, t.transform.translation.y = x, 0.1
    t.transform.rotation.z, t.transform.rotation.w = 0.0, 1.0
    return t


def _stamped(message: Any, frame: str, stamp: int) -> Any:
    message.header.frame_id, message.header.stamp = frame, _time(stamp)
    return message


def write(path: str) -> None:
    """odom -> base_link at 50 Hz (arriving 2 ms after its stamp), base_link -> laser at 20 Hz (30 ms
    late), map -> odom at 10 Hz, static imu, camera and lidar mounts; a laser scan at 20 Hz that waits
    for its transform, an IMU at 100 Hz that is fine, a camera whose frame_id is misspelt ('camra'),
    and point clouds stamped 12 s before they arrive (older than a 10 s cache holds). Every stream
    runs the whole 30 s, as when rosbag record stops them all at once."""
    rows: list[tuple[int, str, Any]] = []  # (record ns, topic, message)

    def every(hz: int, late: int, make: Callable[[int, int], tuple[str, Any]]) -> None:
        for i in range(SECONDS * hz):
            stamp = START + i * 10**9 // hz
            rows.append((stamp + late, *make(stamp, i)))

    every(50, 2 * MS, lambda s, i: ("/tf", TFMessage([_transform("odom", "base_link", s, i * 0.01)])))
    every(20, 30 * MS, lambda s, i: ("/tf", TFMessage([_transform("base_link", "laser", s, 0.2 + 0.001 * (i % 7))])))
    every(10, 5 * MS, lambda s, i: ("/tf", TFMessage([_transform("map", "odom", s, 1.0 + i * 0.001)])))
    mounts = [_transform("base_link", child, START, x) for child, x in (("imu", 0.05), ("camera", 0.1), ("lidar", 0.3))]
    rows.append((START + MS, "/tf_static", TFMessage(mounts)))
    scan = {"angle_max": 1.0, "ranges": [1.0] * 8}
    every(20, 12 * MS, lambda s, i: ("/scan", _stamped(LaserScan(**scan), "laser", s + 7 * MS)))
    every(100, 25 * MS, lambda s, i: ("/imu", _stamped(Imu(), "imu", s + 3 * MS)))
    pixels = {"height": 2, "width": 2, "encoding": "mono8", "step": 2, "data": b"\0" * 4}
    every(5, 3 * MS, lambda s, i: ("/camera/image_raw", _stamped(Image(**pixels), "camra", s)))
    every(1, 4 * MS, lambda s, i: ("/points", _stamped(PointCloud2(height=1, width=0), "lidar", s - 12 * 10**9)))
    with rosbag.Bag(path, "w") as bag:
        for record, topic, message in sorted(rows, key=lambda r: r[0]):
            bag.write(topic, message, _time(record))


def replay(path: str, target: str, cache_s: float) -> dict[str, list[float | None]]:
    tf: list[list[Any]] = []
    asked: list[list[Any]] = []
    topics: list[str] = []
    with rosbag.Bag(path) as bag:
        for topic, message, record in bag.read_messages():
            record = record.to_nsec()
            if topic in ("/tf", "/tf_static"):
                for t in message.transforms:
                    v, q = t.transform.translation, t.transform.rotation
                    stamp = t.header.stamp
                    tf.append([record, t.header.frame_id, t.child_frame_id, stamp.secs, stamp.nsecs,
                               v.x, v.y, v.z, q.x, q.y, q.z, q.w, topic == "/tf_static"])  # fmt: skip
            elif hasattr(message, "header"):
                stamp = message.header.stamp
                asked.append([record, message.header.frame_id, stamp.secs, stamp.nsecs])
                topics.append(topic)
    ready = ready_times({"cache_s": cache_s, "target": target, "tf": tf, "messages": asked})
    per_topic: dict[str, list[float | None]] = {}
    for topic, when in zip(topics, ready, strict=True):
        per_topic.setdefault(topic, []).append(when)
    return per_topic


if __name__ == "__main__":
    if sys.argv[1] == "write":
        write(sys.argv[2])
    else:
        json.dump(replay(sys.argv[2], sys.argv[3], float(sys.argv[4])), sys.stdout)
