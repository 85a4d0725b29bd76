"""What a ROS 2 recording lists of each topic's publishers: one offered QoS profile per publisher the recorder
found when it began (metadata.yaml's ``offered_qos_profiles``, or a bare file's own topics table), the one
count of publishers a ROS 2 bag holds, since its messages name none."""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

from tftools.analysis.findings import counted
from tftools.sources.contents import OfferedQos


class Listed(NamedTuple):
    """How many publishers of a topic a ROS 2 recording lists, and where (``OfferedQos.source``: metadata.yaml,
    or a bare file's own)."""

    publishers: int
    source: str

    def said(self, topic: str = "it") -> str:
        """ "metadata.yaml lists 2 publishers of /tf" (or "the .db3's topics table lists ...")."""
        return f"{self.source} lists {counted(self.publishers, 'publisher')} of {topic}"


def listed_publishers(qos: Mapping[str, OfferedQos], topic: str) -> Listed | None:
    """How many publishers of ``topic`` the recording's files list (``Recording.qos``), and where (the most, where
    several files say); None where no file says, or one lists none of a topic it holds messages of (a bag written
    by a converter, rosbags' ``ros_distro: rosbags``: its messages had a publisher, which it did not list)."""
    said = [q for q in qos.values() if topic in q.counts and not (q.counts[topic][1] == 0 < q.counts[topic][0])]
    found = [Listed(q.counts[topic][1], q.source) for q in said]
    return max(found) if found else None
