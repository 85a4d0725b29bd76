"""The ROS1 wire format without a master: TFMessage and Clock against rosbags' serializer, headers."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.codecs.decoded import message_clock
from tftools.sources.codecs.ros1 import decode_clocks, decode_tf, encode_tf_message
from tftools.sources.codecs.types import CLOCK, TF_MESSAGE, ros1_message_type
from tftools.sources.live.received import Received, decode_received
from tftools.sources.live.ros1 import tcpros


@pytest.fixture(scope="module")
def store() -> Typestore:
    typestore = get_typestore(Stores.ROS1_NOETIC)
    typestore.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF_MESSAGE))
    return typestore


def _rosbags_message(store: Typestore, transforms: list[Transform], seq: int = 7) -> Any:
    t = store.types
    return t[TF_MESSAGE](
        transforms=[
            t["geometry_msgs/msg/TransformStamped"](
                header=t["std_msgs/msg/Header"](
                    seq=seq,
                    stamp=t["builtin_interfaces/msg/Time"](sec=x.stamp // NS_PER_S, nanosec=x.stamp % NS_PER_S),
                    frame_id=x.frame_id,
                ),
                child_frame_id=x.child_frame_id,
                transform=t["geometry_msgs/msg/Transform"](
                    translation=t["geometry_msgs/msg/Vector3"](*x.translation),
                    rotation=t["geometry_msgs/msg/Quaternion"](*x.rotation),
                ),
            )
            for x in transforms
        ]
    )


frames = st.text(st.characters(codec="utf-8", exclude_categories=["Cs"]), max_size=12)
floats = st.floats(allow_nan=False, width=64)
transforms = st.builds(
    Transform,
    st.tuples(floats, floats, floats),
    st.tuples(floats, floats, floats, floats),
    st.integers(0, 2**31 * NS_PER_S - 1),  # rosbags packs sec as int32
    frames,
    frames,
)


@settings(max_examples=60, deadline=None)
@given(st.lists(transforms, max_size=6))
def test_decoding_matches_rosbags_deserializer(store: Typestore, given_transforms: list[Transform]) -> None:
    data = store.serialize_ros1(_rosbags_message(store, given_transforms), TF_MESSAGE)
    batch = decode_received(decode_tf, [Received("/tf_static", bytes(data), "/pub", 42)]).batch
    assert len(batch) == len(given_transforms)
    names = list(batch.frame_names)
    assert [names[i] for i in batch.parent] == [t.frame_id for t in given_transforms]
    assert [names[i] for i in batch.child] == [t.child_frame_id for t in given_transforms]
    assert batch.stamp.tolist() == [t.stamp for t in given_transforms]
    expected = np.array([(*t.translation, *t.rotation) for t in given_transforms]).reshape(-1, 7)
    np.testing.assert_array_equal(np.concatenate([batch.translation, batch.rotation], axis=1), expected)
    assert batch.static.all() and (batch.record_time == 42).all()
    assert [batch.authorities[a] for a in batch.authority] == ["/pub"] * len(given_transforms)


@settings(max_examples=60, deadline=None)
@given(st.lists(transforms, max_size=6))
def test_encoding_is_byte_for_byte_rosbags_serialization(store: Typestore, given_transforms: list[Transform]) -> None:
    expected = store.serialize_ros1(_rosbags_message(store, given_transforms, seq=0), TF_MESSAGE)
    assert encode_tf_message(given_transforms) == bytes(expected)


def test_a_truncated_message_is_refused(store: Typestore) -> None:
    data = encode_tf_message([Transform((1, 2, 3), (0, 0, 0, 1), 5, "a", "b")])
    for cut in (2, 10, 20, len(data) - 1):
        ((_, reason),) = decode_received(decode_tf, [Received("/tf", data[:cut], "", 0)]).unreadable
        assert re.fullmatch(f"message ends at byte {cut}.*|1 transform cannot fit in {cut} bytes", reason)


def test_clock_decodes_as_rosbags_wrote_it(store: Typestore) -> None:
    now = 1_700_000_123_456_789_012
    t = store.types
    message = t[CLOCK](clock=t["builtin_interfaces/msg/Time"](sec=now // NS_PER_S, nanosec=now % NS_PER_S))
    assert message_clock(decode_clocks, bytes(store.serialize_ros1(message, CLOCK))) == now


def test_md5sums_are_noetics() -> None:
    # The md5sums genmsg computes for Noetic's messages (rosmsg md5 tf2_msgs/TFMessage).
    assert ros1_message_type(TF_MESSAGE).md5sum == "94810edda583a504dfda3829e70d7eec"
    assert ros1_message_type(CLOCK).md5sum == "a9c97c1d230cfc112e270351a944ee47"
    assert ros1_message_type(TF_MESSAGE).name == "tf2_msgs/TFMessage"


def test_connection_header_round_trip() -> None:
    fields = {"callerid": "/tfx_1", "topic": "/tf", "message_definition": "a=b\nc", "latching": "1"}
    data = tcpros.encode_header(fields)
    assert int.from_bytes(data[:4], "little") == len(data) - 4
    assert tcpros.decode_header(data[4:]) == fields
    with pytest.raises(tcpros.ProtocolError):
        tcpros.decode_header(data[4:-3])
