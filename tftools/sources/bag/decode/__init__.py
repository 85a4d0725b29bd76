"""Transform and clock messages (CDR, ROS1, protobuf, JSON) decoded in bulk."""

from tftools.sources.bag.decode.codec import Decoder, select

__all__ = ["Decoder", "select"]
