"""Bag files (ROS1 .bag, ROS2 .db3/.mcap bags, MCAP files) turned into transform batches."""

from tftools.sources.bag.contents import BagContents, BagFileInfo, ProgressCallback, RecordWindow
from tftools.sources.bag.reader import BagReader

__all__ = ["BagContents", "BagFileInfo", "BagReader", "ProgressCallback", "RecordWindow"]
