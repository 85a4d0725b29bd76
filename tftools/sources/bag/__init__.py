"""Bag files (ROS1 .bag, ROS2 .db3/.mcap bags, MCAP files) turned into transform batches."""

from tftools.sources.bag.contents import BagContents, BagFileInfo, ProgressCallback
from tftools.sources.bag.reader import read_bag
from tftools.sources.contents import DEFAULT_TOPICS, ClockSamples, is_static_topic

__all__ = [
    "DEFAULT_TOPICS",
    "BagContents",
    "BagFileInfo",
    "ClockSamples",
    "ProgressCallback",
    "is_static_topic",
    "read_bag",
]
