"""The one definition of each figure of a stream of samples: its rate, its period, its pauses, its longest
interval and its delays. Over int64 ns arrays, in ns (a rate in Hz); seconds only where they are shown.

Three things are not called "gap" here: a *pause* is an interval much longer than the usual one (``pauses``),
the *longest interval* is the largest one, pause or not (``longest_interval``); why a lookup extrapolates is
``core.history``'s. A *silence* is no interval: the time since the last sample (``silence``). No figure spans two
time bases (``across_clocks``)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import overload

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int64Array, IntpArray
from tftools.core.batch import TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.rotation import angle_between_many
from tftools.core.time import EPOCH_FLOOR, NS_PER_S, duration

#: A silence or an interval is a stop or a pause only when it lasts this many periods too.
PERIODS = 10


def rate_hz(samples: int, span: int) -> float:
    """The one definition of a rate: ``samples`` over a span of ``span`` ns, (samples - 1) / span; 0
    for fewer than two samples or an empty span."""
    return (samples - 1) * NS_PER_S / span if samples > 1 and span > 0 else 0.0


def record_span(record_times: Int64Array) -> int:
    """How long (ns) samples took to arrive: from the first record time to the last; 0 where any is unknown
    (a record time of 0 or less), which ``across_clocks`` takes for "no evidence"."""
    return int(record_times.max() - record_times.min()) if len(record_times) and record_times.min() > 0 else 0


def across_clocks(stamps: Int64Array, span: int = 0) -> BoolArray:
    """The one definition of a time base: which intervals between consecutive sorted ``stamps`` of one stream
    (or offsets of arrival from stamp) join two time bases rather than two moments of one clock. Two rules, each
    on its own evidence:

    - the stamps': one below ``EPOCH_FLOOR`` (counted from boot or a simulation's start) and the next at or above
      it (from the epoch). Needs no record time (the logistic cobot's /tf: an arm on simulated time beside
      detections on wall time, recorded with record times of 0; one span over both is 55 years).
    - the record ``span``'s (``record_span``, the time the stream took to arrive): longer than it. One clock
      cannot advance further between two samples than the recording lasted; two do (a bag replayed beside live
      nodes: its stamps a week behind theirs). This rule parts none where ``span`` is unknown (0), or where half
      the intervals or more are longer: then the record times are no clock (a writer that put sim-time seconds as
      nanoseconds, 74 ns for 27.7 s of stamps), as two clocks part the stamps once, not at every sample.

    No gap, rate or period is ever measured across such an interval."""
    epochs: BoolArray = (stamps[:-1] < EPOCH_FLOOR) & (stamps[1:] >= EPOCH_FLOOR)
    longer = _longer_than_span(stamps, span)
    return epochs if longer is None else longer | epochs


def same_base(a: int, b: int) -> bool:
    """Whether two times can be on one time base by the stamps' rule of ``across_clocks``: both from the epoch
    or both from boot or a simulation's start (``EPOCH_FLOOR``). Two times alone hold no record span."""
    return (a < EPOCH_FLOOR) == (b < EPOCH_FLOOR)


def _longer_than_span(stamps: Int64Array, span: int) -> BoolArray | None:
    """The intervals of sorted ``stamps`` longer than the record ``span`` (``across_clocks``' second rule); None
    where the record times are no evidence of a clock (an unknown span, or half the intervals longer)."""
    if span <= 0:
        return None
    longer: BoolArray = np.diff(stamps) > span
    return longer if 2 * int(np.count_nonzero(longer)) < len(longer) else None


def on_one_base(values: Int64Array, span: int) -> bool:
    """Whether ``values`` are on one time base, known without sorting them: on one side of the epoch floor,
    none further apart than the record ``span``."""
    return len(values) < 2 or _ends_on_one_base(int(values.min()), int(values.max()), span)


def _ends_on_one_base(low: int, high: int, span: int) -> bool:
    """Whether values from ``low`` to ``high`` are on one time base by their ends alone (``across_clocks``' two
    rules): on one side of the epoch floor, no further apart than the record ``span``."""
    return (high < EPOCH_FLOOR or low >= EPOCH_FLOOR) and (span <= 0 or high - low <= span)


def time_bases(values: Int64Array, span: int = 0) -> int:
    """How many time bases ``values`` are on (``time_base_of``), without an array where they are on one (the
    load path asks it of every edge)."""
    return 1 if on_one_base(values, span) else int(time_base_of(values, span).max()) + 1


