"""``Timeline``: how a recording's clocks relate, and the one place that turns record times into ROS time.

A recording has up to three clocks: the record clock (when each message was received), the clock the
tf stamps are on, and a recorded ``/clock``. They differ on a simulation recorded without
``--use-sim-time`` (receive times on wall time, stamps on simulated time). Every figure relating stamps
to time (delays, ages, staleness, replay, ``+S``/``-S`` times) asks the timeline for ROS time at
arrival, so that it is measured against the stamps' clock or is unavailable for a stated reason.
"""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Iterable, Sequence
from functools import cached_property

import numpy as np
import numpy.typing as npt

from tftools.core import figures
from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.core.buffer import Buffer
from tftools.core.history import FROM_STATIC_TOPIC, EdgeHistory
from tftools.core.time import EPOCH_FLOOR, NS_PER_S, duration
from tftools.sources.codecs import gather
from tftools.sources.contents import ClockSamples
from tftools.sources.edge_clocks import (
    EdgeClock,
    OtherClock,
    ahead_said,
    clock_groups,
    edge_clock,
    other_clocks,
    stamp_groups,
    stamp_medians,
)
from tftools.values import value

#: An edge's delay where its stamps are on another clock than its arrivals' (``Timeline.on_other_clock``): the one
#: wording of ``monitor`` (text and JSON) and ``report``.
OTHER_CLOCK = "not measurable: another clock"
#: Why a recording's span is its tf's stamps' (``Timeline.stamped``): the words every command says it in.
NO_RECORD_CLOCK = "the record times are no clock"
#: Two clocks more than this apart (the median of arrival minus stamp) are different clocks, not a delay.
SAME_CLOCK = 10 * NS_PER_S
#: A clock that ticks in steps up to this long measures delays; a coarser one (a /clock at 10 Hz, or at
#: rosbag play's 100 Hz) lags ROS time by up to a step, more than tf's delays, which it cannot measure.
FINE_STEP = NS_PER_S // 1000
#: ...unless the delays read off it reach this many of its steps: then each is measured to a step (an Ignition
#: run's /clock at 333 Hz, 3 ms steps, under delays of -12 to +21 ms).
STEPS_MEASURED = 3


def seconds_since(origin: int, time: int) -> float | None:
    """Seconds from ``origin`` to ``time`` on the stamps' clock; None where ``time`` is on another time
    base (epoch time against time since boot or a simulation's start): no plausible offset."""
    if not figures.same_base(origin, time):
        return None
    return (time - origin) / NS_PER_S


class Reference(enum.Enum):
    """What ROS time at a message's arrival is read from."""

    CLOCK = "/clock"  # the last /clock message recorded before it, as a node with use_sim_time saw it
    RECORD = "record clock"  # its record time: the tf stamps are on the record clock
    NONE = "none"  # neither: the stamps are on a clock the recording did not keep


class KeptArrivals:
    """The record times of the frames a replay measures on their own record clock (``Timeline.record_clocked`` of
    the recording replayed: a device's beside a simulation on /clock), kept by the replay's first pass: the
    replay's record times are on /clock, whose ticks cannot time them. Per frame, its stamps in order, their record
    times and their replay times; ``step``: how coarse the record times are (ns)."""

    def __init__(self, frames: dict[str, tuple[Int64Array, Int64Array, Int64Array]], step: int) -> None:
        self.frames = frames
        self.step = step

    def at(self, child: str, stamps: Int64Array) -> tuple[Int64Array, BoolArray]:
        """The record times of ``child``'s transforms stamped ``stamps``, and which were kept."""
        kept, records, _ = self.frames[child]
        if not len(kept):
            return np.zeros(len(stamps), np.int64), np.zeros(len(stamps), bool)
        index = np.minimum(np.searchsorted(kept, stamps), len(kept) - 1)
        found = kept[index] == stamps
        return np.where(found, records[index], 0), found

    def window(self, start: int | None, end: int, record_end: int) -> tuple[int | None, int]:
        """A window of replay time (``start`` None: open) as record times: from the first arrival kept that played
        in it to just before the first that played after it (``record_end`` where none did)."""
        played = np.concatenate([p for _, _, p in self.frames.values()])
        records = np.concatenate([r for _, r, _ in self.frames.values()])
        after = records[played > end]
        last = int(after.min()) - 1 if len(after) else record_end
        if start is None:
            return None, last
        within = records[played >= start]
        return (int(within.min()) if len(within) else last + 1), last


