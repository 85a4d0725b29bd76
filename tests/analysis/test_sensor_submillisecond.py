"""Waits shorter than a millisecond on a fine (wall) clock: said as "under 1 ms", never "0.000 s"."""

from __future__ import annotations

import dataclasses
import io
import json

import numpy as np
from rich.console import Console

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.filter import FilterQuery, FilterReport, filter_streams
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.figures import timeout_s, wait_in_words, within_in_words
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.filter import renderable, write_json
from tftools.sources.contents import StampedMessages

START = 1_700_000_000 * NS_PER_S
MS = 1_000_000
PERIOD = 20 * MS
EARLY = 80_000  # each message arrives 80 us before the transform it waits for


def _epuck() -> tuple[list[TfMessage], StampedMessages]:
    """As on ros2_db3_webots_epuck: odom -> base_link stamped every 20 ms, recorded 20 ms after its stamp on
    the wall clock; sensor data stamped with the same instants, recorded 80 us before the tf of their
    stamp (after the tf before it): each waits 80 us for it."""
    n = 300
    tf = [TfMessage("/tf", START + (i + 1) * PERIOD, [_tf(START + i * PERIOD)]) for i in range(n)]
    k = np.arange(1, n)
    stream = StampedMessages(
        "/imu",  # the e-puck's were /joint_states, sensor data only asked for by name (``placed_nowhere``)
        "sensor_msgs/Imu",
        (START + (k + 1) * PERIOD - EARLY).astype(np.int64),
        (START + k * PERIOD).astype(np.int64),
        np.zeros(len(k), np.int32),
        ["base_link"],
        k.astype(np.int64),  # the transforms read before each message: those of the stamps before its own
    )
    return tf, stream


def _tf(stamp: int) -> Transform:
    return Transform.from_rpy((0.1, 0.0, 0.0), (0.0, 0.0, 0.0), stamp, "odom", "base_link")


def _report() -> tuple[FilterReport, Scene]:
    tf, stream = _epuck()
    rec = recording(tf, ros1=False)
    assert rec.timeline.record_step == 0  # a fine clock: no tick to hide a wait under
    report = filter_streams(rec.buffer, [stream], FilterQuery(target="odom"), tick=rec.timeline.record_step)
    return report, Scene(rec, streams=[stream])


def _text(report: FilterReport, width: int) -> str:
    console = Console(width=width, record=True)
    console.print(renderable(report))
    return " ".join(console.export_text().split())


def test_waits_under_a_millisecond_are_said_so_in_filters_table_and_paragraph_and_exact_in_json() -> None:
    """Issue 39: on the e-puck, sensors waiting ~80 us for re-sent odometry read "p50 0.000 s"."""
    report, _ = _report()
    (joints,) = report.streams
    assert joints.later == joints.messages and joints.tick == 0
    assert joints.wait["p50"] == EARLY and joints.wait_needed == EARLY
    for width in (400, 120):  # the table, and the paragraphs a narrow terminal gets
        text = _text(report, width)
        assert "0.000" not in text, text
        assert "under 1 ms" in text
    paragraph = _text(report, 120)
    assert "waiting p50 under 1 ms, p99 under 1 ms, max under 1 ms" in paragraph
    assert "to keep 99.9%: wait under 1 ms" in paragraph
    out = io.StringIO()
    write_json(report, out)
    shown = json.loads(out.getvalue())["topics"][0]
    assert shown["wait_s"]["p50"] == EARLY / NS_PER_S and shown["wait_needed_s"] == EARLY / NS_PER_S


def test_sensor_wait_says_under_1_ms_and_asks_for_a_timeout_of_a_millisecond_not_0_s() -> None:
    _, scene = _report()
    (wait,) = [f for f in findings_of(scene) if f.code == "sensor_wait"]
    assert "waiting under 1 ms (all under 1 ms)" in wait.message, wait.message
    assert "a timeout of at least 0.001 s" in wait.hint and "0.000" not in wait.message + wait.hint


def test_an_instant_s_wait_for_the_transform_of_its_own_stamp_says_who_it_matters_to() -> None:
    """sweep39: the potted-plant AGV's /agv_pose waits under 1 ms for map -> odom of its own stamp, recorded just
    after it: a MessageFilter still queues it (not transformable on arrival) and passes it that instant, so the
    note is kept, saying that only a lookup as it arrives fails and what to do there: send the transform first.
    A wait of a millisecond or more, or for a transform stamped later, is not one instant's."""
    _, scene = _report()
    (wait,) = [f for f in findings_of(scene) if f.code == "sensor_wait"]
    assert wait.severity.value == "info"
    assert "Each waits only for the transform of its own stamp, which comes just after it (sent together, the " in (
        wait.message
    )
    assert "only a node that looks the transform up as the message arrives, without waiting, fails" in wait.message
    assert wait.hint.endswith("or send the transform before the message (where one node publishes both)")
    tf, stream = _epuck()
    later = dataclasses.replace(stream, record_time=stream.record_time - 2 * MS + EARLY)  # 2 ms before
    (slower,) = [f for f in findings_of(Scene(recording(tf, ros1=False), streams=[later])) if f.code == "sensor_wait"]
    assert "sent together" not in slower.message and slower.hint.endswith("make the late transform come sooner")


def test_wait_words_and_timeouts() -> None:
    assert wait_in_words(0) == "0.000 s" and wait_in_words(EARLY) == "under 1 ms"  # nil is nil; 80 us is not
    assert wait_in_words(499_999) == "under 1 ms" and wait_in_words(MS) == "0.001 s"
    assert wait_in_words(EARLY, 100 * MS) == "under one 0.100 s tick"  # a coarse clock's words first
    assert within_in_words(18 * MS) == "within 0.018 s" and within_in_words(EARLY) == "under 1 ms"
    assert timeout_s(EARLY) == 0.001 and timeout_s(18 * MS) == 0.018 and timeout_s(0) == 0.0
    assert timeout_s(EARLY, 100 * MS) == 0.1
