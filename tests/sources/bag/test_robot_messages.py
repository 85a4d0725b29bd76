"""The robot's own messages as the bag readers read them whole: joint states and /robot_description,
thinned evenly per kind when there are hours of them."""

from __future__ import annotations

import numpy as np
import pytest

from tests.analysis.robot_scenes import Recorded, _message
from tests.bags import _typestore
from tftools.sources.bag import messages as message_set
from tftools.sources.codecs.robot import WHOLE_DECODERS, JointState
from tftools.sources.codecs.select import WholeCodec


def _payload(stamp: int, names: list[str]) -> bytes:
    store = _typestore("ros1")
    value = _message(store, Recorded("/joint_states", stamp, (stamp, names, [0.5] * len(names))))
    return bytes(store.serialize_ros1(value, "sensor_msgs/msg/JointState"))


def test_hours_of_joint_states_are_thinned_evenly_per_kind(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(message_set, "MAX_WHOLE", 50)
    key = ("sensor_msgs/msg/JointState", "ros1")
    messages = message_set.MessageSet()
    channel = messages.channel("/joint_states", WholeCodec(*key, WHOLE_DECODERS[key]))
    # an arm at 10x a gripper's rate, each its own kind of message
    kinds = [["gripper"] if i % 10 == 0 else ["arm_1", "arm_2"] for i in range(2000)]
    for start in range(0, 2000, 100):  # as a reader adds them, chunk by chunk
        part = range(start, start + 100)
        messages.add(channel, list(part), list(part), [_payload(i, kinds[i]) for i in part])
    messages.decode()
    (whole,) = messages.whole
    states = [s for s in whole.values if isinstance(s, JointState)]
    arm = [s.stamp for s in states if s.key == ("arm_1", "arm_2")]
    gripper = [s.stamp for s in states if s.key == ("gripper",)]
    assert 25 < len(arm) <= 50 and 25 < len(gripper) <= 50  # both kinds kept, at most MAX_WHOLE each
    assert arm[0] < 20 and arm[-1] > 1900 and gripper[0] == 0 and gripper[-1] > 1900  # over the whole span
    assert len(set(np.diff(arm).tolist())) <= 3  # evenly spread
    assert list(whole.record_time) == sorted(whole.record_time)


@pytest.mark.parametrize("encoding", ["ros1", "cdr"])
def test_names_read_once_per_kind_are_still_each_message_s_own(encoding: str) -> None:
    store = _typestore("ros1" if encoding == "ros1" else "ros2")
    kinds = [["arm_1", "arm_2"], ["arm_3", "arm_4"], ["arm_1", "arm_2", "grip"]]  # alike in length, then not
    payloads = []
    for i in range(30):
        value = _message(store, Recorded("/joint_states", i, (i, kinds[i % 3], [float(i)] * len(kinds[i % 3]))))
        serialize = store.serialize_ros1 if encoding == "ros1" else store.serialize_cdr
        payloads.append(bytes(serialize(value, "sensor_msgs/msg/JointState")))
    raw = np.frombuffer(b"".join(payloads), np.uint8)
    lengths = np.array([len(p) for p in payloads], np.int64)
    read, values, failures = WHOLE_DECODERS["sensor_msgs/msg/JointState", encoding](
        raw, np.cumsum(lengths) - lengths, lengths
    )
    assert read == list(range(30)) and failures == []
    assert [list(v.positions) for v in values] == [kinds[i % 3] for i in range(30)]
    assert [v.positions[kinds[i % 3][0]] for i, v in enumerate(values)] == [float(i) for i in range(30)]


def test_decode_holds_each_message_s_record_time_position_and_channel_once() -> None:
    """``decode`` joins the parts' per-message columns (record times, positions, channels) and lets the parts'
    go before the rows are made: held twice, they were the peak of a 4.1M-transform load (9 B a transform)."""
    import gc
    import weakref

    key = ("sensor_msgs/msg/JointState", "ros1")
    messages = message_set.MessageSet()
    channel = messages.channel("/joint_states", WholeCodec(*key, WHOLE_DECODERS[key]))
    for start in range(0, 300, 100):  # as a reader adds them, chunk by chunk
        part = range(start, start + 100)
        messages.add(channel, list(part), list(part), [_payload(i, ["arm_1"]) for i in part])
    parts = [weakref.ref(column) for columns in messages._messages for column in columns]
    messages.decode()
    gc.collect()
    assert [ref() for ref in parts] == [None] * len(parts)
    (whole,) = messages.whole
    assert list(whole.record_time) == list(range(300))


def _json_payloads(*messages: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    payloads = [m.encode() for m in messages]
    raw = np.frombuffer(b"".join(payloads), np.uint8)
    lengths = np.array([len(p) for p in payloads], np.int64)
    return raw, np.cumsum(lengths) - lengths, lengths


def test_json_joint_states_and_description_are_read_as_foxglove_writes_them() -> None:
    """A Foxglove MCAP's JSON (Franka teleop's /joint_states and /robot_description): each read, a damaged one a
    failure naming why, the others still read."""
    read, values, failures = WHOLE_DECODERS["sensor_msgs/msg/JointState", "json"](
        *_json_payloads(
            '{"header": {"stamp": {"sec": 3, "nanosec": 5}, "frame_id": "world"}, "name": ["j1", "j2"], '
            '"position": [0.5, -1.0]}',
            '{"header": {}, "name": ["j1", "j2"], "position": [0.5]}',
            '{"name": "j1"}',
            "not json",
            '{"name": ["j3"]}',
        )
    )
    assert read == [0, 4] and [m for m, _ in failures] == [1, 2, 3], failures
    assert values == [JointState(3_000_000_005, {"j1": 0.5, "j2": -1.0}), JointState(0, {})]
    assert "2 names but 1 positions" in failures[0][1] and "invalid JSON" in failures[2][1]
    read, values, failures = WHOLE_DECODERS["std_msgs/msg/String", "json"](
        *_json_payloads('{"data": "<robot name=\\"r\\"/>"}', '{"data": 7}')
    )
    assert read == [0] and values == ['<robot name="r"/>'] and [m for m, _ in failures] == [1]
