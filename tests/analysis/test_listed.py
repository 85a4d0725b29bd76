"""What a ROS 2 recording lists of a topic's publishers (``listed_publishers``): none listed for a topic whose
messages it holds is no count (ros4hri's test bag converted by rosbags, ``ros_distro: rosbags``, lists no QoS
profile for /tf: "metadata.yaml lists 0 publishers of /tf" was said beside 1,553 transforms)."""

from __future__ import annotations

from tftools.analysis.listed import Listed, listed_publishers
from tftools.sources.contents import IN_METADATA, OfferedQos


def test_a_topic_with_messages_and_no_listed_publisher_has_no_count() -> None:
    qos = {"bag": OfferedQos({}, counts={"/tf": (2432, 0), "/idle": (0, 0), "/odom": (98, 2)})}
    assert listed_publishers(qos, "/tf") is None
    assert listed_publishers(qos, "/idle") == Listed(0, IN_METADATA)
    assert listed_publishers(qos, "/odom") == Listed(2, IN_METADATA)
    assert listed_publishers(qos, "/absent") is None
