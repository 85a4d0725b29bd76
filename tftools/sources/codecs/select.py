"""Which channels carry transforms or the clock, and how each (type, encoding) is decoded."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import TYPE_CHECKING, cast

from tftools.sources.codecs.types import CLOCK, ODOMETRY, TF1_MESSAGE, TF_MESSAGE, has_header, rosidl_name
from tftools.sources.contents import DEFAULT_TOPICS, NOT_SENSOR_DATA, global_name
from tftools.values import value

if TYPE_CHECKING:
    from tftools.sources.codecs.decoded import BulkDecoder, ClockDecoder, HeaderDecoder
    from tftools.sources.codecs.robot import WholeDecoder
    from tftools.sources.contents import MessageSink, Recorded

#: ROS1's names of TFMessage (and of tf's, the same bytes), as ROS1 bags and MCAP files of ROS1 name them.
ROS1_TF_TYPES = ("tf2_msgs/TFMessage", TF1_MESSAGE)
CLOCK_TYPES = (CLOCK, "rosgraph_msgs/Clock")
FRAME_TRANSFORM = "foxglove_msgs/msg/FrameTransform"
FRAME_TRANSFORMS = "foxglove_msgs/msg/FrameTransforms"


@value
class Encoded:
    """A message type in one message encoding."""

    type_name: str
    encoding: str

    @property
    def name(self) -> str:
        return f"{self.type_name} ({self.encoding})"


@functools.cache
def _decoder(where: str) -> object:
    """The decoder named ``where`` ("module.name" in ``tftools.sources.codecs``), its module imported
    on first use: a .bag needs only ``ros1``'s, a .db3 only ``cdr``'s, and json's and protobuf's
    modules are a good part of a first load's imports."""
    module, name = where.rsplit(".", 1)
    # __import__, not importlib.import_module, whose imports -X importtime does not count
    return getattr(__import__(f"tftools.sources.codecs.{module}", fromlist=[name]), name)


@value
class Codec(Encoded):
    """How transform messages of a type and encoding are decoded (``decoder``: "module.name" of the
    decoder in ``tftools.sources.codecs``, imported on first use)."""

    decoder: str
    foxglove: bool  # read on every topic when the default topics are asked for

    @property
    def decode(self) -> BulkDecoder:
        return cast("BulkDecoder", _decoder(self.decoder))


@value
class ClockCodec(Encoded):
    """How clock messages of a type and encoding are decoded (read on every topic)."""

    decoder: str

    @property
    def decode(self) -> ClockDecoder:
        return cast("ClockDecoder", _decoder(self.decoder))


@value
class HeaderCodec(Encoded):
    """How the headers of messages of a type and encoding are decoded (the rest of each is not); ``limit``: of
    each channel, the first that many at most (``Wanted.header_limit``)."""

    decoder: str
    limit: int | None = None

    @property
    def decode(self) -> HeaderDecoder:
        return cast("HeaderDecoder", _decoder(self.decoder))


@value
class Wanted:
    """What a bag reader reads of each channel: transforms on ``topics`` (and, with the default topics,
    foxglove's transform channels), the clock on any topic, and with ``headers`` the header of every
    message on those topics (none named: of every topic whose type starts with a header, but tf's
    and the clock's); None: no headers; and the messages of the ``whole`` topics, whole (a robot's
    description and joint states: ``codecs.robot``). With ``copy``, nothing is decoded: every message
    of every channel is handed to it as recorded (``CopyCodec``)."""

    topics: tuple[str, ...] = DEFAULT_TOPICS
    headers: tuple[str, ...] | None = None
    whole: tuple[str, ...] = ()
    copy: MessageSink | None = None
    #: With ``headers``, the headers read of each channel at most, in the order the file holds them (None: all).
    header_limit: int | None = None

    def wants_header(self, topic: str) -> bool:
        if self.headers is None:
            return False
        return topic in self.headers if self.headers else global_name(topic) not in NOT_SENSOR_DATA