@value
class Timeline:
    """A recording's clocks: which one the tf stamps are on, and ROS time at any record time."""

    reference: Reference
    clock: ClockSamples
    record_start: int
    record_end: int
    tf_start: int  # the tf data's own span: its first and last dynamic stamp (statics' if none)
    tf_end: int
    edges: tuple[EdgeClock, ...] = ()
    reason: str = ""  # why ROS time at arrival is unavailable (reference NONE)
    same_clock: int = SAME_CLOCK  # the ``clock`` threshold (ns): behind the reference by more, another clock
    record_step: int = 0  # how coarse record times are (ns): the step of the /clock they were read off, 0 if fine
    full_tf: tuple[int, int] | None = None  # every frame's span, where ``tf_start``/``tf_end`` leave some out
    played_estimate: bool = False  # a replay's without a reference: its record times are the replay's clock
    replayed: bool = False  # a replay's (``played``): ``Playback`` gave every record time a value, 0 or less too
    unclocked: int | None = None  # a replay's: the time ``Playback`` gave messages recorded before any /clock
    kept: KeptArrivals | None = dataclasses.field(default=None, compare=False)  # a replay's record-clocked frames'

    @property
    def stamps_span(self) -> tuple[int, int]:
        """The first and last stamp of every frame, those on another clock than the reference's too."""
        return self.full_tf or (self.tf_start, self.tf_end)

    @property
    def origin(self) -> int:
        """The one origin of times shown relative to the recording (``+S``): its tf's first stamp."""
        return self.tf_start

    def since_origin(self, time: int) -> float | None:
        """Seconds from ``origin`` to ``time`` (``seconds_since``); None where ``time`` is further outside the
        tf span than the recording lasted (and ``same_clock``): on another clock (a replay's, a week behind),
        whose distance from the origin is no moment of the recording."""
        reach = max(self.record_end - self.record_start, self.same_clock)
        if self.record_start > 0 and not self.tf_start - reach <= time <= self.tf_end + reach:
            return None
        return seconds_since(self.origin, time)

    @cached_property
    def clocks(self) -> list[list[EdgeClock]]:
        """The frames grouped by the clock their stamps are on: by their offsets from the record clock
        (``clock_groups``), or where the record times time nothing (``record_clock_void``) by their stamps alone
        (``stamp_groups``: offsets from no clock are the stamps themselves, and parted two detections on one clock
        seen 20 s apart). The one grouping of a question's span (``span_of``, ``+S``), of ages (``own_clock_ends``),
        of the clocks beside the tf span's (``other_clocks``) and of the tf span without a reference."""
        if not self.edges:
            return []
        grouped = stamp_groups if self.record_clock_void else clock_groups
        return grouped(self.edges, self.same_clock)

    @cached_property
    def other_clocks(self) -> tuple[OtherClock, ...]:
        """The clocks of stamps outside the tf span, beside the span's own (``edge_clocks.other_clocks``)."""
        return other_clocks(self.clocks, self.tf_start, self.tf_end)

    def span_of(self, children: Iterable[str]) -> tuple[int, int]:
        """The tf span on the clock of the frames a question is about (``children``): the recording's
        (``tf_start``, ``tf_end``) where all of them are stamped within it or none tells its clock; else the
        span of every frame stamped on the clock (``clocks``) of one that is not (a chain on simulated time in a
        recording whose other frames are on wall time: ``+S`` counts from its own first stamp; a chain
        through a replay's frame a week behind, beside live frames: from the replay's, where alone every
        edge of it has data)."""
        wanted = set(children)
        near = self.same_clock
        off = [
            e
            for e in self.edges
            if e.child in wanted and not self.tf_start - near <= e.median_stamp <= self.tf_end + near
        ]
        if not off:
            return self.tf_start, self.tf_end
        group = next(g for g in self.clocks if off[0] in g)
        return min(e.first_stamp for e in group), max(e.last_stamp for e in group)

    def arrival_span(self, children: Iterable[str]) -> tuple[int, int]:
        """``span_of``, as far as a window of arrivals (``arrival``: ``monitor``'s ``--start``/``--end``) can hold
        them: without a reference, widened to where a replay plays the recording (its record span moved by
        ``replay_shift``), which a simulation slower than real time stretches past its stamps' (the JetAcker's,
        stamped over 4.25 s, plays over 62.8 s: +21 s into it holds transforms)."""
        span = self.span_of(children)
        whole = span == (self.tf_start, self.tf_end)
        if not whole or self.reference is not Reference.NONE or self.record_start <= 0 or self.record_clock_void:
            return span
        return min(span[0], self.tf_start), max(span[1], self.record_end - self.replay_shift)

    @cached_property
    def own_clock_ends(self) -> dict[str, int]:
        """For each frame stamped outside the recording's tf span (a chain on simulated time among frames on
        wall time), its own clock at the recording's end: where its ages count from. That is the newest stamp on
        that clock moved on by how long its frame has been silent (``figures.silence``), so that a replay's
        frame that stopped 2.5 s before the end is 2.5 s old, as the monitor's silence and wtf's ``stale`` say,
        not as new as the last stamp its own clock had. Frames within the span are not listed, nor those on the
        reference clock from the future (stamped hours ahead of it: their age is negative, and said so). A clock
        is one of ``clocks``."""
        near = self.same_clock
        ahead = self.reference is not Reference.NONE
        off = {
            e.child
            for e in self.edges
            if not self.tf_start - near <= e.median_stamp <= self.tf_end + near
            and not (ahead and e.child not in self.off_reference)
        }
        if not off:
            return {}
        ends: dict[str, int] = {}
        for group in self.clocks:
            end = max(e.last_stamp + (figures.silence(e.last_record, self.record_end) or 0) for e in group)
            ends.update((e.child, end) for e in group if e.child in off)
        return ends

    @cached_property
    def clock_step(self) -> int:
        """How often ``/clock`` ticked (ns): the median of its positive steps; 0 without /clock."""
        steps = np.diff(self.clock.clock)
        steps = steps[steps > 0]
        return int(np.median(steps)) if len(steps) else 0

    @property
    def resolution(self) -> int:
        """How coarse ROS time at arrival is (ns): it lags the true time by up to this. The step of
        ``/clock`` under it, the record clock's otherwise (0: fine)."""
        return self.clock_step if self.reference is Reference.CLOCK else self.record_step

    @property
    def delays_measured(self) -> bool:
        """Whether delays (and a chain's net delay) can be measured: ROS time at arrival is known, on a
        clock finer than ``FINE_STEP``, or read off a coarser one under delays of ``STEPS_MEASURED`` of its
        steps or more (the frames on the reference clock: the largest 95th percentile of arrival - stamp)."""
        return self.available and (self.resolution <= FINE_STEP or self._reach >= STEPS_MEASURED * self.resolution)

    @cached_property
    def _reach(self) -> int:
        against_clock = self.reference is Reference.CLOCK
        on = [e for e in self.edges if e.child not in self.off_reference]
        return max((e.reach_clock if against_clock else e.reach_record for e in on), default=0)

    @cached_property
    def record_clocked(self) -> frozenset[str]:
        """The frames off a ``/clock`` reference whose stamps keep time with the record clock (a real device's
        beside a simulation on /clock): each edge's delay is arrival minus stamp on its stamps' clock, so theirs
        are measured against their record times, where those are no coarser than ``FINE_STEP``."""
        if self.kept is not None:
            return frozenset(self.kept.frames)
        if self.reference is not Reference.CLOCK or self.record_step > FINE_STEP or self.record_clock_void:
            return frozenset()
        return frozenset(
            e.child for e in self.edges if e.child in self.off_reference and _in_step(e, False, self.same_clock)
        )

    def delays_measured_for(self, child: str) -> bool:
        """Whether the delays of ``child``'s transforms can be measured: on the record clock beside a /clock
        reference (``record_clocked``), else as ``delays_measured`` says."""
        return child in self.record_clocked or self.delays_measured

    def resolution_of(self, child: str) -> int:
        """How coarse ROS time at arrival of ``child``'s transforms is (ns): ``resolution``, or the record
        clock's where ``child`` is ``record_clocked``."""
        if child not in self.record_clocked:
            return self.resolution
        return self.kept.step if self.kept is not None else self.record_step

    def record_window(self, start: int | None, end: int) -> tuple[int | None, int]:
        """A window of ROS time at arrival read off /clock (``start`` None: open) as record times: those that
        ``ros_time`` places in it (the inverse of ``clock_at``), for frames measured on the record clock
        (``record_clocked``); on a replay, a window of its clock (``KeptArrivals.window``)."""
        if self.kept is not None:
            return self.kept.window(start, end, self.record_end)
        ticks = self.clock
        after = int(np.searchsorted(ticks.clock, end, side="right"))
        last = int(ticks.record_time[after]) - 1 if after < len(ticks) else self.record_end
        if start is None:
            return None, last
        first = int(np.searchsorted(ticks.clock, start, side="left"))
        return (int(ticks.record_time[first]) if first < len(ticks) else last + 1), last

    @property
    def delays_anywhere(self) -> bool:
        """Whether some edge's delays can be measured (``delays_measured_for``)."""
        return self.delays_measured or bool(self.record_clocked)

    @property
    def delays_unavailable(self) -> str:
        """Why delays cannot be measured ("" where they can); where some frames' can (``record_clocked``),
        why the others' cannot, and which are measured."""
        if not self.available:
            return self.reason
        if self.delays_measured:
            return ""
        step = self.resolution / NS_PER_S
        ticks = f"ticks every {step:.3f} s ({1 / step:.0f} Hz)"
        if self.reference is Reference.CLOCK:
            said = f"ROS time at arrival is read off {self.clock.topic or '/clock'}, which {self._clock_ticks}"
        else:
            said = f"arrivals were timed by /clock (ROS time under use_sim_time), which {ticks}"
        why = f"{said}: delays shorter than that cannot be measured"
        if self.record_clocked:
            frames = ", ".join(sorted(self.record_clocked))
            why += f"; those of {frames} (stamped on the record clock) are measured against their record times"
        return why

    @property
    def _clock_ticks(self) -> str:
        """How /clock ticks, on its two axes: the step of simulated time (``clock_step``, what delays are read
        to), and the ticks' rate on the record clock (a simulation slower than real time: Gazebo's 0.095 s
        steps at 9.8 Hz of wall time)."""
        step = self.clock_step / NS_PER_S
        rate = figures.rate_hz(len(self.clock), figures.record_span(self.clock.record_time))
        return f"ticks every {step:.3f} s of sim time" + (f" ({rate:.1f} Hz of record time)" if rate else "")

    def on_other_clock(self, children: Iterable[str]) -> tuple[str, ...]:
        """Of ``children``, the frames whose delays no clock of the recording measures: stamped on another clock
        than the one that timed their arrival (``off_reference``, not ``record_clocked``: a Gazebo robot stamped
        from zero beside a device on the wall clock), where arrival minus stamp is how far the clocks are apart."""
        return tuple(c for c in children if c in self.off_reference and c not in self.record_clocked)

    def other_clock_delays(self, children: Iterable[str]) -> str:
        """Why the delays of ``children`` stamped on another clock (``on_other_clock``) are not shown ("" where
        none is): the one wording of ``monitor`` (text and JSON), whole or replayed."""
        other = self.on_other_clock(children)
        if not other:
            return ""
        timed = "the record clock" if self.reference is Reference.RECORD else self.clock.topic or "/clock"
        frames = ", ".join(sorted(other))
        return (
            f"those of {frames} cannot be measured: stamped on another clock than {timed}, which timed their "
            "arrival (arrival minus stamp is how far the two clocks are apart, not a delay)"
        )

    @cached_property
    def off_reference(self) -> frozenset[str]:
        """The frames stamped on another clock than the reference (none without a reference): more than
        ``same_clock`` behind it, or on another time base (epoch against boot or simulated time). Stamps
        ahead on the same time base are on the reference clock, from the future: a publisher's problem."""
        if self.reference is Reference.NONE:
            return frozenset()
        against_clock = self.reference is Reference.CLOCK
        return frozenset(e.child for e in self.edges if not e.agrees(against_clock, self.same_clock))

    @property
    def on_several_bases(self) -> frozenset[str]:
        """The frames whose stamps take turns between time bases (``EdgeClock.bases``: a replay's /tf beside a live
        publisher's, a week apart), which no one stretch of stamps holds."""
        return frozenset(e.child for e in self.edges if e.bases > 1)

    @property
    def beside_span(self) -> frozenset[str]:
        """The frames stamped on a clock beside the tf span's (``other_clocks``), on the reference's time base or
        not: a machine's 5.8 h ahead of the recorder's (the SAIL boat's EKF and IMU), a replay's a week behind."""
        children = {e.child for e in self.edges}
        return frozenset(f for other in self.other_clocks for f in other.frames if f in children)

    def within(self, same_clock: int) -> Timeline:
        """This recording's timeline (``timeline_of``'s) with another ``clock`` threshold (ns), its reference
        chosen again by it."""
        reference, reason = _reference(self.edges, self.clock, same_clock, self.record_start, self.record_end)
        return _spanned(dataclasses.replace(self, reference=reference, reason=reason, same_clock=same_clock))

    @property
    def record_clock_void(self) -> bool:
        """Whether the record times are no clock at all (``no_record_clock``)."""
        return no_record_clock(self.edges, self.record_start, self.record_end)

    @property
    def stamped(self) -> tuple[int, int] | None:
        """tf's first and last stamp (``tf_start``, ``tf_end``) where the record times are no clock
        (``record_clock_void``): the only span such a recording tells, which wtf's header, view-frames' legend and
        report's facts give instead of a record span of nanoseconds; None where the record times are a clock."""
        return (self.tf_start, self.tf_end) if self.record_clock_void else None

    @property
    def available(self) -> bool:
        """Whether ROS time at arrival, and so delays, ages and staleness, can be measured."""
        return self.reference is not Reference.NONE

    @property
    def end(self) -> int:
        """ROS time at the recording's end; without a reference, the newest tf stamp (the best guess). A
        coarse clock lags by up to its ``resolution``: the newest stamp within that is the better reading."""
        if self.reference is Reference.NONE:
            return self.tf_end
        times, known = self.ros_time(np.array([self.record_end], np.int64))
        if not known[0]:
            return self.tf_end
        end = int(times[0])
        return self.tf_end if end < self.tf_end <= end + self.resolution else end

    def ros_time(self, record_times: npt.ArrayLike) -> tuple[Int64Array, BoolArray]:
        """ROS time (on the stamps' clock) when messages recorded at ``record_times`` arrived, and
        where that is known (a record time is known, and under /clock, a /clock had been recorded)."""
        records = np.asarray(record_times, np.int64)
        if self.reference is Reference.RECORD or self.played_estimate:
            known = (records > 0) | self.replayed
            return records, known if self.unclocked is None else known & (records != self.unclocked)
        if self.reference is Reference.NONE:
            return np.zeros(len(records), np.int64), np.zeros(len(records), bool)
        return clock_at(self.clock, records)

    def silence(self, last_arrival: int, end: int) -> int:
        """How long (ns) before ``end`` (the recording's, a record time) a stream last arrived at ``last_arrival``:
        in ROS time where this timeline reads it at both (under /clock: a simulation slowed or paused at the end
        kept tf fresh on its own time, as a listener on it sees), else on the record clock."""
        ros, known = self.ros_time(np.array([last_arrival, end], np.int64))
        return int(ros[1] - ros[0]) if known.all() else end - last_arrival

    def counted_at(self, record_times: Int64Array, stamps: Int64Array) -> tuple[Int64Array, BoolArray]:
        """When messages recorded at ``record_times`` (stamped ``stamps``) arrived on the clock a listener counts
        them on, and which are timed: tf_monitor rates a publisher by ``ros::Time::now()`` at each callback, the
        node's clock. That is ROS time at arrival where the recording has a reference (``ros_time``); without
        one (a simulation recorded without /clock), the record clock, a replay's clock whatever its settings
        (``ros2 bag play`` plays on it, ``--clock`` publishes it), moved onto the stamps' as a replay plays it
        (``replay_shift``), so that a window of stamps holds what a replay's does: the JetAcker's 3,376 /tf
        messages arrived over 62.8 s of it, not over the 4.25 s of simulated time they are stamped in. Where the
        record times are no clock (``record_clock_void``) no arrival is known: the stamps, each time base apart
        (``figures.rate_of``). ``arrival`` less the stamps of messages whose time is unknown."""
        if self.available or self.played_estimate:
            return self.ros_time(record_times)
        if self.record_clock_void:
            return stamps, np.ones(len(stamps), bool)
        records = np.asarray(record_times, np.int64)
        return records - self.replay_shift, records > 0

    def arrival(self, stamps: Int64Array, record_times: Int64Array) -> Int64Array:
        """The one axis of when transforms and messages arrived, as a replay plays them: where a window of arrivals
        (``monitor``'s ``--start``/``--end``, its ``--play`` and live windows) selects them and a silence in it ends.
        It is when they arrived on the clock they are counted on (``counted_at``), in a replay when they played,
        their stamps where that is unknown. Without a reference that is the record clock moved onto the stamps
        (``replay_shift``): +S is S seconds into the recording, as ``ros2 bag play --start-offset`` counts them, not
        the stamps; a whole read's window holds what its replay's does (the JetAcker's simulation at 0.067x real
        time: 33 samples of odom -> base_footprint stamped in its +1 to +2 s, 2 arrived 1 to 2 s into the replay,
        with the 54 /tf messages recorded then). What sits on the stamps' clock: ``arrival_on_stamps``."""
        counted, timed = self.counted_at(record_times, stamps)
        return np.where(timed | self.replayed, counted, stamps)

    def arrival_on_stamps(self, stamps: Int64Array, record_times: Int64Array) -> Int64Array:
        """Where transforms that arrived sit on the stamps' clock, what a finding's times (``Finding.first_time``:
        a key tf is looked up at) and the report's timelines place them by: ``arrival`` where the recording has
        a reference or is a replay; else their stamps, for without a reference no time of arrival is on the
        stamps' clock (``arrival`` is then the record clock, as a replay plays it: the JetAcker's 0.067x
        simulation arrived over 63.4 s of it, stamped over 4.25 s)."""
        if not self.places_arrivals:
            return stamps
        return self.arrival(stamps, record_times)

    @property
    def places_arrivals(self) -> bool:
        """Whether a time of arrival sits on the stamps' clock (``arrival_on_stamps``): with a reference, or in a
        replay."""
        return self.reference is not Reference.NONE or self.replayed

    def measurable(
        self, child: str, record_times: Int64Array, flags: UInt8Array, stamps: Int64Array | None = None
    ) -> tuple[Int64Array, BoolArray]:
        """ROS time at arrival of transforms of ``child`` (``flags``: ``EdgeHistory.flags``), and which have a
        delay: their arrival is known, the frame is on the reference clock (or ``record_clocked``: then its
        record times are its arrivals), they came on /tf (a sample
        latched on /tf_static keeps an old stamp by design), and, given their ``stamps``, they are on the
        time base of the clock they arrived on (``figures.nearest_base``: not a replay's a week behind) and not
        stamped on a clock running ahead of it (``figures.clocks_apart``: a machine 5.8 h ahead)."""
        if child in self.record_clocked and self.kept is not None:  # a replay's: the record times kept
            times, known = self.kept.at(child, stamps) if stamps is not None else (record_times, record_times < 0)
        elif child in self.record_clocked:
            times, known = record_times, record_times > 0
        else:
            times, known = self.ros_time(record_times)
            if child in self.off_reference:
                return times, np.zeros(len(times), bool)
        measured = known & ((flags & FROM_STATIC_TOPIC) == 0)
        if stamps is not None and measured.any():
            read = times[measured] - stamps[measured]
            span = figures.record_span(record_times[measured])
            measured[measured] = figures.nearest_base(read, span) & ~figures.clocks_apart(read, self.same_clock)
        return times, measured

    def delays(self, child: str, stamps: Int64Array, record_times: Int64Array, flags: UInt8Array) -> Int64Array:
        """ROS time at arrival minus stamp (ns) of the ``measurable`` transforms (``delays_of``)."""
        return self.delays_of(child, stamps, record_times, flags)[0]

    def delays_of(
        self, child: str, stamps: Int64Array, record_times: Int64Array, flags: UInt8Array
    ) -> tuple[Int64Array, BoolArray]:
        """The delays (``figures.delays``, ROS time at arrival read off a clock as coarse as ``resolution_of``)
        of the ``measurable`` transforms, and which those are; none where ``delays_measured_for`` is false
        (``delays_unavailable`` says why)."""
        if not self.delays_measured_for(child):
            return np.zeros(0, np.int64), np.zeros(len(stamps), bool)
        times, measured = self.measurable(child, record_times, flags, stamps)
        return figures.delays(times[measured], stamps[measured], self.resolution_of(child)), measured

    def played(self, kept: KeptArrivals | None = None) -> Timeline:
        """The timeline of this recording's replay, whose record times are ``Playback``'s: on the
        stamps' clock (as coarse as ROS time at arrival was), or still without a reference (delays stay
        unknown; playback only estimates: ROS time at arrival is the replay's clock, so that a window of it
        holds what was played in it, not what is stamped in it). ``kept``: the record times of the
        ``record_clocked`` frames, whose delays the replay measures on them as a whole read does."""
        if self.reference is Reference.NONE:
            unknown = self.unknown_played - self.replay_shift
            return dataclasses.replace(self, played_estimate=True, replayed=True, unclocked=unknown)
        edges = tuple(
            dataclasses.replace(
                e,
                offset_record=e.offset(self.reference is Reference.CLOCK) or 0,
                offset_clock=None,
                reach_record=e.reach_clock if self.reference is Reference.CLOCK else e.reach_record,
            )
            for e in self.edges
        )
        return dataclasses.replace(
            self,
            reference=Reference.RECORD,
            clock=ClockSamples.empty(),
            edges=edges,
            record_step=self.resolution,
            replayed=True,
            unclocked=unclocked_time(self.clock) if self.reference is Reference.CLOCK else self.unknown_played,
            kept=kept if kept is not None and kept.frames else None,
        )

    @property
    def replay_shift(self) -> int:
        """How far a replay without a reference moves record times back onto the stamps' clock (``Playback``): so
        that the recording's start plays at the tf data's first stamp, and +S (``since_origin``) of an arrival is S
        seconds into the replay, as ``ros2 bag play`` plays it; 0 with a reference. Not the frames' median offset: a
        simulation slower than real time drifts from the record clock, and the JetAcker's (0.067x) put its start
        30.7 s before its first stamp."""
        return 0 if self.reference is not Reference.NONE else self.record_start - self.tf_start

    @property
    def unknown_played(self) -> int:
        """The record time a replay gives messages recorded at no known time (a record time of 0 or less: an
        MCAP's log time 0), before its shift: 1 ns before the first known one, so that they play first and their
        arrival stays unknown, as a whole read has it (``ros_time``: the Franka teleoperation's /tf message logged
        at 0, played with the first one logged at 1748331282.8 s, made its 4 messages over 1.5 s 5: 2.65 msgs/s
        for 1.99)."""
        return self.record_start - 1

    def describe(self) -> str:
        """One line: which clock the stamps are on, and what cannot be measured if none."""
        coarse = f"; {self.delays_unavailable}" if self.delays_unavailable else ""
        if self.reference is Reference.CLOCK:
            measured = "ages" if coarse else "delays and ages"
            return f"tf stamps on {self.clock.topic} (simulated time); {measured} measured against it{coarse}"
        if self.reference is Reference.RECORD:
            return f"tf stamps on the record clock{coarse}{ahead_said(self.other_clocks, self.origin, self.same_clock)}"
        return self.reason


