"""The live monitor on a replay: each refresh shows the numbers of its window, as they unfold."""

from __future__ import annotations

import io

import numpy as np
import pytest
from rich.console import Console

from tests.analysis.monitor_scenes import START, Scene, scene, scene_buffer
from tests.sources.test_replay import FakeTime, HandDriven
from tftools.analysis.edges import TimeWindow
from tftools.analysis.monitor import ARRIVED_HELD, LiveMonitor, MonitorReport, monitor_buffer
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S, SimClock
from tftools.render import monitor as render
from tftools.sources.contents import SentMessages
from tftools.sources.replay import Replay, follow

WINDOW = 4 * NS_PER_S


def _batch(truth: Scene) -> TransformBatch:
    builder = BatchBuilder()
    for m in truth.messages:
        for t in m.transforms:
            builder.add(t.frame_id, t.child_frame_id, t.stamp, t.translation, t.rotation,
                        static=m.topic == "/tf_static", record_time=m.record_time, authority=m.publisher)  # fmt: skip
    return builder.take()


def _play(truth: Scene, rate: float, target: str | None, source: str | None) -> list[tuple[int, MonitorReport, str]]:
    """Replay at ``rate`` on a fake wall clock; at each once-a-second refresh, the clock, report and table."""
    wall = FakeTime()
    replay = Replay(_batch(truth), rate=rate)
    live = LiveMonitor(replay.clock, WINDOW)
    refreshes: list[tuple[int, MonitorReport, str]] = []

    def refresh() -> None:
        report = live.report(target, source)
        console = Console(file=io.StringIO(), width=200)
        console.print(render.renderable(report, "", target, source))
        refreshes.append((replay.clock.now(), report, console.file.getvalue()))  # type: ignore[attr-defined]  # a StringIO, typed IO[str]

    driven = HandDriven(replay, wall)  # ticks on wall seconds: the path of a live feed
    follow(driven, live.add, refresh, summary=True, sleep=driven.sleep, monotonic=wall.monotonic)  # as monitor_stream
    return refreshes


@pytest.mark.parametrize("rate", [1.0, 3.0])
def test_each_refresh_shows_its_windows_numbers(rate: float) -> None:
    truth = scene()
    whole = scene_buffer(truth.messages)
    refreshes = _play(truth, rate, "map", "camera")
    assert len(refreshes) == int((truth.end - truth.start) / NS_PER_S / rate) + 1  # once a second, and the end
    for i, (now, _, _) in enumerate(refreshes[:-1]):
        assert now == truth.start + round((i + 1) * rate * NS_PER_S)  # sim time = bag time x rate
    for now, report, text in refreshes:
        expected = monitor_buffer(whole, window=TimeWindow(now - WINDOW, now, by_record_time=True))
        assert (report.start, report.end) == (now - WINDOW, now)
        assert [(e.key, e.count) for e in report.edges] == [(e.key, e.count) for e in expected.edges]
        for ours, theirs in zip(report.edges, expected.edges, strict=True):
            assert ours.rate_hz == pytest.approx(theirs.rate_hz, rel=1e-12, nan_ok=True)
            assert ours.delay_max == pytest.approx(theirs.delay_max, rel=1e-12, nan_ok=True)
            assert ours.longest_interval == pytest.approx(theirs.longest_interval, rel=1e-12)
        assert [(a.authority, a.messages) for a in report.authorities] == [
            (a.authority, a.messages) for a in expected.authorities
        ]
        if report.chain is not None:
            chain = monitor_buffer(whole, "map", "camera", TimeWindow(now - WINDOW, now, by_record_time=True)).chain
            assert chain is not None and seconds(report.chain.delay_mean) == pytest.approx(
                seconds(chain.delay_mean), rel=1e-9
            )
            assert f"avg = {seconds(report.chain.delay_mean):.4f}" in text
        odom = next(e for e in report.edges if e.child == "base_link")
        assert f"{odom.rate_hz:.2f}" in text and f"{seconds(odom.delay_mean):.4f}" in text


def test_the_hole_shows_while_it_is_in_the_window() -> None:
    """A hole in progress is a silence, said at once and apart from the gaps (a gap lies between two samples:
    counting the silence to the window's end in it made --play's largest gap differ from the whole read's);
    once the next sample came it is a gap, while it is in the window."""
    refreshes = _play(scene(), 1.0, None, None)
    odom = {round((now - START) / NS_PER_S): (next(e for e in r.edges if e.child == "odom"), text)
            for now, r, text in refreshes}  # fmt: skip
    gap = {at: seconds(e.longest_interval) for at, (e, _) in odom.items()}
    silent = {at: seconds(e.silent_for) for at, (e, _) in odom.items() if e.silent_for is not None}
    assert gap[9] == pytest.approx(0.05, abs=1e-6) and silent[9] < 0.05  # before the hole (it starts at 10 s)
    assert gap[11] == pytest.approx(0.05, abs=1e-6)  # in the hole: no gap yet, the silence so far, at once
    assert 1.03 < silent[11] < 1.05 and f"-> odom: silent for the last {silent[11]:.3f} s" in odom[11][1]
    # the hole within the window (from 10 s): not the 2.55 s from its sample at 9.95 s, before the window (a marker
    # unseen 9.3 s said so in a 10 s window of which it was 7 s); from where the window starts on the stamps' axis
    # (the first sample after the hole, less how long after the window's start it arrived)
    assert 2.5 <= gap[14] < 2.55 and odom[14][0].longest_interval_start >= START + 10 * NS_PER_S - NS_PER_S // 100
    assert silent[14] < 0.05 and "silent for the last" not in odom[14][1]
    assert gap[20] == pytest.approx(0.05, abs=1e-6)  # gone by


def test_waits_for_a_chain_that_does_not_exist_yet() -> None:
    truth = scene()
    camera_starts = START + 5 * NS_PER_S
    late = [m for m in truth.messages if m.transforms[0].child_frame_id != "camera" or m.record_time >= camera_starts]
    refreshes = _play(Scene(late, truth.truth, truth.static), 1.0, "map", "camera")
    waiting = "Waiting for transform chain to become available between map and camera"
    assert all(r.chain is None and waiting in text for now, r, text in refreshes if now < START + 5 * NS_PER_S)
    assert all(r.chain is not None and "Chain is: camera -> base_link -> odom -> map" in text
               for now, r, text in refreshes if now > START + 6 * NS_PER_S)  # fmt: skip


def test_a_monitor_fed_faster_than_it_reports_holds_only_the_messages_a_window_shows() -> None:
    """`monitor --play --rate 100000` of a 4 h recording reports a few times only: the tf messages that arrived
    between two reports were all held (1.1M of the robot's, its peak memory growing with the recording). Held
    unreported past ``ARRIVED_HELD``, those older than the window shows (two windows behind the newest) go."""
    live = LiveMonitor(SimClock(), WINDOW)
    chunk = ARRIVED_HELD // 2 + 1
    for k in range(6):  # a chunk every 100 s, none reported
        times = START + k * 100 * NS_PER_S + np.arange(chunk, dtype=np.int64) * 1_000
        sent = SentMessages(("/tf",), np.zeros(chunk, np.int32), np.zeros(chunk, np.bool_), times, times)
        live.add_sent(sent)
    held = live.sent
    assert held is not None and len(held) <= 3 * chunk, held
    newest = START + 5 * 100 * NS_PER_S + (chunk - 1) * 1_000
    assert int(held.record_time.min()) >= newest - 2 * WINDOW - 100 * NS_PER_S
    assert int(held.record_time.max()) >= START + 4 * 100 * NS_PER_S  # the recent ones are kept