@value
class WholeCodec(Encoded):
    """How whole messages of a type and encoding are decoded into values (a robot's joint states and
    description: ``codecs.robot``)."""

    decode: WholeDecoder


@value
class CopyCodec(Encoded):
    """Messages not decoded: the channel ``recorded`` and each of its messages handed to ``sink`` as
    recorded (a copy)."""

    recorded: Recorded
    sink: MessageSink


def copied(recorded: Recorded, sink: MessageSink) -> CopyCodec:
    return CopyCodec(recorded.type_name, recorded.encoding, recorded, sink)


AnyCodec = Codec | ClockCodec | HeaderCodec | WholeCodec | CopyCodec


CODECS = {
    (c.type_name, c.encoding): c
    for c in [
        # type name, message encoding, bulk decoder (module.name), foxglove
        Codec(TF_MESSAGE, "cdr", "cdr.decode_tf", False),
        Codec(TF_MESSAGE, "json", "json.decode_tf", False),
        *(Codec(ros1_name, "ros1", "ros1.decode_tf", False) for ros1_name in ROS1_TF_TYPES),
        Codec(ROS1_TF_TYPES[0], "json", "json.decode_tf", False),
        Codec(FRAME_TRANSFORMS, "cdr", "cdr.decode_tf", True),
        Codec(FRAME_TRANSFORM, "cdr", "cdr.decode_frame_transform", True),
        Codec("foxglove.FrameTransforms", "protobuf", "protobuf.decode_frame_transforms", True),
        Codec("foxglove.FrameTransform", "protobuf", "protobuf.decode_frame_transform", True),
        Codec("foxglove.FrameTransforms", "json", "json.decode_frame_transforms", True),
        Codec("foxglove.FrameTransform", "json", "json.decode_frame_transform", True),
    ]
}
CLOCK_CODECS = {(t, e): ClockCodec(t, e, f"{e}.decode_clocks") for t in CLOCK_TYPES for e in ("cdr", "ros1", "json")}
_FOXGLOVE_TYPES = {c.type_name for c in CODECS.values() if c.foxglove}
#: The encodings whose headers are read (each module's ``decode_headers``).
_HEADER_ENCODINGS = ("ros1", "cdr")
#: Types whose header's frame_id places nothing in space, so no tf2 filter waits on it: not sensor data
#: unless asked for by topic (the one rule ``tfx filter`` and ``tfx wtf`` count sensor topics by), with what
#: they hold. A gamepad's sensor_msgs/Joy (ROS 2's joy_node stamps it in 'joy'; CyberShip Voyager's
#: /voyager/joy, corpus ros2-cybership-voyager-mocap-basin-2025-db3) is in no tree, rightly. Joint states
#: are positions of joints, which robot_state_publisher turns into tf, whatever frame_id a driver gives them
#: (the Webots e-puck's base_link: filter checked its /joint_states where wtf counted 19 topics of 20).
_UNPLACED = {
    "sensor_msgs/msg/Joy": "a gamepad's axes and buttons",
    "sensor_msgs/msg/JointState": "joint positions, which robot_state_publisher turns into tf",
}


def placed_nowhere(type_name: str) -> str:
    """What messages of ``type_name`` hold where their header's frame_id places nothing in space (a gamepad's
    Joy, joint states), else "": not read as sensor data unless asked for by topic."""
    return _UNPLACED.get(rosidl_name(type_name), "")


def readable() -> str:
    """What tfx reads, for messages about what it does not: "tf2_msgs/msg/TFMessage as cdr or
    json; ...", a type with its plural alike as "foxglove.FrameTransform(s)"."""
    encodings: dict[str, list[str]] = {}
    for type_name, encoding in CODECS:
        encodings.setdefault(type_name, []).append(encoding)
    for plural in [t for t in encodings if t[:-1] in encodings and encodings[t] == encodings[t[:-1]]]:
        encodings[f"{plural[:-1]}(s)"] = encodings.pop(plural)
        del encodings[plural[:-1]]
    return "; ".join(f"{type_name} as {' or '.join(e)}" for type_name, e in encodings.items())