def unclocked_time(clock: ClockSamples) -> int | None:
    """The replay time of messages recorded before the first of ``clock``'s samples (or at no known time): 1 ns
    before its value, so that they play first and their ROS time at arrival stays unknown, as a whole read has it
    (``Timeline.ros_time``: a Webots robot's 96 transforms before the recorder heard /clock, all played at its
    first value, were 147 messages in 1.0 s of the replay: 143 msgs/s for 50)."""
    return int(clock.clock[0]) - 1 if len(clock) else None


class Playback:
    """Record times moved onto the stamps' clock for a replay, never decreasing, part after part of a
    recording (all of it at once, or a stream's windows): ROS time at arrival (before the first /clock,
    ``unclocked_time``); without a reference, shifted so that the recording's start plays at the first stamp
    (``Timeline.replay_shift``: the recording kept no clock of the stamps)."""

    def __init__(self, timeline: Timeline) -> None:
        self.reference = timeline.reference
        self._clock = timeline.clock  # the samples up to the next part: all of them, or the last one heard
        self._unclocked = unclocked_time(timeline.clock) or 0  # before the first /clock: its value less 1 ns
        self._shift = timeline.replay_shift
        self._floor = np.iinfo(np.int64).min
        self._unknown = timeline.unknown_played  # a record time of 0 (unknown, an MCAP's log time 0) plays first

    def heard(self, clock: ClockSamples) -> None:
        """The /clock samples recorded since the last part (of a stream: a window's)."""
        self._clock = self._clock.continued(clock)

    def moved(self, record_times: Int64Array) -> Int64Array:
        """The replay times of the next part's ``record_times``."""
        records = np.asarray(record_times, np.int64)
        if len(records) and self.reference is not Reference.CLOCK and records.min() <= 0:
            records = np.where(records > 0, records, self._unknown)
        if self.reference is Reference.RECORD or not len(records):
            return records
        if self.reference is Reference.NONE:
            return records - self._shift
        times, known = clock_at(self._clock, records)
        times = np.maximum.accumulate(np.maximum(np.where(known, times, self._unclocked), self._floor))
        self._floor = int(times[-1])
        return times