def time_base_of(values: Int64Array, span: int = 0) -> IntpArray:
    """Which time base each of a stream's ``values`` (stamps, or offsets of arrival from stamp; any order) is
    on, numbered from the earliest: sorted, they split where ``across_clocks`` (with the stream's record
    ``span``) parts them. All 0 on one clock."""
    base = np.zeros(len(values), np.intp)
    if on_one_base(values, span):
        return base
    order = np.argsort(values, kind="stable")
    breaks = np.flatnonzero(across_clocks(values[order], span))
    base[order] = np.searchsorted(breaks, np.arange(len(values)), side="left")
    return base


def nearest_base(offsets: Int64Array, span: int) -> BoolArray:
    """Which of a stream's ``offsets`` (ROS time at arrival minus stamp, ns) are on the time base of the clock
    they arrived on (``time_base_of``: no delay grows by more than the recording lasts): the group holding the
    offset nearest zero. A replay's samples a week behind a live publisher's have no delay, only an offset
    between clocks."""
    if not len(offsets):
        return np.ones(0, np.bool_)
    base = time_base_of(offsets, span)
    mine: BoolArray = base == base[int(np.argmin(np.abs(offsets)))]
    return mine


def base_near(stamps: Int64Array, span: int, near: Int64Array) -> BoolArray:
    """Which of an edge's sample ``stamps`` (any order; ``span``: their record span) are on the clock of messages
    stamped ``near``: where the samples are on several time bases (``time_base_of``: two publishers' clocks 5.8 h
    apart), those on the base of the sample nearest the messages' median stamp; else all of them, as without
    messages. A figure of the edge for those messages (its rate, how far their clocks are apart) is of these
    samples, never of a blend of two clocks."""
    if not len(near) or on_one_base(stamps, span):
        return np.ones(len(stamps), np.bool_)
    base = time_base_of(stamps, span)
    mine: BoolArray = base == base[int(np.argmin(np.abs(stamps - median_ns(near))))]
    return mine


def rate_of(times: Int64Array, span: int = 0, records: Int64Array | None = None) -> float:
    """The rate (``rate_hz``) of samples at sorted ``times`` (stamps), never over an interval between two time
    bases (``across_clocks``, with the stream's record ``span``): on one base, its samples over its span. On
    several, the samples over the time they cover side by side: each base's stamps moved onto the record clock
    by its own offset (the median of ``records``, the samples' record times, minus their stamps), so that two
    publishers taking turns on clocks a week apart are counted over the recording's 54 s, not over 108 s nor
    7 days, and a clock that stepped forward in mid-run is counted over the time before plus after. Where the
    record times are no clock (``span`` unknown, or no evidence: ``across_clocks``), each base's rate over its
    own span, summed."""
    if not len(times):
        return 0.0
    first, last = int(times[0]), int(times[-1])
    if _ends_on_one_base(first, last, span):
        return rate_hz(len(times), last - first)  # one base, known from its ends (every edge of a load asks)
    across = across_clocks(times, span)
    if not across.any():
        return rate_hz(len(times), last - first)
    starts = np.concatenate(([0], np.flatnonzero(across) + 1))
    ends = np.concatenate((starts[1:], [len(times)])) - 1
    counts = ends - starts + 1
    if records is None or _longer_than_span(times, span) is None:  # no record clock to place them on
        return sum(rate_hz(int(n), int(times[e] - times[b])) for n, b, e in zip(counts, starts, ends, strict=True))
    offsets = [median_ns(records[b : e + 1] - times[b : e + 1]) for b, e in zip(starts, ends, strict=True)]
    low = times[starts] + np.array(offsets, np.int64)
    high = times[ends] + np.array(offsets, np.int64)
    return rate_hz(int(counts.sum() - len(counts)) + 1, _covered(low, high))


def message_rate(arrivals: Int64Array) -> float:
    """The one definition of a publisher's rate: its messages over the time they arrived in, on the clock they
    arrived on (``Timeline.counted_at``: tf_monitor's, the listening node's; a replay's is the record clock), in
    any order; where that is no clock, their stamps on each time base apart (``rate_of``)."""
    return rate_of(np.sort(arrivals))


def _covered(low: Int64Array, high: Int64Array) -> int:
    """How long (ns) the union of the intervals ``[low[i], high[i]]`` lasts."""
    order = np.argsort(low, kind="stable")
    total, reach = 0, None
    for a, b in zip(low[order].tolist(), high[order].tolist(), strict=True):
        if reach is None or a > reach:
            total, reach = total + b - a, b
        elif b > reach:
            total, reach = total + b - reach, b
    return total


def period(intervals: Int64Array) -> int:
    """The usual interval (ns): the median of ``intervals``; 0 without any."""
    return int(np.median(intervals)) if len(intervals) else 0


