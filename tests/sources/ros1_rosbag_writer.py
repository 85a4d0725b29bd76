"""Writes a ROS1 bag with the real rosbag; run by Debian's /usr/bin/python3, a JSON spec on stdin.

Spec: {"path", "compression", "chunk_threshold", "close", "messages": [[topic, kind, record_ns,
callerid, [[parent, child, stamp_ns, [x, y, z, qx, qy, qz, qw]], ...] or image size]]}.
kind: "tf2" (tf2_msgs/TFMessage), "tf1" (tf/tfMessage), "image" (sensor_msgs/Image), "string",
"clock" (rosgraph_msgs/Clock, its body the clock in ns).
With "close" false the bag is left as a crashed recorder leaves it: flushed, never closed.
"""

import json
import os
import sys
from typing import Any

import genpy
import rosbag
from geometry_msgs.msg import TransformStamped
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Image
from std_msgs.msg import String
from tf.msg import tfMessage
from tf2_msgs.msg import TFMessage

KINDS = {"tf2": TFMessage, "tf1": tfMessage, "image": Image, "string": String, "clock": Clock}


def make(kind: str, body: Any) -> Any:
    if kind == "image":
        return Image(height=1, width=body, encoding="mono8", step=body, data=bytes(body))
    if kind == "string":
        return String(data=body)
    if kind == "clock":
        return Clock(clock=genpy.Time(body // 10**9, body % 10**9))
    transforms = []
    for parent, child, stamp, values in body:
        t = TransformStamped()
        t.header.frame_id = parent
        t.header.stamp = genpy.Time(stamp // 10**9, stamp % 10**9)
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = values[:3]
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = values[3:]
        transforms.append(t)
    return KINDS[kind](transforms=transforms)


def main() -> None:
    spec = json.load(sys.stdin)
    bag = rosbag.Bag(spec["path"], "w", compression=spec["compression"], chunk_threshold=spec["chunk_threshold"])
    seen = set()
    for topic, kind, record_ns, callerid, body in spec["messages"]:
        msg = make(kind, body)
        header = None
        if topic not in seen and callerid:
            cls = KINDS[kind]
            header = {
                "topic": topic,
                "type": cls._type,
                "md5sum": cls._md5sum,
                "message_definition": cls._full_text,
                "callerid": callerid,
            }
            if topic.endswith("tf_static"):
                header["latching"] = "1"
        seen.add(topic)
        bag.write(topic, msg, genpy.Time(record_ns // 10**9, record_ns % 10**9), connection_header=header)
    if spec["close"]:
        bag.close()
    else:
        bag._file.flush()
        os._exit(0)


main()