#: The timeline of a live buffer or a replay: record (receive) times are ROS time.
ON_RECORD_CLOCK = Timeline(Reference.RECORD, ClockSamples.empty(), 0, 0, 0, 0)


def clock_at(clock: ClockSamples, record_times: Int64Array) -> tuple[Int64Array, BoolArray]:
    """The value of the last ``clock`` message recorded at or before each record time (ROS time as
    ``ros::Time::now()`` gave it then), and where there was one."""
    if not len(clock):
        return np.zeros(len(record_times), np.int64), np.zeros(len(record_times), bool)
    index = np.searchsorted(clock.record_time, record_times, side="right") - 1
    known = (index >= 0) & (record_times > 0)
    return np.where(known, clock.clock[np.maximum(index, 0)], 0), known


def timeline_of(
    buffer: Buffer, clock: ClockSamples, record_start: int, record_end: int, record_step: int = 0
) -> Timeline:
    """The timeline of a recording read into ``buffer``, with its recorded ``clock`` (``timeline_from``);
    ``record_step``: how coarse its record times are, where its source knows (a live system on /clock)."""
    edges = tuple(edge_clock(*arrivals) for arrivals in clocked_arrivals(buffer, clock))
    if record_start <= 0 < record_end:  # some messages' record times unknown (0): the span of the known ones
        record_start = _first_known(buffer, clock, record_start)
    tf = tf_span(stamp_spans(buffer), record_start, record_end)
    if not record_step and not records_on_clock(clock):
        histories = [h for _, h in buffer.histories()]
        if shared_ticks(histories) >= SHARED_TICKS:  # else no grid, and the whole read's times need no sorting
            record_step = record_grid(np.concatenate([clock.record_time, *(h.record_times for h in histories)]))
    return timeline_from(edges, clock, record_start, record_end, tf, record_step)


