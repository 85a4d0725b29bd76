"""A finding's "first at" on a recording with no clock of its stamps (no /clock, stamps not on the record clock):
+S counts the stamps, while a replay (``monitor --play --start +S``, ``ros2 bag play --start-offset``) counts the
record clock from the first stamp (``Timeline.replay_shift``). Where the two are apart, both are said."""

from __future__ import annotations

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.monitor import MonitorQuery, monitor
from tftools.analysis.times import Offset
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.recording import Recording
from tftools.sources.timeline import Reference


def _simulation(slower: int) -> Recording:
    """odom -> base_link at 10 Hz of simulated time from 10 s, recorded on wall time ``slower`` times as slow, and
    base_link -> /laser from its 51st sample (stamped 15.0 s, +5.0 s)."""
    messages = []
    for i in range(100):
        stamp = 10 * NS_PER_S + i * NS_PER_S // 10
        sent = [Transform((0.01 * i, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "odom", "base_link")]
        if i >= 50:
            sent.append(Transform((0.1, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "base_link", "/laser"))
        messages.append(TfMessage("/tf", 1_700_000_000 * NS_PER_S + i * slower * NS_PER_S // 10, sent, "/sim"))
    return recording(messages)


def _first_slash(simulation: Recording) -> str:
    (found,) = [f for f in findings_of(Scene(simulation)) if f.code == "leading_slash"]
    return found.message


def test_a_first_moment_a_replay_plays_seconds_from_its_stamp_says_both() -> None:
    """A simulation at 0.1x real time (the JetAcker's at 0.067x): /laser's first sample, stamped +5.0 s, plays 50 s
    into the replay, where a monitor window finds it; a window at +5 s holds none of it."""
    slow = _simulation(10)
    assert slow.timeline.reference is Reference.NONE
    assert "first at 15.000 (+5.0 s; heard 50.0 s into the replay)" in _first_slash(slow)
    at_heard = monitor(slow, MonitorQuery(start=Offset(49.95), end=Offset(50.05)))
    assert [(e.child, e.count) for e in at_heard.edges if e.child == "laser"] == [("laser", 1)]  # tf2 drops the /
    at_stamp = monitor(slow, MonitorQuery(start=Offset(4.95), end=Offset(5.05)))
    assert not [e for e in at_stamp.edges if e.child == "laser"]


def test_a_first_moment_a_replay_plays_at_its_stamps_second_says_it_once() -> None:
    real_time = _simulation(1)
    assert real_time.timeline.reference is Reference.NONE
    message = _first_slash(real_time)
    assert "first at 15.000 (+5.0 s)" in message and "replay" not in message
