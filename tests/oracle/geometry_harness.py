"""tf2_geometry_msgs' doTransform of points, vectors and poses; executed by Debian's /usr/bin/python3.

Reads JSON on stdin: {"transforms": [[tx, ty, tz, qx, qy, qz, qw]], "points": [[x, y, z]],
"orientations": [[x, y, z, w]]} (one row each) and writes {"points", "vectors", "positions",
"orientations"}: each row put through the transform as a PointStamped, a Vector3Stamped and a PoseStamped.
"""

import json
import sys

import tf2_geometry_msgs
from geometry_msgs.msg import PointStamped, PoseStamped, TransformStamped, Vector3Stamped


def main() -> None:
    request = json.load(sys.stdin)
    out: dict[str, list[list[float]]] = {"points": [], "vectors": [], "positions": [], "orientations": []}
    rows = zip(request["transforms"], request["points"], request["orientations"], strict=True)
    for values, (x, y, z), (qx, qy, qz, qw) in rows:
        t = TransformStamped()
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = values[:3]
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = values[3:]
        point = PointStamped()
        point.point.x, point.point.y, point.point.z = x, y, z
        p = tf2_geometry_msgs.do_transform_point(point, t).point
        out["points"].append([p.x, p.y, p.z])
        vector = Vector3Stamped()
        vector.vector.x, vector.vector.y, vector.vector.z = x, y, z
        v = tf2_geometry_msgs.do_transform_vector3(vector, t).vector
        out["vectors"].append([v.x, v.y, v.z])
        pose = PoseStamped()
        pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = x, y, z
        o = pose.pose.orientation
        o.x, o.y, o.z, o.w = qx, qy, qz, qw
        done = tf2_geometry_msgs.do_transform_pose(pose, t).pose
        out["positions"].append([done.position.x, done.position.y, done.position.z])
        q = done.orientation
        out["orientations"].append([q.x, q.y, q.z, q.w])
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
