"""``Ros1StaticBroadcaster``: static transforms on ``/tf_static``, latched, as tf2_ros sends them."""

from __future__ import annotations

from tftools.core.transform import Transform
from tftools.sinks.broadcaster import StaticBroadcaster
from tftools.sources.codecs.ros1 import encode_tf_message
from tftools.sources.codecs.types import TF_MESSAGE, ros1_message_type
from tftools.sources.live.notices import OnNotice
from tftools.sources.live.ros1 import network
from tftools.sources.live.ros1.node import Node
from tftools.sources.live.ros1.publisher import Publication

STATIC_TOPIC = "/tf_static"


class Ros1StaticBroadcaster(StaticBroadcaster):
    """A node publishing ``/tf_static`` latched."""

    def __init__(self, master_uri: str | None = None, on_notice: OnNotice | None = None) -> None:
        super().__init__()
        self._node = Node(network.anonymous_name("tfx_static"), master_uri, on_notice)
        self._publication: Publication | None = None

    @property
    def name(self) -> str:
        """The node's name: the authority subscribers see."""
        return self._node.name

    @property
    def finished(self) -> bool:
        return self._node.shutdown_requested.is_set()  # rosnode kill

    def describe(self) -> str:
        return f"ROS1 master {self._node.master.uri}"

    def _publish(self, transforms: list[Transform]) -> None:
        if self._publication is None:
            self._publication = self._node.advertise(STATIC_TOPIC, ros1_message_type(TF_MESSAGE), latched=True)
        self._publication.publish(encode_tf_message(transforms))

    def close(self) -> None:
        self._node.close()
