"""Figures on one clock: a stream whose stamps hold two time bases (a bag replayed with its /tf beside live
nodes, a week behind them) has no gap, rate, period or delay measured across the two (``figures.across_clocks``)."""

from __future__ import annotations

import numpy as np
import pytest

from tftools.core import figures
from tftools.core.time import NS_PER_S

MS = 1_000_000
WEEK = 7 * 86_400 * NS_PER_S
NOW = 1_700_000_000 * NS_PER_S


def _two_clocks(n: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """Two publishers of one edge, each every 50 ms, taking turns 25 ms apart: one stamped a week behind its
    arrival (a replay), one just after (a live node post-dating its transform by 50 ms); sorted stamps and
    their record times, in arrival order."""
    arrivals = NOW + np.arange(n, dtype=np.int64) * 25 * MS
    replayed = np.arange(n) % 2 == 0
    stamps = np.where(replayed, arrivals - WEEK, arrivals + 50 * MS)
    return stamps, arrivals


def test_an_interval_longer_than_the_recording_joins_two_clocks() -> None:
    stamps, arrivals = _two_clocks()
    span = figures.record_span(arrivals)
    across = figures.across_clocks(np.sort(stamps), span)
    assert int(across.sum()) == 1  # sorted, the week between the two bases is one interval
    assert not figures.across_clocks(np.sort(stamps), 0).any()  # record times unknown: no evidence
    assert figures.record_span(np.zeros(3, np.int64)) == 0


def test_rate_gap_and_pauses_are_each_clocks_own() -> None:
    stamps, arrivals = _two_clocks()
    ordered, span = np.sort(stamps), figures.record_span(arrivals)
    records = arrivals[np.argsort(stamps, kind="stable")]
    # 198 intervals of the two publishers side by side over the 4.975 s they took to arrive: a sample every 25 ms,
    # neither one publisher's 50 ms (199 samples over twice the time) nor 199 samples over a week
    assert figures.rate_of(ordered, span, records) == pytest.approx(198 / 4.975)
    assert figures.rate_of(ordered, span) == 40.0  # nothing places them: each base's 20 Hz, side by side
    assert figures.rate_of(ordered) < 1e-3  # without the record span: the figure clocks11 fixed
    assert figures.longest_interval(ordered, span=span)[0] == 50 * MS
    assert figures.pauses(ordered, 0, span) is None
    assert figures.pauses(ordered, 0) is not None
    assert figures.jitter(ordered, span) == 0.0


def test_one_clock_is_unchanged() -> None:
    """A real pause shorter than the recording stays a pause, and the rate is the usual one."""
    stamps = NOW + np.concatenate([np.arange(100), 300 + np.arange(100)]).astype(np.int64) * 20 * MS
    span = figures.record_span(stamps + 2 * MS)
    assert figures.rate_of(stamps, span) == figures.rate_of(stamps)
    found = figures.pauses(stamps, 0, span)
    assert found is not None and found.longest == 201 * 20 * MS
    assert figures.longest_interval(stamps, span=span) == figures.longest_interval(stamps)


def test_delays_are_measured_on_the_base_of_the_arrival_clock() -> None:
    stamps, arrivals = _two_clocks()
    mine = figures.nearest_base(arrivals - stamps, figures.record_span(arrivals))
    assert np.array_equal(mine, np.arange(len(stamps)) % 2 == 1)  # the live publisher's, -50 ms each
    assert set(figures.time_base_of(arrivals - stamps, figures.record_span(arrivals)).tolist()) == {0, 1}
    assert figures.nearest_base(arrivals - stamps, 0).all()


def test_record_times_that_are_no_clock_part_nothing() -> None:
    """A writer that stored sim-time seconds as nanoseconds (the logistic cobot's 0-74 ns for 27.7 s of
    stamps): every interval is longer than the record span, which is then no evidence of two clocks."""
    stamps = NOW + np.arange(100, dtype=np.int64) * 10 * MS
    records = np.arange(1, 101, dtype=np.int64)
    span = figures.record_span(records)
    assert not figures.across_clocks(stamps, span).any()
    assert figures.rate_of(stamps, span) == figures.rate_of(stamps)
    assert figures.nearest_base(records - stamps, span).all()


def test_a_clock_that_steps_forward_in_mid_run_is_counted_before_plus_after() -> None:
    """One publisher every 50 ms whose clock steps a week forward half way (a robot without a real-time clock
    whose time is set by NTP while it runs): two time bases one after the other, 20 Hz throughout; placed on the
    record clock they do not overlap, so the rate is over their spans added, not their rates summed."""
    arrivals = NOW + np.arange(200, dtype=np.int64) * 50 * MS
    stamps = np.where(np.arange(200) < 100, arrivals - WEEK, arrivals)
    span = figures.record_span(arrivals)
    assert figures.rate_of(stamps, span, arrivals) == pytest.approx(198 / 9.9)
    assert figures.longest_interval(stamps, span=span)[0] == 50 * MS


def test_stamps_either_side_of_the_epoch_floor_are_two_bases_without_any_record_time() -> None:
    """The logistic cobot's /tf: an arm stamped on simulated time (from 46 s) beside detections on wall time,
    record times of 0: the floor parts them, whatever the record span; each base's rate, side by side."""
    sim = 46 * NS_PER_S + np.arange(101, dtype=np.int64) * 10 * MS
    wall = NOW + np.arange(11, dtype=np.int64) * 100 * MS
    stamps = np.sort(np.concatenate([sim, wall]))
    assert int(figures.across_clocks(stamps).sum()) == 1
    assert figures.time_base_of(stamps).tolist() == [0] * 101 + [1] * 11
    assert figures.rate_of(stamps) == pytest.approx(100.0 + 10.0)
    assert figures.rate_of(stamps, 0, np.zeros(len(stamps), np.int64)) == pytest.approx(110.0)
    assert figures.longest_interval(stamps)[0] == 100 * MS  # not the 55 years between the two
    assert figures.jitter(stamps) == np.std(np.concatenate([np.diff(sim), np.diff(wall)]))
    assert not figures.same_base(int(sim[-1]), int(wall[0])) and figures.same_base(int(sim[0]), int(sim[-1]))


def test_a_silence_is_counted_on_one_clock_or_not_at_all() -> None:
    """How long a stream has been silent: to the end on the same clock, 0 where it arrived since; unknown (None,
    never a 0 that reads "it just arrived") where the end is unknown (record times that are no clock), the last
    arrival is (a record time of 0), or they are on two time bases (simulated time against the epoch)."""
    assert figures.silence(NOW, NOW + 3 * NS_PER_S) == 3 * NS_PER_S
    assert figures.silence(NOW + MS, NOW) == 0
    assert figures.silence(NOW, None) is None
    assert figures.silence(0, NOW) is None and figures.silence(74 * NS_PER_S, NOW) is None
    assert figures.silence_in_words(3 * NS_PER_S, 10.0) == "silent for the last 3.000 s"
    assert figures.silence_in_words(NS_PER_S // 2, 10.0) == ""  # within 10 periods: still publishing
    assert figures.silence_in_words(None, 10.0) == ""


@pytest.mark.parametrize(
    "values, span",
    [
        (np.arange(100, dtype=np.int64) * 25 * MS, 0),  # from boot, no record span
        (NOW + np.arange(100, dtype=np.int64) * 25 * MS, 3 * NS_PER_S),  # one clock, within the span
        (np.array([5 * NS_PER_S, NOW, 6 * NS_PER_S, NOW + MS], np.int64), 0),  # either side of the epoch floor
        (np.sort(_two_clocks()[0]), figures.record_span(_two_clocks()[1])),  # a replay beside a live node
        (np.zeros(1, np.int64), 0),
    ],
)
def test_time_bases_counts_what_time_base_of_numbers(values: np.ndarray, span: int) -> None:
    """The count the load path asks of every edge, without the array where there is one base, is the array's."""
    assert figures.time_bases(values, span) == int(figures.time_base_of(values, span).max()) + 1


def test_the_samples_on_a_messages_clock_are_those_of_the_base_nearest_their_stamps() -> None:
    """``base_near``: of an edge two publishers send a week apart (``_two_clocks``), messages stamped on either
    clock meet that clock's samples alone; on one clock, or without messages, every sample is theirs."""
    stamps, arrivals = _two_clocks()
    span = figures.record_span(arrivals)
    live = stamps > arrivals - WEEK // 2
    assert (figures.base_near(stamps, span, arrivals[:5] + 60 * MS) == live).all()
    assert (figures.base_near(stamps, span, arrivals[-5:] - WEEK) == ~live).all()
    assert figures.base_near(stamps, span, np.zeros(0, np.int64)).all()
    assert figures.base_near(stamps[live], span, arrivals[:3] - WEEK).all()  # one clock: all, however far
