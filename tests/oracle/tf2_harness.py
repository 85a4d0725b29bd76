"""Runs scenarios through the real tf2 BufferCore; executed by Debian's /usr/bin/python3.

Reads JSON on stdin: {"scenarios": [{"cache_time_s": int, "inserts": [...] | "bag": path,
"queries": [...]}]} and writes {"results": [{"rejections": [codes], "answers": [...]}]};
or {"bag_rows": path} and writes {"rows": [insert, ...]}: the bag's transforms as rosbag reads them.
An insert is [parent, child, sec, nsec, tx, ty, tz, qx, qy, qz, qw, authority, static].
A query is ["lookup", target, source, sec, nsec], ["lookup_full", target, sec, nsec, source,
sec, nsec, fixed], ["can", target, source, sec, nsec], ["can_full", target, sec, nsec, source, sec, nsec,
fixed], ["chain", target, sec, nsec, source, sec, nsec, fixed], ["lct", target, source], ["frames"] or ["yaml"].
"""

import json
import os
import re
import sys
import tempfile
from collections.abc import Callable, Iterator
from typing import Any

import rospy
import tf2_py
from geometry_msgs.msg import TransformStamped

_CODE = re.compile(r"TF_[A-Z_]+")

# The ROS modules have no type information: their messages and tf2's BufferCore are Any here, as are the
# JSON rows and queries (mixed types, read by position).


def message(row: list[Any]) -> Any:
    parent, child, sec, nsec, tx, ty, tz, qx, qy, qz, qw = row[:11]
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.header.stamp = rospy.Time(sec, nsec)
    tr, rot = t.transform.translation, t.transform.rotation
    tr.x, tr.y, tr.z = tx, ty, tz
    rot.x, rot.y, rot.z, rot.w = qx, qy, qz, qw
    return t


def insert(core: Any, transform: Any, authority: str, static: bool) -> None:
    if static:
        core.set_transform_static(transform, authority)
    else:
        core.set_transform(transform, authority)


def feed_rows(core: Any, rows: list[list[Any]]) -> None:
    for row in rows:
        insert(core, message(row), row[11], row[12])


def bag_transforms(path: str) -> Iterator[tuple[Any, str, bool]]:
    """Each transform of a ROS1 bag's /tf and /tf_static in order, with its publisher and whether static. A bag
    recorded as 'rosbag record tf' holds the relative name: rosbag play advertises it in the root namespace, as
    /tf (Brandon-Yee/open-hand-capacitive-sense's test1.bag)."""
    import rosbag

    topics = ["/tf", "/tf_static", "tf", "tf_static"]
    with rosbag.Bag(path) as bag:
        for topic, msg, _t, header in bag.read_messages(topics=topics, return_connection_header=True):
            authority = header.get("callerid", topic)
            if isinstance(authority, bytes):  # rosbag gives connection header values as bytes
                authority = authority.decode()
            for transform in msg.transforms:
                yield transform, authority, topic.lstrip("/") == "tf_static"


def feed_bag(core: Any, path: str) -> None:
    for transform, authority, static in bag_transforms(path):
        insert(core, transform, authority, static)


def row(transform: Any, authority: str, static: bool) -> list[Any]:
    """An insert row of ``transform``: its stamp as the message's integers, every nanosecond."""
    tr, rot = transform.transform.translation, transform.transform.rotation
    stamp = transform.header.stamp
    frames = [transform.header.frame_id, transform.child_frame_id]
    return [*frames, stamp.secs, stamp.nsecs, tr.x, tr.y, tr.z, rot.x, rot.y, rot.z, rot.w, authority, static]


def capture_stderr(action: Callable[[], None]) -> list[str]:
    """Run ``action`` and return the tf2 codes it logged on file descriptor 2."""
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as log:
        os.dup2(log.fileno(), 2)
        try:
            action()
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        log.seek(0)
        return _CODE.findall(log.read().decode("utf-8", "replace"))


def stamped(t: Any) -> dict[str, Any]:
    tr, rot = t.transform.translation, t.transform.rotation
    return {
        "ok": True,
        "t": [tr.x, tr.y, tr.z],
        "q": [rot.x, rot.y, rot.z, rot.w],
        "stamp": [t.header.stamp.secs, t.header.stamp.nsecs],
        "frame_id": t.header.frame_id,
        "child_frame_id": t.child_frame_id,
    }


def answer(core: Any, query: list[Any]) -> dict[str, Any]:
    kind, args = query[0], query[1:]
    try:
        if kind == "lookup":
            target, source, sec, nsec = args
            return stamped(core.lookup_transform_core(target, source, rospy.Time(sec, nsec)))
        if kind == "lookup_full":
            target, tsec, tnsec, source, ssec, snsec, fixed = args
            return stamped(
                core.lookup_transform_full_core(target, rospy.Time(tsec, tnsec), source, rospy.Time(ssec, snsec), fixed)
            )
        if kind == "can":
            target, source, sec, nsec = args
            ok, _reason = core.can_transform_core(target, source, rospy.Time(sec, nsec))
            return {"ok": True, "can": bool(ok)}
        if kind == "can_full":
            target, tsec, tnsec, source, ssec, snsec, fixed = args
            ok, _reason = core.can_transform_full_core(
                target, rospy.Time(tsec, tnsec), source, rospy.Time(ssec, snsec), fixed
            )
            return {"ok": True, "can": bool(ok)}
        if kind == "chain":
            target, tsec, tnsec, source, ssec, snsec, fixed = args
            chain = core._chain(target, rospy.Time(tsec, tnsec), source, rospy.Time(ssec, snsec), fixed)
            return {"ok": True, "chain": chain}
        if kind == "lct":
            t = core.get_latest_common_time(*args)
            return {"ok": True, "stamp": [t.secs, t.nsecs]}
        if kind == "frames":
            return {"ok": True, "text": core.all_frames_as_string()}
        if kind == "yaml":
            return {"ok": True, "text": core.all_frames_as_yaml()}
    except Exception as e:
        return {"ok": False, "error": type(e).__name__, "message": str(e)}
    raise ValueError(f"unknown query {kind}")


def run(scenario: dict[str, Any]) -> dict[str, Any]:
    core = tf2_py.BufferCore(rospy.Duration(scenario.get("cache_time_s", 10)))
    if "bag" in scenario:
        codes = capture_stderr(lambda: feed_bag(core, scenario["bag"]))
    else:
        codes = capture_stderr(lambda: feed_rows(core, scenario["inserts"]))
    return {"rejections": codes, "answers": [answer(core, q) for q in scenario["queries"]]}


def main() -> None:
    request = json.load(sys.stdin)
    if "bag_rows" in request:
        json.dump({"rows": [row(*t) for t in bag_transforms(request["bag_rows"])]}, sys.stdout)
        return
    json.dump({"results": [run(s) for s in request["scenarios"]]}, sys.stdout)


if __name__ == "__main__":
    main()
