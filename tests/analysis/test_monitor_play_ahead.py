"""``monitor --play`` whose replay runs ahead of its tables (a real TurtleBot3's 22.7 min lap,
ros2_db3_tb3_real_lap_2025, ``--play --rate 40`` piped on a loaded machine): the ticks a replay's clock has
passed are all made when they are due, at the time it reached; 831 of its 1361 tables repeated the one
before (same counts, same span). Each table is now a new window of recording time. On fake replays moved by
the test, not by wall time: no timed assertion."""

from __future__ import annotations

from itertools import pairwise

from tftools.analysis.monitor import LiveMonitor, MonitorQuery, monitor_stream
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.time import NS_PER_S
from tftools.sources.replay import Replay

START = 1_700_000_000 * NS_PER_S
MS = 1_000_000


def _odometry(seconds: float) -> TransformBatch:
    """odom -> base_link at 10 Hz for ``seconds``, recorded 5 ms after its stamps."""
    builder = BatchBuilder()
    for i in range(round(seconds * 10) + 1):
        stamp = START + i * 100 * MS
        builder.add("odom", "base_link", stamp, (0.01 * i, 0, 0), (0, 0, 0, 1), record_time=stamp + 5 * MS)
    return builder.take()


class RunningAhead(Replay):
    """A replay whose first step comes ``ahead`` s of wall time after it began, and whose wall clock moves
    ``during`` s more while each table is drawn (``drawn``): reads and tables slower than its clock. Its wall
    clock moves only so (and by what it sleeps)."""

    def __init__(self, batch: TransformBatch, ahead: float, during: float) -> None:
        super().__init__(batch, monotonic=self._wall, sleep=self._slept)
        self.ahead, self.during = ahead, during
        self.now: float | None = None  # the wall clock, from the replay's first look at it

    def _wall(self) -> float:
        if self.now is None:  # its beginning: its first step comes ``ahead`` s later
            self.now = self.ahead
            return 0.0
        return self.now

    def _slept(self, seconds: float) -> None:
        self.now = (self.now or 0.0) + seconds

    def drawn(self) -> None:
        self.now = (self.now or 0.0) + self.during


def _tables(replay: RunningAhead) -> list[float]:
    """The time of each table ``monitor_stream`` draws, in seconds into the replay."""
    times: list[float] = []

    def table(live: LiveMonitor) -> None:
        live.report()
        times.append(round((live.clock.now() - replay.begin) / NS_PER_S, 3))
        replay.drawn()

    monitor_stream(replay, MonitorQuery(window=10 * NS_PER_S), table)
    return times


def test_a_replay_played_to_its_end_before_the_first_table_gets_one_table_not_one_per_second() -> None:
    assert _tables(RunningAhead(_odometry(6.0), ahead=60.0, during=0.0)) == [6.0]  # was six at 6.0


def test_each_table_of_a_replay_running_ahead_is_a_new_window() -> None:
    """2.5 s played by the first table, 1.2 s more during each: the tables due at 1, 2, 3 and 4 s find the
    clock at 2.5, 3.7, 4.9 and 6.0 s (its end); those due at 5 and 6 s, nothing played meanwhile, showed 6.0 s
    again."""
    times = _tables(RunningAhead(_odometry(6.0), ahead=2.5, during=1.2))
    assert all(later > earlier for earlier, later in pairwise(times)), times
    assert times == [2.5, 3.7, 4.9, 6.0]