@value
class Unread:
    """A topic asked for (or a foxglove transform channel) of a type or encoding tfx does not read."""

    topic: str
    type_name: str
    encoding: str


def select(
    topic: str, type_name: str, encoding: str, wanted: Wanted, definition: str = ""
) -> tuple[AnyCodec | None, Unread | None]:
    """The codec to read a channel with (None: skip it), and what is not read when a channel asked
    for (or a foxglove transform channel, with the default topics) is skipped. Clocks are read on
    any topic; headers on the topics ``wanted`` says (``definition``: the type's, when the
    recording gives it); the topics it reads ``whole``, only whole (``codecs.robot``'s types)."""
    if topic in wanted.whole:
        from tftools.sources.codecs.robot import WHOLE_DECODERS  # only for a read that takes topics whole

        whole = WHOLE_DECODERS.get((rosidl_name(type_name), encoding))
        return (WholeCodec(rosidl_name(type_name), encoding, whole) if whole is not None else None), None
    clock = CLOCK_CODECS.get((type_name, encoding))
    if clock is not None:
        return clock, None
    topics = wanted.topics
    unread = None
    if topic in topics or global_name(topic) in topics or (topics == DEFAULT_TOPICS and type_name in _FOXGLOVE_TYPES):
        codec = CODECS.get((type_name, encoding))
        if codec is not None:
            return codec, None
        # asked for as transforms, whether or not its headers are read: a LaserScan given as --topic is
        # said to be one, to wtf as to echo
        unread = Unread(topic, type_name, encoding)
    if (
        wanted.wants_header(topic)
        and encoding in _HEADER_ENCODINGS
        and (wanted.headers or not placed_nowhere(type_name))
        and has_header(type_name, encoding, definition)
    ):
        kind = "odometry_headers" if rosidl_name(type_name) == ODOMETRY else "headers"
        headed = HeaderCodec(rosidl_name(type_name), encoding, f"{encoding}.decode_{kind}", wanted.header_limit)
        return headed, unread
    return None, unread


def unread_lines(unread: Sequence[Unread]) -> list[str]:
    """One line per type and encoding not read, naming its topics (and what tfx reads, for
    transform types in an encoding it does not read)."""
    topics: dict[tuple[str, str], list[str]] = {}
    for u in unread:
        named = topics.setdefault((u.type_name, u.encoding), [])
        if u.topic not in named:
            named.append(u.topic)
    return [f"{', '.join(named)}: {_why(type_name, encoding)}" for (type_name, encoding), named in topics.items()]


#: Types that hold one transform but are no tf message: tf2's listeners (RViz's, every node's) subscribe to
#: tf2_msgs/msg/TFMessage, so a topic named tf of these types (the e-Yantra eBot's) is no tf to them either.
_LONE_TRANSFORMS = frozenset({"geometry_msgs/msg/TransformStamped", "geometry_msgs/TransformStamped"})


def carries_transforms(type_name: str) -> bool:
    """Whether tfx reads transforms from messages of ``type_name`` (in some encoding)."""
    return any(type_name == t for t, _ in CODECS)


def _why(type_name: str, encoding: str) -> str:
    if carries_transforms(type_name):
        return f"{type_name} in {encoding or 'no'} encoding, which tfx does not read (it reads {readable()})"
    if type_name in _LONE_TRANSFORMS:
        return (
            f"{type_name} ({encoding or 'no encoding'}) is one transform, not a tf2_msgs TFMessage: no tf2 listener "
            "reads it, nor does tftools; skipped"
        )
    return f"{type_name or 'no type'} ({encoding or 'no encoding'}) is not a transform message tftools reads, skipped"
