"""A jump back of a live source's clock clears what was heard, as tf2_ros's listener clears its
buffer: no network, a stand-in source driven by the test (the real ones: test_*_sim_time_loop)."""

from __future__ import annotations

import subprocess
import textwrap

import numpy as np
import pytest

from tests.oracle import ROS_PYTHON, unavailable_reason
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.errors import ConnectivityError
from tftools.core.rejection import RejectionCode
from tftools.core.time import NS_PER_S, SimClock
from tftools.core.transform import Transform
from tftools.sources.live import time_jump
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.capture import capture, listen
from tftools.sources.live.time_jump import JumpDetector, TimeJump

S = NS_PER_S


class SimSource(LiveSource):
    """A live source whose /clock and transforms the test sends, on the test's thread."""

    format = "test-live"

    def __init__(self) -> None:
        self.notices: list[str] = []
        super().__init__(None, True, self.notices.append)
        self._on_batch: OnBatch | None = None
        self.closed = False

    @property
    def clock(self) -> SimClock:
        assert isinstance(self._clock, SimClock)
        return self._clock

    @property
    def finished(self) -> bool:
        return self.closed

    def start(self, on_batch: OnBatch) -> None:
        self._on_batch = on_batch

    def describe(self) -> str:
        return "a test"

    def close(self) -> None:
        self.closed = True

    def tick(self, seconds: float) -> None:
        """A /clock message, as the sources handle it: a replay that loops resets the clock."""
        self._clock_message(round(seconds * S))

    def send(self, *rows: tuple[str, str, float, float], static: bool = False, received: float | None = None) -> None:
        """(parent, child, stamp s, x) rows in one message, received now (or at ``received`` s)."""
        builder = BatchBuilder()
        record = self._clock.now() if received is None else round(received * S)
        for parent, child, stamp, x in rows:
            builder.add(
                parent,
                child,
                round(stamp * S),
                (x, 0, 0),
                (0, 0, 0, 1),
                static=static,
                record_time=record,
                authority="/p",
            )
        assert self._on_batch is not None
        self.message_count += 1
        self._on_batch(builder.take())


def play(source: SimSource, start: float, seconds: float) -> None:
    """A pass of a replay: /clock, then odom -> base at 10 Hz, x = stamp - 1000."""
    for i in range(round(seconds * 10)):
        t = start + i / 10
        source.tick(t)
        source.send(("odom", "base", t, t - 1000))


def test_a_source_is_a_live_source() -> None:
    assert isinstance(SimSource(), LiveSource)


def test_the_detector_sees_the_clock_go_back_not_stand_still() -> None:
    clock = SimClock()
    detector = JumpDetector(clock)
    clock.set(1012 * S)
    assert detector.check() is None  # the first /clock: forwards from 0
    assert detector.check() is None  # no /clock since
    clock.reset(1000 * S)
    assert detector.check() == TimeJump(1012 * S, 1000 * S, sim_time=True)
    assert detector.check() is None  # said once
    clock.set(1001 * S)
    assert detector.check() is None


def test_the_wall_clock_jumping_back_is_a_jump_too() -> None:
    times = iter([50 * S, 60 * S, 40 * S])

    class Wall:
        def now(self) -> int:
            return next(times)

    detector = JumpDetector(Wall())
    assert detector.check() is None
    jump = detector.check()
    assert jump == TimeJump(60 * S, 40 * S, sim_time=False)
    assert jump.notice() == (
        "wall time jumped back from 60.000 s to 40.000 s (the clock set back?): "
        "cleared the tf buffer, static transforms kept"
    )