#: Record times on one grid (``record_grid``): at least this many distinct ones, ``FINE_STEP`` or more apart.
GRID_MIN_TIMES = 15
#: Samples of one edge with other stamps recorded at one instant, in pairs: no wall clock gives this many.
SHARED_TICKS = 5


class TickedGrid:
    """The step of the clock the record times were read off (``record_grid``), where they show one: on one
    grid, and samples of one edge with other stamps recorded at the same instant (received within one tick);
    learnt part after part in record order (a stream's windows: Stage's 100 ms ticks, which its replay missed,
    read whole or not), in memory that does not grow with the recording."""

    def __init__(self) -> None:
        self.shared = 0  # samples of one edge with other stamps recorded at one instant, in pairs
        self._distinct = 0  # distinct known record times
        self._last: int | None = None  # the latest of them
        self._least = 0  # the smallest step between them (0: none yet)
        self._common = 0  # the greatest common divisor of those steps

    def add(self, clock_records: Int64Array, histories: Sequence[EdgeHistory]) -> None:
        """The record times of a part's /clock messages and of its edges' samples (``histories``)."""
        self.shared += shared_ticks(histories)
        times = np.concatenate([clock_records, *(h.record_times for h in histories)])
        distinct = gather.distinct(times[times > 0])
        if self._last is not None:
            distinct = np.concatenate(([self._last], distinct[distinct > self._last]))
        if len(distinct) > 1:
            steps = np.diff(distinct)
            least = int(steps.min())
            self._least = min(self._least, least) if self._least else least
            self._common = int(np.gcd.reduce(np.concatenate(([self._common], steps))))
        self._distinct += len(distinct) - (self._last is not None)
        if len(distinct):
            self._last = int(distinct[-1])

    def step(self) -> int:
        """The grid's step (ns), or 0: too few samples shared a tick, or record times as fine as a wall clock's."""
        return _grid_step(self._distinct, self._least, self._common) if self.shared >= SHARED_TICKS else 0


