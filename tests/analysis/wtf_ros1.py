"""The real ROS1 tools on the checker's scenes; executed by Debian's /usr/bin/python3.

``wtf_ros1.py roswtf``: reads {"scenes": [[message, ...], ...]} on stdin and writes, per scene, what
the rules of roswtf's tf plugin (tf/tfwtf.py) report when they see the scene's /tf messages.
``wtf_ros1.py bag OUT``: reads {"messages": [...]} and writes them with the real rosbag to OUT.
A message is [topic, record_ns, publisher, [[parent, child, stamp_ns, tx, ty, tz, qx, qy, qz, qw], ...]].
"""

import json
import sys
from typing import Any

import genpy
import rospy
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

RULES = ("rostime_delta", "reparenting", "cycle_detection", "multiple_authority", "not_normalized")


def tf_message(transforms: Any) -> Any:
    msg = TFMessage()
    for parent, child, stamp, tx, ty, tz, qx, qy, qz, qw in transforms:
        t = TransformStamped()
        t.header.frame_id, t.child_frame_id = parent, child
        t.header.stamp = genpy.Time(*divmod(stamp, 10**9))
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = tx, ty, tz
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = qx, qy, qz, qw
        msg.transforms.append(t)
    return msg


def roswtf(scenes: Any) -> Any:
    import tf.tfwtf as wtf

    results = []
    for messages in scenes:
        # roswtf listens to /tf only; a scene's other moving topics stand for more /tf publishers
        wtf._msgs[:] = [
            (tf_message(ts), rospy.Time(*divmod(record, 10**9)), publisher)
            for topic, record, publisher, ts in messages
            if not topic.endswith("tf_static") and topic.startswith("/tf")
        ]
        result = {name: getattr(wtf, name)(None) for name in RULES}
        result["no_msgs"] = wtf.no_msgs(None)
        results.append(result)
    return results


def write_bag(path: str, messages: Any) -> None:
    import rosbag

    with rosbag.Bag(path, "w") as bag:
        for topic, record, publisher, ts in messages:
            msg = tf_message(ts)
            header = {
                "topic": topic,
                "type": msg._type,
                "md5sum": msg._md5sum,
                "message_definition": msg._full_text,
                "callerid": publisher,
            }
            if topic.endswith("tf_static"):
                header["latching"] = "1"
            bag.write(topic, msg, genpy.Time(*divmod(record, 10**9)), connection_header=header)


if __name__ == "__main__":
    request = json.load(sys.stdin)
    if sys.argv[1] == "roswtf":
        json.dump({"results": roswtf(request["scenes"])}, sys.stdout)
    else:
        write_bag(sys.argv[2], request["messages"])
