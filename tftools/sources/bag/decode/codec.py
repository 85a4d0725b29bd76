"""Which channels carry transforms, and how each (type, encoding) is decoded."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from tftools.sources.bag.contents import DEFAULT_TOPICS
from tftools.sources.bag.decode import cdr, foxglove_json, foxglove_protobuf, ros1
from tftools.sources.bag.decode.reference import (
    FRAME_TRANSFORM,
    FRAME_TRANSFORMS,
    ROS1_TF_MESSAGES,
    TF_MESSAGE,
    reference_frame_transform,
    reference_frame_transforms,
    reference_ros1_tf_message,
    reference_tf_message,
)
from tftools.sources.bag.decode.template import Parser

#: "fast": templates with numpy, "simple": every message parsed in Python, "reference": rosbags
#: deserializes CDR and ROS1 messages (other encodings as "simple").
Decoder = Literal["fast", "simple", "reference"]


@dataclass(frozen=True)
class Codec:
    type_name: str
    encoding: str
    parse: Parser
    reference: Parser
    templated: bool  # messages have fixed layouts that templates can learn
    foxglove: bool  # read on every topic when the default topics are asked for

    @property
    def name(self) -> str:
        return f"{self.type_name} ({self.encoding})"

    def parser(self, decoder: Decoder) -> Parser:
        return self.reference if decoder == "reference" else self.parse


def _codecs() -> dict[tuple[str, str], Codec]:
    pb, js = foxglove_protobuf, foxglove_json
    tf2, tf1 = ROS1_TF_MESSAGES
    table = [
        # type name, message encoding, parser, reference parser, templated, foxglove
        Codec(TF_MESSAGE, "cdr", cdr.parse_tf_message, reference_tf_message, True, False),
        Codec(tf2, "ros1", ros1.parse_tf_message, reference_ros1_tf_message, True, False),
        Codec(tf1, "ros1", ros1.parse_tf_message, reference_ros1_tf_message, True, False),
        Codec(FRAME_TRANSFORMS, "cdr", cdr.parse_tf_message, reference_frame_transforms, True, True),
        Codec(FRAME_TRANSFORM, "cdr", cdr.parse_frame_transform, reference_frame_transform, True, True),
        Codec("foxglove.FrameTransforms", "protobuf", pb.parse_frame_transforms, pb.parse_frame_transforms, True, True),
        Codec("foxglove.FrameTransform", "protobuf", pb.parse_frame_transform, pb.parse_frame_transform, True, True),
        Codec("foxglove.FrameTransforms", "json", js.parse_frame_transforms, js.parse_frame_transforms, False, True),
        Codec("foxglove.FrameTransform", "json", js.parse_frame_transform, js.parse_frame_transform, False, True),
    ]
    return {(c.type_name, c.encoding): c for c in table}


CODECS = _codecs()


def select(topic: str, type_name: str, encoding: str, topics: tuple[str, ...]) -> tuple[Codec | None, str]:
    """The codec to read a channel with (None: skip it), and a problem line when it is skipped
    although asked for."""
    codec = CODECS.get((type_name, encoding))
    if topic in topics:
        if codec is None:
            kind = f"{type_name or 'no type'} ({encoding or 'no encoding'})"
            return None, f"{topic}: {kind} is not a transform message tftools reads, skipped"
        return codec, ""
    if codec is not None and codec.foxglove and topics == DEFAULT_TOPICS:
        return codec, ""
    return None, ""