class FakeSeconds:
    """A monotonic clock the test moves."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_a_looped_replay_clears_the_listeners_buffer_but_its_statics(monkeypatch: pytest.MonkeyPatch) -> None:
    seconds = FakeSeconds()
    monkeypatch.setattr("tftools.sources.live.time_jump.time.monotonic", seconds)
    source = SimSource()
    buffer = listen(source)
    source.tick(999.9)
    source.send(("base", "laser", 0.0, 0.25), static=True)
    play(source, 1000.0, 12.5)  # tf2's cache is 10 s: the next pass would be too old
    assert buffer.lookup("odom", "laser").stamp == 1012_400_000_000
    play(source, 1000.0, 1.0)  # the replay loops
    latest = buffer.lookup("odom", "laser")
    assert latest.stamp == 1000_900_000_000 and latest.translation == pytest.approx((0.9 + 0.25, 0, 0))
    assert [r for r in buffer.rejections if r.code is RejectionCode.OLD_DATA] == []
    history = buffer.history("base")
    assert history is not None and history.oldest_stamp == 1000 * S  # nothing of the pass before
    assert source.notices == [
        "ROS time jumped back from 1012.400 s to 1000.000 s (a looped replay?): "
        "cleared the tf buffer, static transforms kept"
    ]
    seconds.now = 10.0
    play(source, 1000.0, 1.0)  # each loop says so again, even in the same words
    seconds.now = 20.0
    play(source, 1000.0, 1.0)
    assert source.notices[1:] == [source.notices[1]] * 2 and "from 1000.900 s to 1000.000 s" in source.notices[1]


def test_a_clock_going_back_and_forth_is_said_once_a_second_with_a_count(monkeypatch: pytest.MonkeyPatch) -> None:
    """A clock going back every 10 ms: 100 jumps within a second make 2 lines, the second counting the rest
    (446 lines in 5 s before)."""
    seconds = FakeSeconds()
    monkeypatch.setattr("tftools.sources.live.time_jump.time.monotonic", seconds)
    source = SimSource()
    listen(source)
    for n in range(100):
        seconds.now = n * 0.0099  # the first jump at 0.0099 s, the last at 0.98 s: within the first line's second
        play(source, 1000.0, 0.3)
    seconds.now = 0.0099 + time_jump.QUIET_SECONDS
    play(source, 1000.0, 0.3)
    assert len(source.notices) == 2
    assert source.notices[1].endswith("(98 more jumps back since the last said)")


def test_the_buffer_keeps_answering_while_the_clock_only_runs_forwards() -> None:
    source = SimSource()
    buffer = listen(source)
    play(source, 1000.0, 3.0)
    assert source.notices == [] and len(buffer.history("base") or ()) == 30


def test_the_batch_that_shows_the_jump_is_kept_whole() -> None:
    """/clock and /tf come on separate connections: the new pass's first transform may be received
    while the clock still reads the pass before's time, and delivered once it went back."""
    source = SimSource()
    buffer = listen(source)
    source.send(("base", "laser", 0.0, 0.25), static=True)
    play(source, 1000.0, 2.0)
    source.tick(1000.0)
    source.send(("odom", "base", 1000.0, 0.0), received=1001.9)
    history = buffer.history("base")
    assert history is not None and history.stamps.tolist() == [1000 * S]
    assert buffer.lookup("odom", "laser").translation[0] == 0.25


def test_the_pass_befores_last_transforms_delivered_after_the_jump_are_dropped() -> None:
    """Sent before the clock went back, delivered after: stamped nearer the time before the jump.
    The clearing waits for a transform of the new pass, so lookups never find the buffer empty."""
    source = SimSource()
    buffer = listen(source)
    source.send(("base", "laser", 0.0, 0.25), static=True)
    play(source, 1000.0, 2.0)
    source.tick(1000.0)
    source.send(("odom", "base", 1001.95, 1.95))
    assert buffer.lookup("odom", "base").stamp == 1001_900_000_000 and source.notices == []
    source.send(("odom", "base", 1001.97, 1.97), ("odom", "base", 1000.0, 0.0))
    history = buffer.history("base")
    assert history is not None and history.stamps.tolist() == [1000 * S] and len(source.notices) == 1
    assert buffer.lookup("odom", "laser").translation[0] == 0.25


def test_the_clearing_waits_for_one_batch_only() -> None:
    source = SimSource()
    buffer = listen(source)
    play(source, 1000.0, 2.0)
    source.tick(1000.0)
    source.send(("odom", "base", 1001.95, 1.95))
    source.send(("odom", "base", 1001.96, 1.96))  # stamps that do not follow the clock: cleared all the same
    assert len(buffer.history("base") or ()) == 0 and len(source.notices) == 1
    source.send(("odom", "base", 1001.97, 1.97))  # after the jump: kept
    assert buffer.lookup("odom", "base").stamp == 1001_970_000_000