def sustained_period(intervals: Int64Array) -> int:
    """The interval (ns) a stream keeps up for most of its time: the median of ``intervals`` each weighted by
    its length (a real Neato's 44 samples 10 ms apart in its first 0.44 s, then one every 0.32-0.55 s for 7 s:
    about 0.4 s, where ``period``, a median by count, is the burst's 10 ms); 0 without any."""
    if not len(intervals):
        return 0
    ordered = np.sort(intervals)
    held = np.cumsum(ordered, dtype=np.float64)
    return int(ordered[min(int(np.searchsorted(held, held[-1] / 2)), len(ordered) - 1)])


def median_ns(values: Int64Array) -> int:
    """The median of ``values`` (ns), exact: ``np.median`` works in float64, whose step at a wall-clock time
    in ns (1.7e18) is 256 ns. Of an even count, the mean of the middle two, towards zero (as
    ``int(np.median(...))``); 0 without any. Ascending ``values`` (a history's stamps) are read off the
    middle without a partition."""
    n = len(values)
    if not n:
        return 0
    middle = _middle(n)
    ordered = values if bool(np.all(values[1:] >= values[:-1])) else np.partition(values, middle)
    return _median_of(ordered, middle)


def _middle(n: int) -> list[int]:
    """Where the middle one or two of ``n`` sorted values are."""
    return sorted({(n - 1) // 2, n // 2})


def _median_of(ordered: Int64Array, middle: list[int]) -> int:
    """``median_ns`` of values whose ``middle`` (``_middle``) are in their sorted places."""
    total = int(ordered[middle[0]]) + int(ordered[middle[-1]])
    return total // 2 if total >= 0 else -(-total // 2)


def median_and_percentile(values: Int64Array, q: float) -> tuple[int, float]:
    """``median_ns(values)`` and ``percentile(values, q)`` of non-empty ``values``, from one partition (a
    timeline asks both of every edge's arrival offsets)."""
    middle, ranks = _middle(len(values)), _ranks(len(values), q)
    ordered = np.partition(values, sorted({*middle, ranks[0] % len(values), ranks[1] % len(values)}))
    return _median_of(ordered, middle), _percentile_of(ordered, q, ranks)


#: The share of a sensor's messages the settings suggested for a tf2 MessageFilter (or a lookup's timeout)
#: keep: the wait, queue and cache ``tfx filter`` and ``tfx wtf`` suggest are those keeping it.
KEEP = 0.999


def wait_keeping(waits: Int64Array, on_arrival: int, decided: int, keep: float = KEEP) -> int | None:
    """The one definition of the wait a sensor stream needs: the smallest timeout (ns) with which ``keep`` of
    its ``decided`` messages are transformed, ``on_arrival`` of them at once, the others after their
    ``waits`` (ns); 0 where those on arrival are enough, None where no timeout is (too many never are)."""
    must = math.ceil(keep * decided) - on_arrival
    if must <= 0:
        return 0
    return int(np.partition(waits, must - 1)[must - 1]) if must <= len(waits) else None


def kept_in_words(decided: int, keep: float = KEEP) -> str:
    """The share ``wait_keeping`` keeps of ``decided`` messages, in words: "99.9%", or "all" where that share is every
    one of them (fewer than a thousand: 99.9% of 116 messages is 116, and "99.9% within" read as a figure no count
    of them can give)."""
    return "all" if math.ceil(keep * decided) >= decided else f"{keep:.1%}"


def jitter(stamps: Int64Array, span: int = 0) -> float:
    """How irregular sorted ``stamps`` are (ns): the standard deviation of their intervals (on one time base:
    ``across_clocks``); 0 for fewer than two."""
    intervals = np.diff(stamps)[~across_clocks(stamps, span)]
    return float(np.std(intervals)) if len(intervals) else 0.0


def silence_limit(rate: float, floor: int = 0) -> float:
    """How long (ns) a stream at ``rate`` Hz may be silent and still be publishing: ``PERIODS`` of its
    periods, and at least ``floor``."""
    return max(float(floor), PERIODS * NS_PER_S / rate if rate > 0 else 0.0)


@dataclass(frozen=True)
class Pauses:
    """The pauses in sorted stamps: intervals longer than ``PERIODS`` periods and a floor (ns)."""

    period: int  # the median interval between consecutive stamps
    count: int
    longest: int
    longest_start: int  # the stamp the longest one begins at
    first: int  # where the first one begins, and the last one ends
    last: int


#: A pause is also longer than PERIODS of the usual interval among the NEIGHBOURS intervals either side of it.
NEIGHBOURS = 5


def pause_rows(stamps: Int64Array, floor: int, span: int = 0) -> tuple[int, Int64Array, IntpArray]:
    """The ``period`` of sorted ``stamps``, their intervals, and the rows ``i`` where the interval from
    ``stamps[i]`` to ``stamps[i + 1]`` is a pause: longer than ``floor`` and ``PERIODS`` periods, of the
    whole stream and of its ``NEIGHBOURS`` either side where it has that many (a driver that flushed a burst of
    samples 10 ms apart at its start, then sent every 0.4 s, has a median of the burst's: its 0.55 s intervals
    are its rhythm; a simulation's last seconds, 4.5, 0.96, 4.74 and 3.36 s apart, set none),
    on one time base (an interval between two clocks, ``across_clocks`` with the record ``span``, is none)."""
    intervals = np.diff(stamps)
    one_clock = ~across_clocks(stamps, span)
    usual = period(intervals[one_clock])
    rows = np.flatnonzero((intervals > max(floor, PERIODS * usual)) & one_clock)
    kept = intervals[one_clock]
    at = np.cumsum(one_clock) - 1  # each one-clock interval's place among them
    around = [
        np.concatenate((kept[max(at[r] - NEIGHBOURS, 0) : at[r]], kept[at[r] + 1 : at[r] + 1 + NEIGHBOURS]))
        for r in rows
    ]
    whole = 2 * NEIGHBOURS  # a rhythm is read off full neighbourhoods: by the stream's ends, its own period judges
    paused = [
        r
        for r, near in zip(rows.tolist(), around, strict=True)
        if len(near) < whole or intervals[r] > PERIODS * period(near)
    ]
    return usual, intervals, np.array(paused, dtype=np.intp)


def pauses(stamps: Int64Array, floor: int, span: int = 0) -> Pauses | None:
    """The pauses of sorted ``stamps`` (``pause_rows``); None if there is none, or fewer than 3 stamps."""
    if len(stamps) < 3:
        return None
    usual, intervals, rows = pause_rows(stamps, floor, span)
    if not len(rows):
        return None
    longest = int(rows[np.argmax(intervals[rows])])
    return Pauses(
        usual, len(rows), int(intervals[longest]), int(stamps[longest]), int(stamps[rows[0]]), int(stamps[rows[-1] + 1])
    )


def longest_interval(
    stamps: Int64Array, before: int | None = None, span: int = 0, since: int | None = None
) -> tuple[int, int]:
    """The longest interval (ns) of sorted ``stamps`` and the stamp it begins at: between two of them on one
    time base (``across_clocks`` with the record ``span``), or from the stamp ``before`` them, counted from
    ``since`` where that is later (a window's start: a monitor's window shows the part of a gap within it, not
    9.3 s of a marker unseen in a 10 s window of which it was 7 s). A gap lies between two samples: the silence
    after the last is ``silence``'s."""
    candidates = [(0, int(stamps[0]))]
    if len(stamps) > 1:
        intervals = np.where(across_clocks(stamps, span), 0, np.diff(stamps))
        i = int(np.argmax(intervals))
        candidates.append((int(intervals[i]), int(stamps[i])))
    if before is not None:
        begins = before if since is None else min(max(before, since), int(stamps[0]))
        candidates.append((int(stamps[0]) - begins, begins))
    return max(candidates, key=lambda c: c[0])


#: An interval this many usual ones long (``period``) or longer parts two bursts of sightings (``sightings``): a
#: detector that missed the frame between, or more.
MISSED = 2


@dataclass(frozen=True)
class Sightings:
    """A stream seen in bursts (a detector's marker, published while the camera sees it): how many bursts, its
    rate within them, and the share of its span they cover; the longest time it went unseen (ns) and the stamp
    that began at."""

    bursts: int
    rate_hz: float
    seen: float  # 0 to 1
    longest_unseen: int
    longest_unseen_start: int

    def in_words(self, longest: bool = True) -> str:
        """ "seen in 162 bursts, at 27.0 Hz within them, 58% of the time from its first sighting to its last
        (unseen for up to 0.345 s)": the share is of its span, not of the recording's or a window's (a marker first
        seen 8.9 s into a 10 s window, then in bursts for 1.1 s, was seen 76% of that time); without
        the ``longest`` time unseen where it is said beside."""
        unseen = f" (unseen for up to {duration(self.longest_unseen / NS_PER_S)})" if longest else ""
        within = (
            f"at {self.rate_hz:.1f} Hz within them, {self.seen:.0%} of the time from its first sighting to its last"
        )
        return f"seen in {self.bursts} bursts, {within}{unseen}"


def unseen_between(stamps: Int64Array, span: int = 0) -> BoolArray:
    """Which intervals of a stream's sorted ``stamps`` part its bursts (``sightings``): ``MISSED`` times its
    ``period`` or longer, on one time base (an interval ``across_clocks`` is none)."""
    across, every = across_clocks(stamps, span), np.diff(stamps)
    usual = period(every[~across])
    return (every >= MISSED * usual) & ~across if usual else np.zeros(len(every), np.bool_)


def sightings(stamps: Int64Array, span: int = 0) -> Sightings | None:
    """The one definition of a stream seen in bursts, over its sorted ``stamps`` (on one time base: an interval
    between two, ``across_clocks`` with the record ``span``, counts as neither): its intervals ``MISSED`` times
    its ``period`` or longer part the bursts, the others are within one; the rate within bursts is theirs
    (``rate_hz`` of what they hold), the share seen is their time over all. None for fewer than 3 stamps or where
    it was never unseen (one burst: its rate is the stream's)."""
    if len(stamps) < 3:
        return None
    across, every = across_clocks(stamps, span), np.diff(stamps)
    intervals = every[~across]
    usual = period(intervals)
    apart = unseen_between(stamps, span)[~across]
    if not usual or not apart.any():
        return None
    within, whole = int(intervals[~apart].sum()), int(intervals.sum())
    longest = int(np.argmax(np.where(across, 0, every)))
    return Sightings(
        int(apart.sum()) + 1,
        rate_hz(int((~apart).sum()) + 1, within),
        within / whole if whole else 0.0,
        int(stamps[longest + 1] - stamps[longest]),
        int(stamps[longest]),
    )


def silence(last_arrival: int, end: int | None) -> int | None:
    """The one definition of how long a stream has been silent (ns): from its last arrival to ``end`` (the
    recording's end, a live listener's now, on the same clock); 0 where it arrived since; None, unknown, where
    either is (no end: record times that are no clock; an arrival of 0 or less) or they are on two time bases
    (``same_base``): no figure, never a 0 that reads "it just arrived". Said apart from its gaps: "silent for
    the last 2.500 s" (``silence_in_words``), unknown as "-" in tables, null in JSON."""
    if end is None or last_arrival <= 0 or not same_base(last_arrival, end):
        return None
    return max(end - last_arrival, 0)


#: A stream silent at least this long (ns; and ``PERIODS`` of its periods) before its recording ends has stopped,
#: by default (``Thresholds.stale_after``'s default, which ``tfx wtf --stale-after`` changes): a recorder that
#: stops some topics a little before others ended nothing.
STOP_FLOOR = NS_PER_S


def stopped(silent: int | None, rate: float, floor: int = 0) -> bool:
    """Whether a stream at ``rate`` Hz silent for ``silent`` ns (``silence``) has stopped: silent longer than
    ``silence_limit`` (at least ``floor``); not where either is unknown (None, no rate)."""
    return silent is not None and rate > 0 and silent > silence_limit(rate, floor)


def silence_in_words(silent: int | None, rate: float) -> str:
    """A stream's ``silence`` as a person reads it, where it is one (longer than ``PERIODS`` periods at ``rate``
    Hz, ``silence_limit``): "silent for the last 2.500 s"; "" where it is not or is unknown."""
    if silent is None or not stopped(silent, rate):
        return ""
    return f"silent for the last {silent / NS_PER_S:.3f} s"


def delays(arrivals: Int64Array, stamps: Int64Array, resolution: int = 0) -> Int64Array:
    """The one definition of a delay: time at arrival minus stamp (ns). Arrival times read off a clock that
    ticks every ``resolution`` ns lag by up to a step, so the delay lies between the reading and a step
    more: the value nearest zero in that range, never a negative delay that the clock's steps made."""
    read = arrivals - stamps
    return np.minimum(np.maximum(read, 0), read + resolution) if resolution else read


def clocks_apart(read: Int64Array, same_clock: int) -> BoolArray:
    """Which readings of arrival minus stamp (ns) are no delay: a stamp more than ``same_clock`` ahead of its
    arrival is on a clock running ahead of the one that timed the arrival (a machine 5.8 h ahead of the
    recorder's), and their difference is how far the clocks are apart, not how late a transform came."""
    apart: BoolArray = read < -same_clock
    return apart


def apart_in_words(ahead: int) -> str:
    """Why a delay is not shown where the stamps run ``ahead`` (ns) of the clock that timed their arrival
    (``clocks_apart``): the one wording of ``monitor`` (text and JSON), ``report`` and ``view-frames``."""
    return f"not measurable (clock apart by {duration(ahead / NS_PER_S)})"


def percentile(values: Int64Array, q: float) -> float:
    """``np.percentile(values, q)`` (its default, linear method) of non-empty ``values``, computed with
    numpy's very operations, without its partition's call of ``np.unique``: whose first call imports
    ``numpy.ma`` (about a fifth of a small bag's load; timeline.py asked it of every edge)."""
    count = len(values)
    low, high = _ranks(count, q)
    return _percentile_of(np.partition(values, sorted({low % count, high % count})), q, (low, high))


def _ranks(count: int, q: float) -> tuple[int, int]:
    """The two ranks (-1: the last) whose values ``percentile`` weighs, of ``count`` values."""
    virtual = (count - 1) * np.true_divide(q, 100)
    low = high = -1 if virtual >= count - 1 else int(np.floor(virtual))  # numpy's: past the last index, the last
    if low >= 0:
        high = low + 1
    return low, high


def _percentile_of(part: Int64Array, q: float, ranks: tuple[int, int]) -> float:
    """``percentile`` of values whose ``ranks`` (``_ranks``) are in their sorted places in ``part``."""
    virtual = (len(part) - 1) * np.true_divide(q, 100)
    below = np.floor(virtual)
    a, b = part[ranks[0]], part[ranks[1]]
    gamma = float(virtual - below)
    difference = b - a
    if gamma >= 0.5:  # numpy's lerp, from the nearer end
        return float(np.subtract(b, difference * (1 - gamma)))
    return float(np.add(a, difference * gamma))


def mean_max(values: Int64Array) -> tuple[float, float]:
    """The mean and the largest of ``values`` (ns); NaN, NaN without any."""
    if not len(values):
        return math.nan, math.nan
    return float(values.mean()), float(values.max())


def age(now: int, stamp: int) -> int:
    """The one definition of a sample's age (ns): how far its ``stamp`` is behind ``now``, the time ages are
    counted from (a recording's end, a live listener's clock). Signed: negative where the stamp is ahead of
    ``now`` (a publisher's clock running ahead of the recorder's); ``age_in_words`` never shows it so."""
    return now - stamp


def age_in_words(age_ns: int, clock: str) -> str:
    """An age (``age``) as a person reads it: "0.051 s old", or where the stamp is ahead of ``clock`` (the
    clock ages are counted on), what was observed: "stamped 0.051 s ahead of the recording's clock"; an
    age is never negative."""
    if age_ns < 0:
        return f"stamped {-age_ns / NS_PER_S:.3f} s ahead of {clock}"
    return f"{age_ns / NS_PER_S:.3f} s old"


@dataclass(frozen=True)
class Disagreement:
    """How far two publishers' values of one edge are apart at the same instants: the largest translation
    (m) and rotation (degrees) between them, each with the stamp it was seen at; ``instants`` compared, and how
    far apart at each (``each_metres``, ``each_degrees``: ``beyond`` counts them)."""

    metres: float
    metres_at: int
    degrees: float
    degrees_at: int
    instants: int
    each_metres: FloatArray = field(compare=False, repr=False)
    each_degrees: FloatArray = field(compare=False, repr=False)

    def beyond(self, metres: float, degrees: float) -> int:
        """At how many of the instants compared the values are further apart than ``metres`` or ``degrees``."""
        return int(np.count_nonzero((self.each_metres > metres) | (self.each_degrees > degrees)))


def disagreement(a_stamps: Int64Array, a: FloatArray, b_stamps: Int64Array, b: FloatArray) -> Disagreement | None:
    """How far two streams of one edge's values (N x 7: translation, quaternion; stamps sorted) are apart at
    the same time: at each stamp of one within the other's span, against the other's value at that stamp,
    interpolated between its samples around it by tf2 (``_against``). None where their spans never overlap."""
    pairs = [_against(a_stamps, a, b_stamps, b), _against(b_stamps, b, a_stamps, a)]
    stamps = np.concatenate([p[0] for p in pairs])
    if not len(stamps):
        return None
    mine, theirs = np.concatenate([p[1] for p in pairs]), np.concatenate([p[2] for p in pairs])
    with np.errstate(over="ignore", invalid="ignore"):
        metres = np.nan_to_num(np.linalg.norm(mine[:, :3] - theirs[:, :3], axis=1), nan=np.inf)
    degrees = np.degrees(angle_between_many(mine[:, 3:], theirs[:, 3:]))
    far, turned = int(np.argmax(metres)), int(np.argmax(degrees))
    return Disagreement(
        float(metres[far]), int(stamps[far]), float(degrees[turned]), int(stamps[turned]), len(stamps), metres, degrees
    )


def largest_disagreement(streams: Sequence[tuple[Int64Array, FloatArray]]) -> Disagreement | None:
    """The largest ``disagreement`` between any two of several publishers' streams of one edge (sorted
    stamps, N x 7 values each), by metres then degrees; None where no two overlap in time."""
    found = [disagreement(*a, *b) for a, b in itertools.combinations(streams, 2)]
    return max((d for d in found if d is not None), key=lambda d: (d.metres, d.degrees), default=None)


def _against(
    stamps: Int64Array, values: FloatArray, other_stamps: Int64Array, other: FloatArray
) -> tuple[Int64Array, FloatArray, FloatArray]:
    """``stamps`` within ``other_stamps``' span, their values, and ``other`` at them as tf2 gives it: one
    edge's samples in a buffer, looked up in one batch (tf2's lerp and slerp). A stamp of 0 is tf2's
    "latest", not a time: not compared."""
    none = stamps[:0], values[:0], values[:0]
    inside = (stamps >= other_stamps[0]) & (stamps <= other_stamps[-1]) & (stamps != 0) if len(other_stamps) else None
    if inside is None or not inside.any():
        return none
    n = len(other_stamps)
    buffer = Buffer(cache_time=None)
    buffer.insert(
        TransformBatch(
            frame_names=("parent", "child"),
            authorities=("",),
            parent=np.zeros(n, np.int32),
            child=np.ones(n, np.int32),
            stamp=other_stamps,
            translation=np.ascontiguousarray(other[:, :3]),
            rotation=np.ascontiguousarray(other[:, 3:]),
            static=np.zeros(n, np.bool_),
            record_time=np.zeros(n, np.int64),
        )
    )
    if not buffer.has_frame("child"):  # every sample refused (tf2's rules: a NaN, an unnormalisable rotation)
        return none
    looked = buffer.lookup_many("parent", "child", stamps[inside])
    found = looked.valid
    theirs = np.concatenate([looked.translations[found], looked.rotations[found]], axis=1)
    return stamps[inside][found], values[inside][found], theirs


#: A wait (ns) shorter than this is an instant: the message and the transform it waits for were sent together,
#: the message first (the potted-plant AGV's /agv_pose, 3 us to 1.8 ms before map -> odom of its stamp).
#: tf2_ros's MessageFilter still queues such a message (it is not transformable when it arrives) and passes it
#: on the transform; a lookup as it arrives fails: the one user to act is one that does not wait.
INSTANT = NS_PER_S // 1000


def under_tick(wait_ns: float, tick: int) -> bool:
    """Whether a wait read off a clock stepping every ``tick`` ns (0: a fine one) is shorter than one step."""
    return tick > 0 and wait_ns < tick


def seconds_in_words(ns: float) -> str:
    """A figure in seconds to the millisecond, or "under 1 ms" where that would read 0.000 s though it is not 0
    (a real car's markers stamped a few microseconds after their tf were "0.000 s behind")."""
    return "under 1 ms" if 0 < ns < NS_PER_S / 2000 else f"{ns / NS_PER_S:.3f} s"


def wait_in_words(wait_ns: float, tick: int = 0) -> str:
    """A wait (ns) as a person reads it: "0.181 s", "under 1 ms" (``seconds_in_words``: the e-puck's sensors
    wait a few microseconds for a re-sent odometry), or where it was read off a clock that steps every
    ``tick`` ns (record times under use_sim_time without /clock) and is shorter than one step, what was
    observed: "under one 0.100 s tick". A wait that is not nil is never "0.000 s"."""
    if under_tick(wait_ns, tick):
        return f"under one {tick / NS_PER_S:.3f} s tick"
    return seconds_in_words(wait_ns)


def within_in_words(wait_ns: float, tick: int = 0) -> str:
    """How long the messages kept waited at most, in words: "within 0.018 s", "under 1 ms", "under one 0.100 s
    tick" (``wait_in_words``)."""
    said = wait_in_words(wait_ns, tick)
    return said if said.startswith("under") else f"within {said}"


def timeout_s(wait_ns: float, tick: int = 0) -> float:
    """The timeout (s) to set for a wait of ``wait_ns``, shown to the millisecond: a wait under 1 ms asks for
    0.001 s, never 0.000 s; one step of a clock ticking every ``tick`` ns where the wait is under it (such a
    clock cannot tell how much under)."""
    if under_tick(wait_ns, tick):
        return tick / NS_PER_S
    return max(wait_ns, NS_PER_S / 1000) / NS_PER_S if wait_ns > 0 else 0.0


@overload
def seconds(ns: float) -> float: ...
@overload
def seconds(ns: FloatArray) -> FloatArray: ...
def seconds(ns: float | FloatArray) -> float | FloatArray:
    """A figure (or figures) in ns, shown in seconds (NaN stays NaN)."""
    return ns / NS_PER_S


#: How far a transform's values may wander and still be one value held (a fixed transform re-sent on /tf, a static
#: re-published, a stamp re-sent): float rounding, a double computed again (the UR5's joints on /tf 1.3e-15 m
#: apart, the SAIL ZED's re-sends 7e-12 m, a JetAcker joint 8e-8° in Gazebo), ten times the 1e-9 m and 1e-7° of
#: it at most, never a motion (a Kobuki at rest in Gazebo drifts 7e-8 m and 2e-4° between two sends of one
#: stamp: updates, however small). The one tolerance of "the same value" wherever an edge's values are compared
#: with each other: diff's held and fixed parts, a static's values received, dynamic_on_static, static_conflict,
#: repeated stamps.
HELD_M = 1e-8
HELD_DEG = 1e-6


def apart(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """How far each value of ``b`` is from the one of ``a`` (N x 7 each): metres, and degrees of rotation."""
    with np.errstate(over="ignore"):  # values near 1e308 are apart by an infinity of metres
        metres: FloatArray = np.linalg.norm(b[:, :3] - a[:, :3], axis=1)
    return metres, np.degrees(angle_between_many(a[:, 3:], b[:, 3:]))


def held_apart(a: FloatArray, b: FloatArray) -> tuple[BoolArray, BoolArray]:
    """Whether each row of ``a`` (N x 7: translation, quaternion) is further than ``HELD_M`` from the one of ``b``
    (the same shape, or one row) in translation, and further than ``HELD_DEG`` in rotation (q and -q are one)."""
    metres, degrees = apart(a, np.broadcast_to(b, a.shape))
    return metres > HELD_M, degrees > HELD_DEG


#: ``held_parts`` compares this many samples at a time: a moving edge is told in its first chunk, a held one of
#: millions in little memory.
HELD_CHUNK = 65_536


def held_parts(values: FloatArray) -> tuple[bool, bool]:
    """Whether every row of ``values`` (N x 7) holds the first one's translation, and its rotation (``held_apart``).
    Bounds decide first where they can (a distance is at least its largest component's; a turn of a unit
    quaternion at least twice its largest component's change, either sign): a moving edge of a million samples
    is told in a few passes, its distances and angles computed only where the bounds leave it open; read
    ``HELD_CHUNK`` rows at a time, stopping once both are told."""
    t_held = q_held = True
    for start in range(0, len(values), HELD_CHUNK):
        t, q = _held_chunk(values[:1], values[start : start + HELD_CHUNK])
        t_held, q_held = t_held and t, q_held and q
        if not (t_held or q_held):
            break
    return t_held, q_held


def _held_chunk(first: FloatArray, values: FloatArray) -> tuple[bool, bool]:
    """``held_parts`` of the rows ``values`` against the row ``first``."""
    with np.errstate(over="ignore", invalid="ignore"):  # values near the largest float differ by inf: not held
        step = np.abs(values[:, :3] - first[0, :3]).max()
        q = values[:, 3:]
        change = np.minimum(np.abs(q - first[0, 3:]).max(axis=1), np.abs(q + first[0, 3:]).max(axis=1)).max()
    t_held = bool(step == 0) or bool(step <= HELD_M and not held_apart(values, first)[0].any())
    q_held = bool(change == 0) or bool(
        change <= _TURN_BOUND * math.radians(HELD_DEG) and not held_apart(values, first)[1].any()
    )
    return t_held, q_held


#: A unit quaternion whose largest component changes by ``d`` turns by at least 2d radians; with room for
#: quaternions a little off unit length, beyond ten times the tolerance a change is a turn without computing it.
_TURN_BOUND = 10.0


def held_groups(values: FloatArray) -> IntpArray:
    """Each row's value among the distinct ones of ``values`` (N x 7), numbered as they first come: a row within
    the tolerances (``held_apart``) of an earlier value is that value, not another. Rows exactly alike are
    told apart once (a static re-sent a thousand times with two values is two values to compare)."""
    distinct, first, inverse = np.unique(values, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    kind = np.full(len(distinct), -1, np.intp)
    kinds = 0
    for k in order.tolist():
        if kind[k] >= 0:
            continue
        left = np.flatnonzero(kind < 0)
        moved, turned = held_apart(distinct[left], distinct[k : k + 1])
        kind[left[~(moved | turned)]] = kinds
        kinds += 1
    return kind[inverse.reshape(-1)]
