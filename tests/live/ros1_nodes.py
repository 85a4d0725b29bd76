"""ROS1 nodes for the live tests, run by Debian's /usr/bin/python3 with rospy (never imported by pytest).

ros1_nodes.py dynamic NODE PARENT CHILD X [HZ]   TransformBroadcaster: translation (X, stamp - 1.7e9 s, 0), yaw 0.3
ros1_nodes.py wrong_type NODE TOPIC             a std_msgs/String publisher on TOPIC (another md5sum)
ros1_nodes.py scan NODE TOPIC FRAME [HZ]        a sensor_msgs/LaserScan publisher on TOPIC, stamped now, in FRAME
ros1_nodes.py static_listener                   prints the first /tf_static message as JSON, with its header
ros1_nodes.py write_bag PATH PARENT CHILD [S]   S (10) s of /tf at 20 Hz from t = 1000 s, x = t - 1000, real rosbag
ros1_nodes.py clock_and_tf NODE                 what stdin says: "clock T" on /clock, "tf PARENT CHILD T" on /tf
"""

import json
import math
import sys


def dynamic(node: str, parent: str, child: str, x: str, hz: str = "20") -> None:
    import rospy
    import tf2_ros
    from geometry_msgs.msg import TransformStamped

    rospy.init_node(node.lstrip("/"), anonymous=False, disable_signals=True)
    broadcaster = tf2_ros.TransformBroadcaster()
    rate = rospy.Rate(float(hz))
    print("ready", flush=True)
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        t = TransformStamped()
        t.header.stamp = now
        t.header.frame_id = parent
        t.child_frame_id = child
        t.transform.translation.x = float(x)
        t.transform.translation.y = now.to_sec() - 1.7e9  # steady, never wrapping: a wrap is a true jump
        t.transform.rotation.z = math.sin(0.15)
        t.transform.rotation.w = math.cos(0.15)
        broadcaster.sendTransform(t)
        rate.sleep()


def wrong_type(node: str, topic: str) -> None:
    import rospy
    from std_msgs.msg import String

    rospy.init_node(node.lstrip("/"), anonymous=False, disable_signals=True)
    publisher = rospy.Publisher(topic, String, queue_size=1)
    print("ready", flush=True)
    while not rospy.is_shutdown():
        publisher.publish(String("not a transform"))
        rospy.sleep(0.05)


def scan(node: str, topic: str, frame: str, hz: str = "10") -> None:
    import rospy
    from sensor_msgs.msg import LaserScan

    rospy.init_node(node.lstrip("/"), anonymous=False, disable_signals=True)
    publisher = rospy.Publisher(topic, LaserScan, queue_size=10)
    rate = rospy.Rate(float(hz))
    print("ready", flush=True)
    while not rospy.is_shutdown():
        message = LaserScan(angle_min=-1.0, angle_max=1.0, angle_increment=0.5, range_max=10.0)
        message.header.stamp = rospy.Time.now()
        message.header.frame_id = frame
        message.ranges = [1.0, 2.0, 3.0, 4.0, 5.0]
        publisher.publish(message)
        rate.sleep()


def static_listener() -> None:
    import rospy
    from tf2_msgs.msg import TFMessage

    rospy.init_node("static_listener", anonymous=True, disable_signals=True)
    message = rospy.wait_for_message("/tf_static", TFMessage, timeout=20)
    header = message._connection_header
    print(
        json.dumps(
            {
                "callerid": header["callerid"],
                "latching": header.get("latching"),
                "transforms": [
                    {
                        "frame_id": t.header.frame_id,
                        "child_frame_id": t.child_frame_id,
                        "stamp": t.header.stamp.to_nsec(),
                        "translation": [getattr(t.transform.translation, k) for k in "xyz"],
                        "rotation": [getattr(t.transform.rotation, k) for k in "xyzw"],
                    }
                    for t in message.transforms
                ],
            }
        ),
        flush=True,
    )


def write_bag(path: str, parent: str, child: str, seconds: str = "10") -> None:
    import genpy
    import rosbag
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage

    with rosbag.Bag(path, "w") as bag:
        for i in range(round(float(seconds) * 20)):
            stamp = genpy.Time(1000) + genpy.Duration.from_sec(i * 0.05)
            t = TransformStamped()
            t.header.stamp = stamp
            t.header.frame_id = parent
            t.child_frame_id = child
            t.transform.translation.x = i * 0.05
            t.transform.rotation.w = 1.0
            bag.write("/tf", TFMessage([t]), stamp)


def clock_and_tf(node: str) -> None:
    """tf2_ros's time_reset_test's publisher: /clock and /tf as stdin says, "ok" on stdout after each line."""
    import rospy
    import tf2_ros
    from geometry_msgs.msg import TransformStamped
    from rosgraph_msgs.msg import Clock

    rospy.init_node(node.lstrip("/"), anonymous=False, disable_signals=True)
    clock = rospy.Publisher("/clock", Clock, queue_size=10)
    broadcaster = tf2_ros.TransformBroadcaster()
    print("ready", flush=True)
    for line in sys.stdin:
        words = line.split()
        if words[0] == "clock":
            clock.publish(Clock(rospy.Time.from_sec(float(words[1]))))
        else:
            t = TransformStamped()
            t.header.stamp = rospy.Time.from_sec(float(words[3]))
            t.header.frame_id, t.child_frame_id = words[1], words[2]
            t.transform.rotation.x = 1.0
            broadcaster.sendTransform(t)
        print("ok", flush=True)


if __name__ == "__main__":
    globals()[sys.argv[1]](*sys.argv[2:])
