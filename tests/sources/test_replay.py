"""The replay clock: sim time follows bag time at --rate, rows arrive in order, never early."""

from __future__ import annotations

import itertools
import threading
import time

import numpy as np
import pytest

from tests.analysis.monitor_scenes import START, scene, scene_buffer
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S
from tftools.sources.contents import SentMessages, concat_sent
from tftools.sources.replay import CLOCK_HZ, OnBatch, Replay, follow, follow_into

MS = 1_000_000


class FakeTime:
    """A wall clock that moves only when slept on."""

    def __init__(self) -> None:
        self.now = 100.0
        self.sleeps: list[float] = []

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        assert seconds >= 0
        self.sleeps.append(seconds)
        self.now = round(self.now + seconds, 9)  # to the ns, as bag time: no float drift between the two


class HandDriven:
    """A replay as a live source for ``follow``, moved by a fake wall clock instead of its own thread."""

    def __init__(self, replay: Replay, wall: FakeTime) -> None:
        self.replay, self.wall = replay, wall
        self.clock = replay.clock

    @property
    def finished(self) -> bool:
        return self.replay.finished

    def start(self, on_batch: OnBatch) -> None:
        self.replay.attach(on_batch)

    def close(self) -> None:
        pass

    def sleep(self, seconds: float) -> None:
        """The wall clock sleeps; the replay catches up at its rate."""
        self.wall.sleep(seconds)
        self.replay.advance_to(self.replay.begin + round((self.wall.now - 100.0) * self.replay.rate * NS_PER_S))


def recorded(times_ms: list[int], static: list[bool] | None = None) -> TransformBatch:
    """One row per record time (ms after START); the stamp is the record time."""
    builder = BatchBuilder()
    for i, t in enumerate(times_ms):
        is_static = bool(static and static[i])
        builder.add("a", f"f{i}", START + t * MS, (0, 0, 0), (0, 0, 0, 1), static=is_static, record_time=START + t * MS)
    return builder.take()


@pytest.mark.parametrize("rate", [0.5, 1.0, 4.0])
def test_sim_time_follows_bag_time_at_the_rate(rate: float) -> None:
    batch = recorded([0, 5, 5, 130, 900, 2500])
    wall = FakeTime()
    replay = Replay(batch, rate=rate, sleep=wall.sleep, monotonic=wall.monotonic)
    deliveries: list[tuple[float, int, list[int]]] = []  # wall, clock before delivery, rows' record times

    def on_batch(b: TransformBatch) -> None:
        deliveries.append((wall.now, replay.clock.now(), b.record_time.tolist()))

    replay.run(on_batch)
    delivered = [t for _, _, times in deliveries for t in times]
    assert delivered == batch.record_time.tolist()  # every row once, in record order
    for now, _, times in deliveries:
        bag_now = START + round((now - 100.0) * rate * NS_PER_S)
        assert max(times) <= bag_now  # never before its time
    assert all(clock <= min(times) for _, clock, times in deliveries)  # the clock moves after delivery
    # Rows with one record time arrive together, each as soon as it is due (within a clock tick):
    assert [len(times) for _, _, times in deliveries] == [1, 2, 1, 1, 1]
    for now, _, times in deliveries:
        due = 100.0 + (times[0] - START) / NS_PER_S / rate
        assert due <= now < due + 1.0 / CLOCK_HZ + 1e-9
    assert replay.clock.now() == START + 2500 * MS and replay.finished
    assert max(wall.sleeps) <= 1.0 / CLOCK_HZ  # the clock ticks at least at 100 Hz
    assert wall.now - 100.0 == pytest.approx(2.5 / rate, abs=1.0 / CLOCK_HZ)


def test_clock_ticks_between_messages() -> None:
    wall = FakeTime()
    replay = Replay(recorded([0, 1000]), rate=2.0, sleep=wall.sleep, monotonic=wall.monotonic)
    seen: list[tuple[float, int]] = []
    original = wall.sleep

    def sleep(seconds: float) -> None:
        original(seconds)
        seen.append((wall.now, replay.clock.now()))

    replay._sleep = sleep  # observe the clock at every tick
    replay.run(lambda b: None)
    # After each sleep, the clock is where bag time was at the previous tick: wall x rate.
    for (before, _), (_, clock) in itertools.pairwise(seen):
        assert clock == START + round((before - 100.0) * 2.0 * NS_PER_S)
    assert len(seen) >= 0.5 * CLOCK_HZ - 1  # 0.5 s of wall at 100 Hz


