"""tf2's side of the benchmark, run by Debian's /usr/bin/python3 (the real rosbag and tf2_py).

``write BAG SECONDS [images]``: the robot's ROS1 bag through the real rosbag writer.
``measure BAG LOOKUPS SECONDS``: rosbag + BufferCore ingest, then lookups and can_transform through
the binding in a Python loop, and ``set_transform`` one call per transform into a new BufferCore;
prints one JSON object.
``script BAG``: what a user's whole script does (the bag read into a BufferCore, one lookup), the
imports included: its parent times the whole process (``ratios.py``).
"""

import json
import resource
import sys
import time
import warnings

import robot
import rosbag
import rospy
import tf2_py
from geometry_msgs.msg import TransformStamped
from spent import spent_since, usage
from tf2_msgs.msg import TFMessage

SET_CALLS = 100_000


def write(path, seconds, images):
    from sensor_msgs.msg import Image

    with rosbag.Bag(path, "w") as bag:
        for record, topic, callerid, content in robot.messages(seconds, images):
            kind = Image if topic == robot.IMAGE_TOPIC else TFMessage
            header = {
                "type": kind._type,
                "md5sum": kind._md5sum,
                "message_definition": kind._full_text,
                "callerid": callerid,
                "latching": "1" if topic == "/tf_static" else "0",
            }
            msg = (kind._type, robot.ros1_payload(topic, content), kind._md5sum, None, kind)
            bag.write(topic, msg, rospy.Time(*divmod(record, robot.NS)), raw=True, connection_header=header)


def ingest(path):
    warnings.simplefilter("ignore")  # rosbag's message classes are not geometry_msgs' own: tf2_py warns once
    core = tf2_py.BufferCore(rospy.Duration(1_000_000))
    count = 0
    with rosbag.Bag(path) as bag:
        for topic, msg, _t, header in bag.read_messages(topics=["/tf", "/tf_static"], return_connection_header=True):
            authority = header.get("callerid", topic)
            if isinstance(authority, bytes):
                authority = authority.decode()
            static = topic == "/tf_static"
            for transform in msg.transforms:
                if static:
                    core.set_transform_static(transform, authority)
                else:
                    core.set_transform(transform, authority)
                count += 1
    return core, count


def per_call(action, items):
    """Seconds a call, wall and CPU (the CPU time tells a slow call from one another process held off the CPU)."""
    cpu, began = time.process_time(), time.perf_counter()
    for item in items:
        action(item)
    return (time.perf_counter() - began) / len(items), (time.process_time() - cpu) / len(items)


def set_transform_per_call(seconds):
    """One ``set_transform`` call's time, wall and CPU, on the robot's first moving transforms built beforehand."""
    messages = []
    for parent, child, stamp, values, callerid in robot.dynamic_transforms(seconds, SET_CALLS):
        msg = TransformStamped()
        msg.header.frame_id, msg.child_frame_id = parent, child
        msg.header.stamp = rospy.Time(*divmod(stamp, robot.NS))
        t, r = msg.transform.translation, msg.transform.rotation
        t.x, t.y, t.z, r.x, r.y, r.z, r.w = values
        messages.append((msg, callerid))
    core = tf2_py.BufferCore(rospy.Duration(1_000_000))
    return per_call(lambda m: core.set_transform(*m), messages)


def measure(path, lookups, seconds):
    spent, began = usage(), time.perf_counter()
    core, count = ingest(path)
    ingest_s = time.perf_counter() - began
    spent = spent_since(spent, "ingest")
    # Times spread over the recording, inside every edge's history, as rospy.Time built beforehand.
    first, span = robot.START + robot.NS, (seconds - 2) * robot.NS
    times = [rospy.Time(*divmod(first + (k * 7_919_000_017) % span, robot.NS)) for k in range(lookups)]
    target, source = robot.TARGET, robot.SOURCE
    lookup_s, lookup_cpu_s = per_call(lambda t: core.lookup_transform_core(target, source, t), times)
    can_s, can_cpu_s = per_call(lambda t: core.can_transform_core(target, source, t), times)
    set_s, set_cpu_s = set_transform_per_call(seconds)
    first = [core.lookup_transform_core(target, source, t).transform.translation for t in times[:1000]]
    print(
        json.dumps(
            {
                "checksum": sum(v.x + v.y + v.z for v in first),
                "transforms": count,
                "ingest_s": ingest_s,
                **spent,
                "lookup_s": lookup_s,
                "lookup_cpu_s": lookup_cpu_s,
                "can_transform_s": can_s,
                "can_transform_cpu_s": can_cpu_s,
                "set_transform_s": set_s,
                "set_transform_cpu_s": set_cpu_s,
                "peak_rss_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
            }
        )
    )


def script(path):
    core, _count = ingest(path)
    at = rospy.Time(*divmod(robot.START + 100 * robot.NS, robot.NS))
    print(json.dumps({"x": core.lookup_transform_core(robot.TARGET, robot.SOURCE, at).transform.translation.x}))


def main():
    command, path = sys.argv[1], sys.argv[2]
    if command == "script":
        script(path)
    elif command == "write":
        write(path, int(sys.argv[3]), sys.argv[4:] == ["images"])
    else:
        measure(path, int(sys.argv[3]), int(sys.argv[4]))


if __name__ == "__main__":
    main()
