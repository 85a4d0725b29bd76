"""Waits read off a ticking record clock (a recorder under use_sim_time without /clock recorded)."""

from __future__ import annotations

import numpy as np

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.figures import wait_in_words
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.filter import renderable
from tftools.sources.contents import StampedMessages

START = 1_000 * NS_PER_S
MS = 1_000_000
TICK = 100 * MS


def _stage() -> tuple[list[TfMessage], StampedMessages]:
    """As on ros1_stage_amcl_sim_time_2015.bag: odom -> base_link stamped every 50 ms, recorded on 100 ms
    ticks (two samples a tick); scans stamped 60 ms into a tick, recorded two ticks on just before the tf
    of that tick (rosbag's order): each waits for that tf, which the record clock puts at the same instant."""
    tf = [TfMessage("/tf", START + (i // 2 + 1) * TICK, [_tf(START + i * 50 * MS)], "/stageros") for i in range(600)]
    k = np.arange(290)
    stream = StampedMessages(
        "/scan",
        "sensor_msgs/LaserScan",
        (START + (k + 2) * TICK).astype(np.int64),
        (START + k * TICK + 60 * MS).astype(np.int64),
        np.zeros(len(k), np.int32),
        ["base_link"],
        (2 * k + 2).astype(np.int64),  # the transforms read before each scan: those of the earlier ticks
    )
    return tf, stream


def _tf(stamp: int) -> Transform:
    return Transform.from_rpy((0.1, 0.0, 0.0), (0.0, 0.0, 0.0), stamp, "odom", "base_link")


def test_a_wait_shorter_than_the_record_clocks_tick_is_said_as_such_never_as_0_s() -> None:
    """Issue 39: sensor_wait and tfx filter said 'waiting 0.000 s' on the Stage bag, whose record times are
    100 ms ticks: a wait under the clock's step is 'under one 0.100 s tick', in wtf, filter (and the report,
    which says sensor_wait's words and the filter's p50)."""
    tf, stream = _stage()
    rec = recording(tf)
    assert rec.timeline.record_step == TICK
    report = filter_streams(rec.buffer, [stream], FilterQuery(target="odom"), tick=rec.timeline.record_step)
    scan = report.streams[0]
    assert scan.later == len(stream) and scan.wait["p50"] == 0 and scan.tick == TICK
    text = " ".join(_text(report).split())
    assert "waiting p50 under one 0.100 s tick" in text and "0.000 s" not in text
    (wait,) = [f for f in findings_of(Scene(rec, streams=[stream])) if f.code == "sensor_wait"]
    assert "waiting under one 0.100 s tick" in wait.message and "0.000 s" not in wait.message


def test_waits_on_a_fine_clock_or_of_a_tick_and_more_are_said_as_figures() -> None:
    assert wait_in_words(0) == "0.000 s" and wait_in_words(3 * MS) == "0.003 s"  # a wall clock: 0 is 0
    assert wait_in_words(99 * MS, TICK) == "under one 0.100 s tick"
    assert wait_in_words(TICK, TICK) == "0.100 s" and wait_in_words(250 * MS, TICK) == "0.250 s"


def _text(report: object) -> str:
    from rich.console import Console

    console = Console(width=250, record=True)
    console.print(renderable(report))  # type: ignore[arg-type]  # a FilterReport, passed as object
    return console.export_text()


def test_the_timeout_for_waits_under_a_tick_is_one_tick_not_0_s() -> None:
    """Every scan of ``_stage`` waits under a tick: the advice is a wait, never 'fine as it is' or 0 s."""
    tf, stream = _stage()
    rec = recording(tf)
    report = filter_streams(rec.buffer, [stream], FilterQuery(target="odom"), tick=rec.timeline.record_step)
    assert "to keep 99.9%: wait under one 0.100 s tick" in " ".join(_text(report).split())
    (wait,) = [f for f in findings_of(Scene(rec, streams=[stream])) if f.code == "sensor_wait"]
    assert "all under one 0.100 s tick" in wait.message and "a timeout of at least 0.100 s" in wait.hint