def test_a_capture_forgets_what_it_heard_before_a_jump_but_statics() -> None:
    source = SimSource()
    heard: list[TransformBatch] = []

    def during() -> bool:  # capture calls it once listening: the replay runs, loops and runs on
        if not heard:
            play(source, 1000.0, 3.0)
            source.send(("base", "laser", 0.0, 0.25), static=True)
            play(source, 1000.0, 1.0)
            heard.append(TransformBatch.empty())
        return True

    recording = capture(source, duration=5.0, until=during)
    batch = recording.transforms
    dynamic = ~batch.static
    assert batch.stamp[dynamic].tolist() == [1000 * S + i * S // 10 for i in range(10)]
    assert int(batch.static.sum()) == 1
    assert recording.start == 1000 * S and len(source.notices) == 1


def test_clearing_keeps_frames_and_statics_as_tf2_does() -> None:
    buffer = Buffer()
    buffer.set_transform(Transform((1, 0, 0), (0, 0, 0, 1), 0, "base", "laser"), "/a", static=True)
    for t in range(1000, 1013):
        buffer.set_transform(Transform((t - 1000, 0, 0), (0, 0, 0, 1), t * S, "odom", "base"), "/a")
    buffer.lookup_many("odom", "laser", np.array([1005 * S]))  # the compiled lookups' table, if any, is built
    buffer.clear()
    assert buffer.frames == ["laser", "base", "odom"]
    assert buffer.lookup("base", "laser").translation[0] == 1.0
    with pytest.raises(ConnectivityError):
        buffer.lookup("odom", "laser")
    assert not buffer.lookup_many("odom", "laser", np.array([1005 * S])).valid.any()
    buffer.set_transform(Transform((5, 0, 0), (0, 0, 0, 1), 1000 * S, "odom", "base"), "/a")
    assert buffer.lookup("odom", "laser").translation[0] == 6.0
    assert buffer.rejections == []


TF2_CLEAR = textwrap.dedent(
    """
    import rospy, tf2_py
    from geometry_msgs.msg import TransformStamped

    def ts(parent, child, t, x):
        m = TransformStamped()
        m.header.frame_id, m.child_frame_id, m.header.stamp = parent, child, rospy.Time(t)
        m.transform.translation.x, m.transform.rotation.w = x, 1.0
        return m

    core = tf2_py.BufferCore(rospy.Duration(10))
    core.set_transform_static(ts("base", "laser", 0, 1.0), "/a")
    for t in range(1000, 1013):
        core.set_transform(ts("odom", "base", t, t - 1000.0), "/a")
    core.clear()
    try:
        core.lookup_transform_core("odom", "laser", rospy.Time(0))
    except Exception as error:
        print(type(error).__name__, error)
    core.set_transform(ts("odom", "base", 1000, 5.0), "/a")
    print(core.lookup_transform_core("odom", "laser", rospy.Time(0)).transform.translation.x)
    print(core.all_frames_as_yaml(), end="")
    """
)


def test_clearing_answers_as_the_real_tf2_after_its_clear() -> None:
    reason = unavailable_reason()
    if reason is not None:
        pytest.skip(reason)
    real = subprocess.run([ROS_PYTHON, "-c", TF2_CLEAR], capture_output=True, text=True, check=True).stdout
    buffer = Buffer()
    buffer.set_transform(Transform((1, 0, 0), (0, 0, 0, 1), 0, "base", "laser"), "/a", static=True)
    for t in range(1000, 1013):
        buffer.set_transform(Transform((t - 1000, 0, 0), (0, 0, 0, 1), t * S, "odom", "base"), "/a")
    buffer.clear()
    with pytest.raises(ConnectivityError) as error:
        buffer.lookup("odom", "laser")
    buffer.set_transform(Transform((5, 0, 0), (0, 0, 0, 1), 1000 * S, "odom", "base"), "/a")
    ours = f"ConnectivityException {error.value}\n{buffer.lookup('odom', 'laser').translation[0]}\n"
    assert ours + buffer.all_frames_as_yaml() == real


def test_a_transform_stamped_ahead_of_both_passes_is_stored_after_the_jump() -> None:
    """tf2_ros's time_reset_test: /clock at 100 s, foo -> bar at 100 and 102 s; /clock jumps back to 90 s;
    then foo2 -> bar2 stamped 110 s. tf2_ros clears its buffer at the jump and stores the new transform:
    a stamp far ahead of both the time before the jump and after it is of neither pass, never dropped."""
    source = SimSource()
    buffer = listen(source)
    source.tick(100.0)
    source.send(("foo", "bar", 100.0, 1.0))
    source.send(("foo", "bar", 102.0, 1.0))
    assert buffer.can_transform("foo", "bar", 101 * S)
    source.tick(90.0)
    source.send(("foo2", "bar2", 110.0, 1.0))
    assert buffer.lookup("foo2", "bar2").stamp == 110 * S
    assert not buffer.can_transform("foo", "bar", 101 * S)
    assert source.notices == [
        "ROS time jumped back from 100.000 s to 90.000 s (a looped replay?): cleared the tf buffer, "
        "static transforms kept"
    ]


def test_a_capture_on_sim_time_spans_what_it_heard_not_time_zero() -> None:
    """ROS time reads 0 until the first /clock: a capture that began then spanned from 0 ('1700000012.2 s')."""
    source = SimSource()

    def during() -> bool:
        if not source.message_count:
            play(source, 1_700_000_000.0, 2.0)
        return True

    recording = capture(source, duration=5.0, until=during)
    assert recording.start == 1_700_000_000 * S and recording.end == 1_700_000_001_900_000_000


def test_the_clock_step_of_a_source_on_sim_time() -> None:
    source = SimSource()
    assert source.clock_step == 0
    listen(source)
    play(source, 1000.0, 1.0)  # /clock every 100 ms
    assert source.clock_step == S // 10