def shared_ticks(histories: Sequence[EdgeHistory]) -> int:
    """Samples of one edge with other stamps recorded at one instant (received within one tick), in pairs."""
    return sum(_shared(h.record_times, h.stamps) for h in histories)


def _shared(record_times: Int64Array, stamps: Int64Array) -> int:
    """Consecutive samples recorded at one instant with other stamps (compared, not subtracted)."""
    return int(np.count_nonzero((record_times[1:] == record_times[:-1]) & (stamps[1:] != stamps[:-1])))


def record_grid(record_times: Int64Array) -> int:
    """The step (ns) of the grid on which every known record time (tf's and /clock's) lies, where there is
    one of at least ``FINE_STEP``: a recorder under use_sim_time reads them off /clock, which it need not
    record (Stage's ticks every 100 ms: messages received within one tick share a record time, the next
    skips one); 0 for record times as fine as a wall clock's."""
    distinct = gather.distinct(record_times[record_times > 0])
    if len(distinct) < 2:
        return 0
    steps = np.diff(distinct)
    return _grid_step(len(distinct), int(steps.min()), int(np.gcd.reduce(steps)))


def _grid_step(distinct: int, least: int, common: int) -> int:
    """``least``, the smallest of the steps between ``distinct`` record times, where it is the grid's: every step a
    multiple of it (``common``, their greatest common divisor, is it), enough times, and ``FINE_STEP`` or more."""
    return least if distinct >= GRID_MIN_TIMES and least >= FINE_STEP and common == least else 0


