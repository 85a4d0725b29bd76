"""Transform messages of ROS2 bags and MCAP files (CDR, ROS1, protobuf, JSON) decoded in bulk into batches."""

from tftools.sources.bag.decode.codec import Decoder, select
from tftools.sources.bag.decode.messages import MessageSet, Unpack
from tftools.sources.bag.decode.scan import FileScan, file_result

__all__ = ["Decoder", "FileScan", "MessageSet", "Unpack", "file_result", "select"]
