"""Live ROS1 in pure Python: XML-RPC with the master, TCPROS with the other nodes."""

from tftools.sources.live.ros1.node import Node
from tftools.sources.live.ros1.source import Ros1Source

__all__ = ["Node", "Ros1Source"]