def _first_known(buffer: Buffer, clock: ClockSamples, otherwise: int) -> int:
    """The earliest known (positive) record time of ``buffer``'s transforms and the ``clock`` messages."""
    known = [t[t > 0] for t in (clock.record_time, *(h.record_times for _, h in buffer.histories()))]
    return min((int(t.min()) for t in known if len(t)), default=otherwise)


def records_on_clock(clock: ClockSamples) -> bool:
    """Whether the record clock is ``/clock`` itself (recorded with use_sim_time): most /clock messages
    recorded at exactly the time they carry, or the one before them carried (the recorder's ROS time)."""
    if len(clock) < 2:
        return False
    records = clock.record_time[1:]
    return bool(np.mean((records == clock.clock[1:]) | (records == clock.clock[:-1])) >= 0.5)


def _spanned(timeline: Timeline) -> Timeline:
    """``timeline`` with its tf span made plausible (``_plausible``)."""
    start, end = _plausible(timeline)
    return dataclasses.replace(timeline, tf_start=start, tf_end=end)


def _plausible(timeline: Timeline) -> tuple[int, int]:
    """The tf span of the frames on the reference clock (without one, of the most frames agreeing with one
    another), where other frames are stamped on another clock: the full span otherwise. Frames stamped further
    ahead of the reference than ``same_clock`` are on it (from the future: ``off_reference`` leaves them in)
    but out of the span where some frame keeps time with it: a machine 5.8 h ahead of the recorder's (the
    SAIL vehicle's EKF beside its ZED) is no 5.8 h of the recording, and its stamps no ``+20881.5 s``."""
    edges = timeline.edges
    if timeline.reference is Reference.NONE:
        on = [e.child for e in max(timeline.clocks, key=len)] if edges else []  # the most frames on one clock
    else:
        against_clock = timeline.reference is Reference.CLOCK
        following = [e for e in edges if e.child not in timeline.off_reference]
        in_step = [e.child for e in following if _in_step(e, against_clock, timeline.same_clock)]
        on = in_step or [e.child for e in following]
    if not on or (len(on) == len(edges) and not any(e.elsewhere for e in edges)):
        return timeline.stamps_span
    chosen = [e for e in edges if e.child in set(on)]
    return min(e.first_stamp for e in chosen), max(e.last_stamp for e in chosen)


def _in_step(edge: EdgeClock, against_clock: bool, same_clock: int) -> bool:
    """Whether a frame's stamps keep time with the reference: neither behind it nor ahead by more than
    ``same_clock``."""
    offset = edge.offset(against_clock)
    return offset is not None and abs(offset) <= same_clock


