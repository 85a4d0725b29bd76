"""Transform and clock messages of ROS2 bags and MCAP files gathered, and decoded by the codecs into batches."""

from tftools.sources.bag.decode.messages import MessageSet, Unpack
from tftools.sources.bag.decode.scan import FileScan, file_result

__all__ = ["FileScan", "MessageSet", "Unpack", "file_result"]
