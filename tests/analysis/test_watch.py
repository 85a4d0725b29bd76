"""The watcher's sliding window: what it keeps, forgets and says gone, and its checks on a held window."""

from __future__ import annotations

from tftools.analysis.wtf.health import Level, edge_name
from tftools.analysis.wtf.watch import Window, check_window
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.time import NS_PER_S, SimClock
from tftools.sources.live.base import LiveSource
from tftools.sources.live.time_jump import TimeJump

START = 1_000 * NS_PER_S
IDENTITY = (0.0, 0.0, 0.0, 1.0)


def _batch(rows: list[tuple[str, str, int, bool]], authority: str = "/robot") -> TransformBatch:
    builder = BatchBuilder()
    for parent, child, at, static in rows:
        builder.add(
            parent, child, at, (at / NS_PER_S, 0.0, 0.0), IDENTITY, static=static, record_time=at, authority=authority
        )
    return builder.take()


def _odom(seconds: float, hz: int = 20, begin: int = START) -> TransformBatch:
    return _batch([("odom", "base_link", begin + i * NS_PER_S // hz, False) for i in range(int(seconds * hz))])


def test_the_window_keeps_its_last_seconds_and_the_statics_for_ever() -> None:
    window = Window(2 * NS_PER_S)
    window.keep(_batch([("base_link", "laser", START, True)]))
    window.keep(_odom(10))
    kept, begin, gone = window.take(START + 10 * NS_PER_S)
    dynamic = kept.record_time[~kept.static]
    assert dynamic.min() >= START + 8 * NS_PER_S and len(dynamic) == 40
    assert [kept.frame_names[c] for c in kept.child[kept.static]] == ["laser"]  # 10 s old, still there
    assert begin == START + 8 * NS_PER_S
    assert gone == {}


def test_an_edge_no_longer_heard_is_gone_with_when_it_was_last() -> None:
    window = Window(2 * NS_PER_S)
    window.keep(_odom(1))
    window.take(START + NS_PER_S)
    _, _, gone = window.take(START + 5 * NS_PER_S)
    assert gone == {("odom", "base_link"): START + 19 * NS_PER_S // 20}


def test_a_jump_back_forgets_the_dynamic_transforms_and_what_was_heard() -> None:
    window = Window(10 * NS_PER_S)
    window.keep(_batch([("base_link", "laser", START, True)]))
    window.keep(_odom(5))
    window.take(START + 5 * NS_PER_S)
    window.forget_dynamic(TimeJump(START + 5 * NS_PER_S, START, sim_time=True))
    kept, begin, gone = window.take(START + NS_PER_S // 2)
    assert len(kept) == 1 and kept.static.all()
    assert begin == START and gone == {}


def test_memory_is_bounded_by_the_window_however_long_it_runs() -> None:
    window = Window(NS_PER_S)
    for second in range(200):
        window.keep(_odom(1, begin=START + second * NS_PER_S))
        kept, _, _ = window.take(START + (second + 1) * NS_PER_S)
        assert len(kept) <= 21


class _Held(LiveSource):
    """A live source that is only a clock, for ``check_window``."""

    format = "ros1-live"

    def __init__(self, now: int) -> None:
        super().__init__(None, use_sim_time=False, on_notice=None)
        self._clock = SimClock(now)
        self.message_count = 1

    def describe(self) -> str:
        return "a test"

    def close(self) -> None:
        pass


def test_a_healthy_window_is_ok_and_an_edge_that_stopped_is_an_error_then_stale() -> None:
    window = Window(10 * NS_PER_S)
    window.keep(_batch([("base_link", "laser", START, True)]))
    window.keep(_odom(10))
    health = check_window(_Held(START + 10 * NS_PER_S), window)
    levels = {s.name: s.level for s in health.statuses}
    assert levels["tf: tree"] is Level.OK, [s for s in health.statuses if s.level]
    assert levels[edge_name("odom", "base_link")] is Level.OK
    assert levels[edge_name("base_link", "laser")] is Level.OK
    odom = next(s for s in health.statuses if s.name == edge_name("odom", "base_link"))
    assert dict(odom.values)["rate (Hz)"] == "20.000"

    stopped = check_window(_Held(START + 14 * NS_PER_S), window)  # silent 4 s: stale
    levels = {s.name: s.level for s in stopped.statuses}
    assert levels[edge_name("odom", "base_link")] is Level.ERROR
    assert levels["tf check: stale"] is Level.ERROR

    gone = check_window(_Held(START + 30 * NS_PER_S), window)  # out of the window: not heard
    levels = {s.name: s.level for s in gone.statuses}
    assert levels[edge_name("odom", "base_link")] is Level.STALE
    assert levels[edge_name("base_link", "laser")] is Level.OK
