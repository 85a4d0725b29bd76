"""What a MessageFilter on the real tf2 would do; executed by Debian's /usr/bin/python3.

Reads JSON on stdin: {"cache_s": float, "target": str, "tf": [[record_ns, parent, child, sec, nsec,
tx, ty, tz, qx, qy, qz, qw, static]], "messages": [[record_ns, frame_id, sec, nsec]]} and writes
{"ready": [record_ns or null per message]}: a BufferCore fed the tf in record order, asked
canTransform(target, frame_id, stamp) at each message's arrival and after each later tf message,
as tf2_ros::MessageFilter asks it (a leading '/' of frame_id stripped, as it strips it); a message
ready at the first yes, never without one.
"""

import json
import sys
from typing import Any

import rospy
import tf2_py
from geometry_msgs.msg import TransformStamped

# The ROS modules have no type information: their messages are Any here, as are the JSON rows (mixed types,
# read by position).


def transform(row: list[Any]) -> Any:
    parent, child, sec, nsec, tx, ty, tz, qx, qy, qz, qw = row[1:12]
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.header.stamp = rospy.Time(sec, nsec)
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = tx, ty, tz
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = qx, qy, qz, qw
    return t


def ready_times(request: dict[str, Any]) -> list[int | None]:
    """When each of ``request["messages"]`` became transformable (record ns), or None: see the module."""
    core = tf2_py.BufferCore(rospy.Duration(request["cache_s"]))
    target = request["target"]
    events = [(row[0], 0, i) for i, row in enumerate(request["tf"])]
    events += [(m[0], 1, i) for i, m in enumerate(request["messages"])]  # tf first when records tie
    ready: list[int | None] = [None] * len(request["messages"])
    pending: list[int] = []

    def can(i: int) -> bool:
        _record, frame, sec, nsec = request["messages"][i]
        frame = frame[1:] if frame.startswith("/") else frame
        ok, _reason = core.can_transform_core(target, frame, rospy.Time(sec, nsec))
        return bool(ok)

    for record, kind, i in sorted(events):
        if kind == 0:
            row = request["tf"][i]
            t = transform(row)
            if row[12]:
                core.set_transform_static(t, "oracle")
            else:
                core.set_transform(t, "oracle")
            still = []
            for m in pending:
                if can(m):
                    ready[m] = record
                else:
                    still.append(m)
            pending = still
        elif can(i):
            ready[i] = record
        else:
            pending.append(i)
    return ready


def main() -> None:
    json.dump({"ready": ready_times(json.load(sys.stdin))}, sys.stdout)


if __name__ == "__main__":
    main()