def timeline_from(
    edges: tuple[EdgeClock, ...],
    clock: ClockSamples,
    record_start: int,
    record_end: int,
    tf: tuple[int, int],
    record_step: int = 0,
) -> Timeline:
    """A recording's timeline from how its frames relate to its clocks (``edges``) and its tf's span: on
    ``/clock`` when some frame's stamps follow it, else on the record clock when some frame's follow that,
    else on none (the reason says why); frames that follow neither are ``off_reference``, and the tf span
    is theirs only where no frame is on the reference (a span across two clocks is no span). Record times
    read off /clock (recorded with use_sim_time) are as coarse as its steps."""
    reference, reason = _reference(edges, clock, SAME_CLOCK, record_start, record_end)
    timeline = Timeline(reference, clock, record_start, record_end, tf[0], tf[1], edges, reason, full_tf=tf)
    if not record_step and records_on_clock(clock):
        record_step = timeline.clock_step
    return _spanned(dataclasses.replace(timeline, record_step=record_step))


def _reference(
    edges: tuple[EdgeClock, ...], clock: ClockSamples, same_clock: int, record_start: int, record_end: int
) -> tuple[Reference, str]:
    if no_record_clock(edges, record_start, record_end):
        return Reference.NONE, _why_no_record_clock(edges, record_start, record_end)
    if any(e.agrees(True, same_clock) for e in edges):
        return Reference.CLOCK, ""
    if any(e.agrees(False, same_clock) for e in edges) or not edges:
        return Reference.RECORD, ""
    return Reference.NONE, _why_none(edges, clock)


def no_record_clock(edges: Sequence[EdgeClock], record_start: int, record_end: int) -> bool:
    """Whether the record times are no clock: every known one within ``FINE_STEP`` of the others while some
    frame's stamps span a second or more (a writer that stored something else as receive times: a pymoveit2
    script's rosbag2_py writer gave 8,351 messages record times of 0 to 74 ns). Nothing can be timed by them,
    /clock at arrival neither."""
    return record_end - record_start < FINE_STEP and any(e.last_stamp - e.first_stamp >= NS_PER_S for e in edges)


def _why_no_record_clock(edges: Sequence[EdgeClock], record_start: int, record_end: int) -> str:
    spread = max(e.last_stamp - e.first_stamp for e in edges) / NS_PER_S
    return (
        f"{NO_RECORD_CLOCK}: {sum(e.arrivals for e in edges):,} transforms recorded within "
        f"{record_end - record_start} ns of one another (at {record_start} ns) while tf's stamps span {spread:.1f} s "
        "(the recorder stored something else as receive times): delays, ages and staleness against arrival "
        "cannot be measured"
    )


def clocked_arrivals(
    buffer: Buffer, clock: ClockSamples, since: int = 0
) -> Iterable[tuple[str, Int64Array, Int64Array, Int64Array, BoolArray]]:
    """Per frame, the stamps and record times of its transforms that tell its clock (dynamic, on /tf,
    with a known record time, offered from arrival ``since`` on), and ``clock_at`` those record times;
    frames without any left out."""
    for child, hist in buffer.histories():
        keep = (hist.record_times > 0) & ((hist.flags & FROM_STATIC_TOPIC) == 0)
        if since:
            keep &= hist.sequence >= since
        if hist.static or not keep.any():
            continue
        stamps, records = (
            (hist.stamps, hist.record_times) if keep.all() else (hist.stamps[keep], hist.record_times[keep])
        )
        yield child, stamps, records, *clock_at(clock, records)


def stamp_spans(buffer: Buffer) -> Iterable[tuple[bool, int, int]]:
    """Whether each history is static, and its oldest and newest stamp. The samples a static history got on
    /tf (ROS 1's tf2 keeps a frame first sent on /tf_static static, and each /tf sample replaces its value)
    span as dynamic ones: the tf data runs when they do, not from a latched stamp of before the recording."""
    for _, hist in buffer.histories():
        if hist.static and len(hist):
            on_tf = (hist.flags & FROM_STATIC_TOPIC) == 0
            for dynamic in (True, False):
                mine = hist.stamps[on_tf == dynamic]
                if len(mine):
                    yield not dynamic, int(mine.min()), int(mine.max())
        elif len(hist):
            yield False, hist.oldest_stamp, hist.latest_stamp


def tf_span(spans: Iterable[tuple[bool, int, int]], record_start: int, record_end: int) -> tuple[int, int]:
    """The tf data's own span (``stamp_spans``): its first and last dynamic stamp, the statics' if none,
    the record span if no stamp at all."""
    spans = list(spans)
    chosen = [(first, last) for static, first, last in spans if not static] or [(f, la) for _, f, la in spans]
    if not chosen:
        return record_start, record_end
    return min(first for first, _ in chosen), max(last for _, last in chosen)


def _why_none(edges: tuple[EdgeClock, ...], clock: ClockSamples) -> str:
    stamp, record = stamp_medians(edges)
    if record < EPOCH_FLOOR <= stamp:
        what = (
            f"tf is stamped on wall-clock time ({stamp / NS_PER_S:.1f} s) while the record clock is simulated "
            f"time ({record / NS_PER_S:.1f} s)"
        )
        cause = "the recorder ran with use_sim_time, the nodes without"
    elif stamp < EPOCH_FLOOR <= record:
        what = (
            f"tf is stamped on simulated time or time since boot (around {stamp / NS_PER_S:.1f} s) while the "
            f"record clock is wall time ({record / NS_PER_S:.1f} s)"
        )
        cause = "a simulation recorded on wall time, or a driver stamping on its own clock"
    else:
        side = "before" if record > stamp else "after"
        what = f"tf is stamped {duration(abs(record - stamp) / NS_PER_S)} {side} the record clock"
        cause = "recorded on another machine's or process's clock"
    measured = "delays, ages and staleness against arrival cannot be measured"
    if len(clock):
        return f"{what}, and does not follow the recorded {clock.topic} either ({cause}?): {measured}"
    return f"{what} and no /clock was recorded ({cause}): {measured}"