def test_start_and_end_play_a_stretch_with_the_static_rows_first() -> None:
    batch = recorded([0, 10, 20, 30, 40, 50], static=[True, False, True, False, False, False])
    wall = FakeTime()
    replay = Replay(batch, start=START + 25 * MS, end=START + 40 * MS, sleep=wall.sleep, monotonic=wall.monotonic)
    deliveries: list[list[int]] = []
    replay.run(lambda b: deliveries.append(((b.record_time - START) // MS).tolist()))
    assert deliveries[0] == [0, 20]  # latched static transforms recorded before the start
    assert [t for d in deliveries[1:] for t in d] == [30, 40]  # not 10 (dynamic, before), not 50 (after the end)
    assert replay.clock.now() == START + 40 * MS


def test_advance_to_drives_the_replay_by_hand() -> None:
    replay = Replay(recorded([0, 10, 20]))
    got: list[int] = []
    replay.attach(lambda b: got.extend(b.record_time.tolist()))
    replay.advance_to(START + 15 * MS)
    assert got == [START, START + 10 * MS] and replay.clock.now() == START + 15 * MS and not replay.finished
    replay.advance_to(START + 5 * MS)  # the clock never runs backwards
    assert replay.clock.now() == START + 15 * MS
    replay.advance_to(START + 99 * MS)
    assert got[-1] == START + 20 * MS and replay.clock.now() == START + 20 * MS and replay.finished


def test_close_stops_a_background_replay() -> None:
    replay = Replay(recorded([0, 3_600_000]))  # an hour of bag at real speed
    got = threading.Event()
    replay.start(lambda b: got.set())
    assert got.wait(5.0)
    replay.close()
    assert replay.finished and replay.clock.now() < START + 3_600_000 * MS


def test_follow_ticks_once_a_second_until_the_feed_ends() -> None:
    wall = FakeTime()
    replay = Replay(recorded(list(range(0, 3500, 100))))  # 3.4 s of bag
    ticks: list[int] = []

    driven = HandDriven(replay, wall)
    rows: list[int] = []
    follow(driven, lambda b: rows.extend(b.record_time.tolist()), lambda: ticks.append(replay.clock.now()),
           sleep=driven.sleep, monotonic=wall.monotonic)  # fmt: skip
    assert len(rows) == 35
    # One tick per wall second (bag time = wall time here), none once the replay ended at 3.4 s.
    assert [round((t - START) / NS_PER_S, 1) for t in ticks] == [1.0, 2.0, 3.0]


def followed(times_ms: list[int], period: float, *, summary: bool = False) -> int:
    """How many ticks ``follow`` makes on a replay (real time) of rows at ``times_ms``: as they are on its clock,
    from its beginning, each is due at a whole period of bag time. Not fast: ticks a replay outran, made at
    once at the time it reached, show that time once (``test_follow_never_ticks_twice_at_one_time...``)."""
    replay = Replay(recorded(times_ms))
    ticks: list[int] = []
    follow(replay, lambda b: None, lambda: ticks.append(replay.clock.now()), period=period, summary=summary)
    assert all(t <= START + times_ms[-1] * MS for t in ticks)  # never after the replay's end
    return len(ticks)


def test_a_replay_ending_just_after_a_tick_gets_no_tick_of_its_own() -> None:
    """The json_mcap_lbx_franka.mcap case: 1.507 s of bag at 2 ticks a second, the last due 7 ms before the
    end; echo --play printed a fourth line at the end (7 ms after the third), which tf_echo on rosbag play's
    clock does not."""
    assert followed([0, 500, 1000, 1507], period=0.5) == 3


def test_a_replay_ending_on_a_tick_gets_it_and_one_shorter_than_a_period_gets_one_at_its_end() -> None:
    assert followed([0, 1000, 2000], period=1.0) == 2  # the tick due as the replay ends is made
    assert followed([0, 100, 300], period=1.0) == 1  # its state shown once rather than never


@pytest.mark.parametrize(
    ("times_ms", "period", "seen"),
    [([0, 500, 1000, 1507], 0.5, [0.5, 1.0, 1.5, 1.507]), ([0, 1000, 2000], 1.0, [1.0, 2.0])],
    ids=["after", "on"],
)
def test_a_summary_comes_as_a_feed_ends_after_its_last_tick(
    times_ms: list[int], period: float, seen: list[float]
) -> None:
    """monitor's last table covers the whole replay (echo's lines do not go past their rate); a feed that ended
    on its last tick gets none. On a fake wall clock, so that the clock of each tick is known."""
    wall = FakeTime()
    replay = Replay(recorded(times_ms))
    ticks: list[int] = []
    driven = HandDriven(replay, wall)
    follow(driven, lambda b: None, lambda: ticks.append(replay.clock.now()), period=period, summary=True,
           sleep=driven.sleep, monotonic=wall.monotonic)  # fmt: skip
    assert [round((t - START) / NS_PER_S, 3) for t in ticks] == seen


def test_follow_stops_after_its_duration() -> None:
    wall = FakeTime()
    closed: list[bool] = []

    class Endless:
        clock = Buffer().clock

        def start(self, on_batch: OnBatch) -> None:
            pass

        def close(self) -> None:
            closed.append(True)

    ticks: list[float] = []
    follow(Endless(), lambda b: None, lambda: ticks.append(wall.now), duration=2.5, sleep=wall.sleep,
           monotonic=wall.monotonic)  # fmt: skip
    assert ticks == [101.0, 102.0] and closed == [True]
    ticks.clear()
    follow(Endless(), lambda b: None, lambda: ticks.append(wall.now), duration=2.0, sleep=wall.sleep,
           monotonic=wall.monotonic)  # fmt: skip
    assert ticks == [103.5, 104.5]  # the tick due as the duration ends is made, once


def test_follow_into_a_buffer_sees_the_whole_bag() -> None:
    truth = scene()
    everything = scene_buffer(truth.messages)
    builder = BatchBuilder()
    for m in truth.messages:
        for t in m.transforms:
            builder.add(t.frame_id, t.child_frame_id, t.stamp, t.translation, t.rotation,
                        static=m.topic == "/tf_static", record_time=m.record_time, authority=m.publisher)  # fmt: skip
    live = Buffer(cache_time=None)
    follow_into(Replay(builder.take(), rate=1e6), live, lambda: None)  # 30 s of bag in 30 us
    assert sorted(live.frames) == sorted(everything.frames)
    for child, hist in everything.histories():
        ours = live.history(child)
        assert ours is not None and np.array_equal(ours.stamps, hist.stamps)
        assert np.array_equal(ours.record_times, hist.record_times)


def test_messages_play_with_their_transforms_statics_recorded_before_the_start_first() -> None:
    """``on_sent`` is told each message when its transforms are delivered, two messages of one record time
    both; the /tf_static ones recorded before the start first, the /tf ones before it never."""
    rows = recorded([0, 5, 10, 10, 20, 30], static=[True, False, True, False, False, False])
    sent = SentMessages(rows.authorities, rows.authority, rows.static, rows.record_time, rows.stamp)  # a row each
    replay = Replay(rows, sent=sent, start=START + 10 * MS)
    told: list[SentMessages] = []
    batches: list[TransformBatch] = []
    replay.on_sent = told.append
    replay.attach(batches.append)
    assert [list(s.record_time - START) for s in told] == [[0]]
    replay.advance_to(START + 20 * MS)
    assert [list(s.record_time - START) for s in told[1:]] == [[10 * MS, 10 * MS, 20 * MS]]
    assert [list(b.record_time - START) for b in batches[1:]] == [[10 * MS, 10 * MS, 20 * MS]]
    replay.advance_to(START + 40 * MS)
    assert len(concat_sent(told)) == 5 and replay.finished


def test_follow_never_ticks_twice_at_one_time_of_the_feeds_clock() -> None:
    """A replay played to its end before its first tick (``echo --play`` outrun by its replay): the three ticks
    due meanwhile come at once, at the time it reached; one is made, not three lines of one moment."""
    wall = iter([100.0, 110.0])  # its first step comes 10 s of wall time after it began: a slow read or table
    replay = Replay(recorded([0, 1000, 2000, 3000]), monotonic=lambda: next(wall))
    ticks: list[int] = []
    follow(replay, lambda b: None, lambda: ticks.append(replay.clock.now()))
    assert ticks == [START + 3000 * MS]


def test_follow_plays_a_replay_on_the_calling_thread() -> None:
    """Read and decoded on a thread of its own, a replay's windows were served by a second glibc heap (arena)
    whose peak took one of two levels ~22 MB apart at random: a 4 h replay in 1.16x the memory of a 1.3 h one
    (issue 41). Its rows and its ticks now come on the thread that follows it."""
    replay = Replay(recorded([0, 500, 1000, 1500]), rate=1e6)
    threads: set[threading.Thread] = set()
    follow(replay, lambda b: threads.add(threading.current_thread()), lambda: threads.add(threading.current_thread()))
    assert threads == {threading.current_thread()}


def test_a_tick_shows_one_instant_of_a_replay_playing_on_in_its_thread() -> None:
    """``monitor --play --rate 500`` on the sample bag, under load, showed one window twice: the tick read the
    replay's clock, the table read it again later (the replay's thread had reached the end), and the summary
    at that end showed it again. A tick now holds the replay (``Replay.held``) while it is drawn."""
    replay = Replay(recorded(list(range(0, 3000, 10))), rate=20.0)
    seen: list[tuple[int, int]] = []

    def drawn_slowly() -> None:
        first = replay.clock.now()
        time.sleep(0.03)  # 0.6 s of the replay's time at 20x, had it played on
        seen.append((first, replay.clock.now()))

    follow(replay, lambda b: None, drawn_slowly, period=0.5, summary=True)
    assert len(seen) >= 2 and all(read == shown for read, shown in seen), seen
    shown = [at for at, _ in seen]
    assert all(later > earlier for earlier, later in itertools.pairwise(shown)), shown
    assert shown[-1] == START + 2990 * MS
