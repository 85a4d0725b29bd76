"""Checks of time: edges that stop or pause, stamps on another clock, from the future, late, or going back."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator

import numpy as np

from tftools.analysis.detections import DETECTION
from tftools.analysis.edges import EdgeStats
from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.wtf.broadcasters import APART_DEG, APART_M, inferred_edges, sent_before
from tftools.analysis.wtf.joint_sources import with_joint_sources
from tftools.analysis.wtf.jumps import sent_together
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.rows import Rows, split
from tftools.analysis.wtf.scene import EdgeSamples, Scene, duration, edge, transforms
from tftools.core.arrays import BoolArray, FloatArray, Int64Array, IntpArray
from tftools.core.buffer import DEFAULT_CACHE_TIME
from tftools.core.figures import (
    Sightings,
    apart,
    held_apart,
    longest_interval,
    pauses,
    record_span,
    silence_limit,
    sustained_period,
)
from tftools.core.figures import delays as delays_of
from tftools.core.history import old_data
from tftools.core.semantics import dialect
from tftools.core.time import NS_PER_S, from_sec
from tftools.sources.codecs.gather import distinct
from tftools.sources.timeline import FINE_STEP, seconds_since

#: Stamps going back this far (ns) are a jump in time, never transforms that arrived late.
TIME_JUMP = NS_PER_S
#: An edge arrives late when more than this share of its transforms do.
DELAY_SHARE = 0.05
#: A rate is irregular when more than IRREGULAR_SHARE of its intervals are off the median by IRREGULAR of it.
IRREGULAR = 0.5
IRREGULAR_SHARE = 0.25
IRREGULAR_MIN_INTERVALS = 20
#: A rhythm is a cycle when this share of its intervals equals the one a cycle (2 to 4) later.
CYCLIC_SHARE = 0.8
#: Off intervals all in a row are said as one stretch (``_one_stretch``) from this many on.
BURST_MIN = 3


@register(
    "stale",
    Severity.error,
    "an edge that stops updating while the recording goes on (a warning where it is a detection, which comes and goes)",
)
def stale(scene: Scene) -> Iterator[Finding]:
    latest: dict[str, int] = {}
    last_sent = scene.shared("last arrivals", lambda: _last_sent(scene))
    for s in scene.stats:
        latest[s.child] = max(latest.get(s.child, 0), _last_arrival(s), last_sent.get(s.key, 0))
    for s in scene.stats:
        figures: dict[str, float | int | str] = {}
        if s.static or max(_last_arrival(s), last_sent.get(s.key, 0)) < latest[s.child]:
            continue  # a frame that went on under another parent has not stopped
        # re-sent after its last new transform (ROS 2's tf2 stores an identical one once): it did not stop
        # arriving; its stamp stood still, as far behind as its clock went on (a stalled localizer's)
        resent = s.count > 1 and last_sent.get(s.key, 0) > _last_arrival(s)
        silent = (_age(scene, s.last_stamp) or 0) if resent else _silence(scene, _last_arrival(s))
        if silent <= silence_limit(s.rate_hz, from_sec(scene.thresholds.stale_after)):
            continue
        by = scene.by(s.authorities)
        before_end: int | None = silent
        severity = Severity.error
        detected = scene.detections.get(s.key)
        if detected is not None and not resent:
            # what a detector sees comes and goes: lookups after its last sighting fail, but nothing stopped
            severity = Severity.warning
            message, hint = _last_sighting(scene, s, by, *detected)
            figures[DETECTION] = 1
        elif s.count == 1:
            sent = scene.shared("arrivals", lambda: _sent(scene)).get(s.key, 1)
            where = by if by.startswith(" on ") else f" on /tf{by}"
            times = "once" if sent == 1 else f"{sent:,} times"
            always = "" if sent == 1 else " always"
            message = f"{edge(*s.key)} was sent {times}{where},{always} stamped {scene.at(s.last_stamp)}"
            static = "ros2 run tf2_ros static_transform_publisher" if scene.ros2 else "static_transform_publisher"
            hint = (
                "a /tf transform holds only at its stamp, so lookups at any other time fail: publish a fixed "
                f"transform on /tf_static ({static}), or keep publishing it"
            )
            if sent > 1:
                before_end = _age(scene, s.last_stamp)  # re-sent to the end, but its stamp stood still
                hint = (
                    "its publisher re-sends one old transform without stamping it anew (a stalled localizer "
                    "re-sending its last correction, a node whose input stopped): " + hint.split(": ", 1)[1]
                )
        elif resent and (refused := _refused_after(scene, s)) is not None:
            count, last = refused
            message = (
                f"{edge(*s.key)}{by} holds nothing newer than {scene.at(s.last_stamp)}: the {transforms(count)} sent "
                f"after it, stamped up to {scene.at(last)}, {'were' if count > 1 else 'was'} refused by tf2 for "
                f"{'their values' if count > 1 else 'its value'} (invalid_values)"
            )
            figures["refused_after"] = count
            hint = (
                "lookups after its last valid transform fail with 'Lookup would require extrapolation into the "
                "future': send no transform where its value is unknown (a detector without a depth reading), or "
                "mend the values where they are made"
            )
        elif resent:
            message = f"{edge(*s.key)}{by} stopped advancing at {scene.at(s.last_stamp)}, re-sent to the end"
            hint = (
                "its publisher re-sends one old transform without stamping it anew (a stalled localizer re-sending "
                "its last correction, a node whose input stopped): lookups after that stamp fail with 'Lookup "
                "would require extrapolation into the future'; check that node"
            )
        else:
            message = f"{edge(*s.key)}{by} stopped at {scene.at(s.last_stamp)}"
            hint = (
                "its publisher stopped (crashed, shut down or stalled) while the recording went on: lookups after "
                "its last stamp fail with 'Lookup would require extrapolation into the future'; check that node"
            )
        if before_end is not None:
            message += f", {duration(before_end / NS_PER_S)} before the recording ends"
        # how long after its stamp its last sample arrived: which clock its stamps are on (a replay's)
        if s.last_record:
            figures["arrival_minus_stamp_s"] = (s.last_record - s.last_stamp) / NS_PER_S
        found = Finding(severity, "stale", message, hint, s.key, s.authorities, s.last_stamp, scene.end, s.count)
        yield dataclasses.replace(found, figures=figures)


def _refused_after(scene: Scene, s: EdgeStats) -> tuple[int, int] | None:
    """Where every transform of ``s``'s edge that came after its last stored one was refused for its values (NaN:
    a real e-Yantra fruit detection's 33 last, their stamps going on): how many, and the last one's stamp. None
    where some were usable (re-sent ones: the stamp stood still)."""
    rows = scene.rows
    mine = rows.of_edge(*s.key)
    after = mine[scene.received(mine) > s.last_record] if s.last_record else mine[:0]
    if not len(after) or rows.usable[after].any():
        return None
    return len(after), int(rows.stamp[after].max())


def _last_sighting(scene: Scene, s: EdgeStats, by: str, why: str, seen: Sightings | None) -> tuple[str, str]:
    """What ``stale`` says of a detection (``detections.detection``) that was not seen again: how often and in how
    many bursts it was seen, and when last; not a publisher that stopped, nor a fixed transform to publish."""
    seen_as = f"once, at {scene.at(s.last_stamp)}"
    if s.count > 1:
        bursts = f", {seen.in_words()}" if seen is not None else ""
        seen_as = f"{s.count:,} times{bursts}, last at {scene.at(s.last_stamp)}"
    message = f"{edge(*s.key)}{by}, a detection ({why}), was seen {seen_as}"
    hint = (
        "a detection is only as fresh as its last sighting: lookups of it at later times (a newer sensor stamp, "
        "or the latest common time with frames that moved on) extrapolate and fail with 'Lookup would require "
        "extrapolation into the future'; look it up with a timeout (canTransform) or at its own stamp, and check "
        "the stamp's age before acting on it (a marker that left the camera's view is not a fault)"
    )
    return message, hint


def _last_sent(scene: Scene) -> dict[tuple[str, str], int]:
    """When each moving edge's last transform arrived, re-sent ones too (record time; 0 where unknown)."""
    rows = scene.rows
    return {
        (parent, child): int(rows.record_time[mine].max())
        for parent, child, mine in rows.by_edge(~rows.static)
        if len(mine)
    }


def _age(scene: Scene, stamp: int) -> int | None:
    """How far ``stamp`` is behind ROS time at the recording's end, on its clock (None: another time base)."""
    since = seconds_since(stamp, scene.timeline.end)
    return None if since is None else from_sec(since)


def _silence(scene: Scene, last_arrival: int) -> int:
    """How long before the recording's end an edge's last transform arrived (``Timeline.silence``)."""
    return scene.timeline.silence(last_arrival, scene.end)


def _sent(scene: Scene) -> dict[tuple[str, str], int]:
    """How many times each moving edge was received (its re-sent samples, which tf2 keeps once, counted)."""
    rows = scene.rows
    return {(parent, child): len(mine) for parent, child, mine in rows.by_edge(~rows.static)}


def _last_arrival(s: EdgeStats) -> int:
    """When an edge's last transform arrived: its record time, or its stamp where that is unknown
    (a buffer filled by hand)."""
    return s.last_record or s.last_stamp


def _arrivals(scene: Scene, every_base: bool = False) -> Iterator[tuple[EdgeSamples, Int64Array, Int64Array]]:
    """Each moving edge with the stamps and ROS times at arrival of its samples with a delay
    (``Timeline.measurable``), where there are any; with ``every_base``, also those on another time base
    than the clock they arrived on (a second publisher's clock hours ahead is ahead all the same)."""
    for e in scene.dynamic_edges:
        ros, measured = scene.timeline.measurable(e.child, e.record_times, e.flags, None if every_base else e.stamps)
        if measured.any():
            yield e, e.stamps[measured], ros[measured]


@register("future", Severity.error, "stamps ahead of the time they were recorded")
def future(scene: Scene) -> Iterator[Finding]:
    # every base: two publishers of one edge on clocks 5.8 h apart (a ZED beside an EKF on another machine) put
    # the EKF's samples on another base than the recorder's clock, and each of them hours ahead of its arrival
    for e, stamps, records in _arrivals(scene, every_base=True):
        ahead = stamps - records - scene.timeline.resolution  # ROS time at arrival lags by up to a clock step
        early = ahead > from_sec(scene.thresholds.future)
        if early.any():
            # said on the stamps' clock, as the finding's times are: its arrival, on a clock running ahead of the
            # publisher's, read "first at 1547728537.122 (79.4 s before the first tf stamp)"
            first = int(stamps[early].min())
            by, sent = _senders(scene, e, stamps, early)
            finding = e.finding(
                Severity.error,
                "future",
                f"{edge(*e.key)}{scene.by(by)}: {int(early.sum())} of {transforms(sent)} "
                f"stamped up to {duration(ahead.max() / NS_PER_S)} after they arrived, the first stamped "
                f"{scene.at(first, e.recorded_at(first))}",
                "the publisher's clock runs ahead of the recorder's (sync the clocks: chrony/NTP), or it post-dates "
                f"its transforms by more than {scene.thresholds.future:g} s (amcl's or a SLAM node's "
                "transform_tolerance): listeners then take them for the newest data and lookups at the present "
                "extrapolate wrongly or fail",
                stamps[early],
            )
            typical = float(np.median(ahead[early])) / NS_PER_S  # one clock ahead: the same on every edge it stamps
            constant = float(bool((e.values == e.values[0]).all()))  # a fixed joint sent on /tf
            figures = {"ahead_s_median": typical, "ahead_s_max": ahead.max() / NS_PER_S, "constant": constant}
            yield dataclasses.replace(finding, authorities=by, figures=figures)


def _senders(scene: Scene, e: EdgeSamples, stamps: Int64Array, early: BoolArray) -> tuple[tuple[str, ...], int]:
    """Who sent ``e``'s ``early`` samples (of ``stamps``), and how many of ``stamps`` they sent: of an edge two
    publishers take turns on, the one whose clock runs ahead, not both."""
    if len(e.authorities) < 2:
        return e.authorities, len(stamps)
    rows = scene.rows
    senders = []  # (the first row it sent of an early stamp, the publisher, its rows)
    for publisher, own in rows.edge_publishers(e.parent, e.child):
        theirs = own[np.isin(rows.stamp[own], stamps[early])]
        if len(theirs):
            senders.append((int(theirs[0]), publisher, own))
    if not senders:
        return e.authorities, len(stamps)
    senders.sort(key=lambda s: s[0])
    sent = rows.stamp[np.concatenate([own for _, _, own in senders])]
    by = tuple(rows.authorities[publisher] for _, publisher, _ in senders)
    return by, int(np.unique(sent[np.isin(sent, stamps)]).size)


#: No sample of an edge sooner than this after its stamp: a clock behind the recorder's more likely than a link or a
#: slow node (roswtf's 1 s for out-of-date transforms); a node stamping with its input's time is late by less.
CLOCK_BEHIND_S = 1.0

#: Edges whose stamps are ahead of (or behind) their arrival by typical amounts this close (s) are off by one clock;
#: an edge each of whose samples is late by at most this more than its earliest is late by one steady amount.
SAME_CLOCK_S = 0.1


@dataclasses.dataclass(frozen=True)
class _Late:
    """An edge ``delay`` reports: its samples' stamps, arrivals, delays and which are late."""

    edge: EdgeSamples
    stamps: Int64Array
    records: Int64Array
    delays: Int64Array
    late: BoolArray

    @property
    def floor(self) -> int:
        return int(self.delays.min())

    def steady(self, limit: int) -> bool:
        """Every sample late, each by about the same amount (``SAME_CLOCK_S`` of the earliest, at the median)."""
        return self.floor > limit and float(np.median(self.delays)) - self.floor <= from_sec(SAME_CLOCK_S)


def _one_offset(found: list[_Late], limit: int) -> dict[tuple[str, str], int]:
    """The late edges put down to one clock, each with how many such edges there are: any none of whose samples
    came sooner than ``CLOCK_BEHIND_S``; and, however small the offset, those each of whose samples is late by one
    steady amount (``_Late.steady``) as late as another such edge's (``SAME_CLOCK_S``): two real drones' servers
    and MAVROS, every sample 0.39-0.44 s late, none sooner than 0.385-0.403 s. A link or a pipeline delaying each
    edge its own way keeps neither."""
    steady = sorted((f for f in found if f.steady(limit)), key=lambda f: f.floor)
    alike: dict[tuple[str, str], int] = {}
    run: list[_Late] = []
    for f in [*steady, None]:
        if f is not None and (not run or f.floor - run[0].floor <= from_sec(SAME_CLOCK_S)):
            run.append(f)
            continue
        if len(run) >= 2:
            alike.update((r.edge.key, len(run)) for r in run)
        run = [f] if f is not None else []
    for f in found:
        if f.floor > from_sec(CLOCK_BEHIND_S):
            alike.setdefault(f.edge.key, 1)
    return alike


@register("delay", Severity.warning, "transforms arriving late enough to cause extrapolation errors")
def delay(scene: Scene) -> Iterator[Finding]:
    limit = from_sec(scene.thresholds.delay)
    found = []
    for e, stamps, records in _arrivals(scene):
        delays = delays_of(records, stamps, scene.timeline.resolution)
        late = delays > limit
        if late.mean() <= DELAY_SHARE:
            continue
        if e.child in scene.shared("time_jumps", lambda: _jumped(scene)):
            continue  # stamps behind arrival since a jump back in time: ``time_backwards`` says so
        found.append(_Late(e, stamps, records, delays, late))
    offset = _one_offset(found, limit)
    for f in found:
        e, stamps, records, delays, late = f.edge, f.stamps, f.records, f.delays, f.late
        by = scene.by(e.authorities)
        step = scene.timeline.resolution
        coarse = f"; at least: ROS time at arrival ticks every {duration(step / NS_PER_S)}" if step > FINE_STEP else ""
        causes = "a busy publisher, a slow link, stamping with an old acquisition time"
        sooner = f"none arrived sooner than {duration(f.floor / NS_PER_S)} after its stamp"
        alike = offset.get(e.key)
        if alike is not None and f.floor > from_sec(CLOCK_BEHIND_S):
            # a hobby robot of 2016 (qjones81/johnny5's data.bag): every edge of three publishers 5.6-6.2 s late at
            # 10-50 Hz, none ever sooner: the robot's clock behind the recorder's, as ``future`` says of one ahead
            causes = (
                f"{sooner}: most likely the publisher's clock runs behind the recorder's (sync the clocks: "
                f"chrony/NTP); else {causes}"
            )
        elif alike is not None:
            causes = (
                f"{sooner} nor much later, as with {counted(alike - 1, 'more edge')}: one "
                "steady offset, most likely the publishers' clock behind the recorder's (sync the clocks: "
                "chrony/NTP); else a link or a pipeline delaying them alike"
            )
        finding = e.finding(
            Severity.warning,
            "delay",
            f"{edge(*e.key)}{by} arrives late: {int(late.sum())} of {transforms(len(stamps))} "
            f"more than {scene.thresholds.delay:g} s after their stamp (median "
            f"{duration(float(np.median(delays)) / NS_PER_S)}, at most {duration(delays.max() / NS_PER_S)}{coarse}), "
            f"first at {scene.at(int(records[late].min()))}{_held_back(scene, stamps, records)}",
            "a node looking it up at a fresh sensor stamp fails with 'extrapolation into the future' unless it "
            f"waits: use a tf2_ros MessageFilter or lookupTransform with a timeout (canTransform), and find what "
            f"delays it ({causes})",
            records[late],
        )
        figures: dict[str, float | int | str] = {
            "late_s_min": f.floor / NS_PER_S,
            "clock_behind": float(alike is not None),
        }
        yield dataclasses.replace(finding, figures=figures)


#: The stalls ``delay`` names one by one, longest first: those at least this share of the longest, up to
#: ``STALLS_NAMED``; shorter ones are counted with their range (a WiFi link's hiccups of 1-2 s beside its 12 s outage).
STALL_SHARE = 0.5
STALLS_NAMED = 3


def _held_back(scene: Scene, stamps: Int64Array, records: Int64Array) -> str:
    """The times nothing of an edge arrived while its stamps went on (a real drone's tf over WiFi: 12.0 s without
    a sample, those stamped meanwhile arriving together after it; a Pioneer's link to its recorder stalled twice,
    12.3 and 7.7 s): the samples were held back on their way, which the late ones' largest delays are. Each such
    stall is longer than the gap threshold and twice the longest pause of the stamps; none where the stamps paused
    as long (``rate``'s)."""
    if len(records) < 2:
        return ""
    arrived = np.sort(records)
    intervals = np.diff(arrived)
    floor = max(from_sec(scene.thresholds.max_gap), longest_interval(np.sort(stamps))[0] * 2)
    stalls = np.flatnonzero(intervals > floor)
    if not len(stalls):
        return ""
    stalls = stalls[np.argsort(-intervals[stalls], kind="stable")]
    lengths = intervals[stalls]
    named = stalls[:STALLS_NAMED][lengths[:STALLS_NAMED] >= STALL_SHARE * lengths[0]]
    said = " and ".join(f"for {duration(intervals[i] / NS_PER_S)} from {scene.at(int(arrived[i]))}" for i in named)
    rest = lengths[len(named) :]
    spread = " to ".join(dict.fromkeys(duration(v / NS_PER_S) for v in (rest.min(), rest.max()))) if len(rest) else ""
    shorter = f" (and {counted(len(rest), 'shorter time')}, of {spread})" if len(rest) else ""
    return (
        f"; none arrived {said}{shorter} while its stamps went on: the samples stamped meanwhile were held back on "
        "their way, and came late together"
    )


@register("rate", Severity.warning, "irregular publishing and long gaps")
def rate(scene: Scene) -> Iterator[Finding]:
    """Pauses in each edge's stamps (the samples tf2 holds: the pauses ``report`` shades, ``figures.pauses``);
    then, where there is none, each publisher's rhythm per frame by when its transforms were received
    (a sample sent again, stamp and value, counted once, however late; refused values included: other checks
    judge those)."""
    silent = set()
    for e in scene.dynamic_edges:
        found = _silences(scene, e)
        if found is not None:
            silent.add(e.child)
            yield found
    rows = scene.rows
    for child, mine in _streams(scene, rows.named & ~rows.static):
        if child in silent:
            continue
        stamps = rows.stamp[mine]
        counted = ~sent_before(stamps, _values_of(rows, mine))
        if _steady(stamps[counted]):
            continue  # what tf2 holds is steady; arrivals bunched by a link are ``delay``'s (or ``future``'s)
        arrivals = np.sort(scene.received(mine[counted]))
        if len(arrivals) >= 3:
            frames = (rows.names[rows.parent[mine[-1:]][0]], child)
            span = (int(stamps[counted].min()), int(stamps[counted].max()))
            yield from _rhythm(scene, frames, scene.authorities_of(mine), arrivals, span)


#: ``rate``'s hint for a detection seen in bursts (``detections.detection``): the camera lost it, no publisher failed.
DETECTION_GAPS = (
    "a detector publishes what it sees only while it sees it: lookups between two sightings interpolate across "
    "the time it was unseen (a guess of where it was), after the last one they extrapolate and fail; look it up "
    "with a timeout (canTransform) and check the stamp's age before acting on it"
)


#: The rhythm of arrivals read off a clock with steps of a third of the period or more cannot be judged.
STEPS_PER_PERIOD = 3


def _silences(scene: Scene, e: EdgeSamples) -> Finding | None:
    found = pauses(e.stamps, from_sec(scene.thresholds.max_gap), record_span(e.record_times))
    if found is None:
        return None
    message = (
        f"{edge(*e.key)}{scene.by(e.authorities)} went silent {counted(found.count, 'time')} (it "
        f"publishes every {duration(found.period / NS_PER_S)}): the longest "
        f"for {duration(found.longest / NS_PER_S)} from {scene.at(found.longest_start)}"
    )
    hint = (
        "lookups inside a gap interpolate across it, and fail at its end while the data is missing: check "
        "the publisher's load, its rate parameter and its connection"
    )
    detected = scene.detections.get(e.key)
    if detected is not None:
        why, seen = detected
        bursts = f": {seen.in_words(longest=False)}" if seen is not None else ""
        times = "once" if found.count == 1 else counted(found.count, "time")
        unseen = seen.bursts - 1 if seen is not None else found.count
        if unseen > found.count:  # its bursts part at two periods, a pause is ten and max_gap: say both counts
            times = f"{counted(unseen, 'time')}, " + ("once" if found.count == 1 else f"{found.count} of them")
        message = (
            f"{edge(*e.key)}{scene.by(e.authorities)}, a detection ({why}), went unseen "
            f"{times} for longer than its rhythm (every {duration(found.period / NS_PER_S)}) "
            f"allows, the longest for {duration(found.longest / NS_PER_S)} from {scene.at(found.longest_start)}"
            f"{bursts}"
        )
        hint = DETECTION_GAPS
    figures: dict[str, float | int | str] = {DETECTION: 1} if detected is not None else {}
    return Finding(
        Severity.warning,
        "rate",
        message,
        hint,
        e.key,
        e.authorities,
        found.first,
        found.last,
        found.count,
        figures=figures,
    )


def _rhythm(
    scene: Scene, frames: tuple[str, str], who: tuple[str, ...], arrivals: Int64Array, span: tuple[int, int]
) -> Iterator[Finding]:
    """Irregular arrivals, or two publishers taking turns; ``arrivals`` read off a clock with steps of
    ``Timeline.record_step`` (a live system on /clock) are each late by up to a step: an interval is
    off only beyond that, and a period of less than ``STEPS_PER_PERIOD`` steps is not judged. The finding's
    times are ``span``, its first and last stamps, as every finding's: edges sent by one publisher in messages
    of their own share them (not their arrivals, microseconds apart), one rhythm said once (``causes``)."""
    intervals = np.diff(arrivals)
    step = scene.timeline.record_step
    if len(intervals) < IRREGULAR_MIN_INTERVALS or float(np.median(intervals)) < STEPS_PER_PERIOD * step:
        return
    off = _off_share(intervals, step)
    if off <= IRREGULAR_SHARE:
        return
    what = f"{edge(*frames)}{scene.by(who)}"
    if not scene.publishers_known and _interleaved(arrivals, step):
        return  # two rhythms taking turns: one publisher on a stepped clock, or two (``broadcasters`` tells)
    elif _cyclic(intervals):  # a driver sending two messages every 100 ms, 33 then 67 ms apart, is regular
        return
    else:
        code = "rate"
        usual = sustained_period(intervals)  # a burst of many short intervals is how it was delivered, not its rate
        detected = scene.detections.get(frames)
        if detected is not None and detected[1] is not None:  # seen in bursts: no period that few intervals keep
            message = f"{what}, a detection ({detected[0]}), is {detected[1].in_words()}"
            yield Finding(
                Severity.warning,
                code,
                message,
                DETECTION_GAPS,
                frames,
                who,
                span[0],
                span[1],
                len(arrivals),
                figures={DETECTION: 1},
            )
            return
        runs = _paused_runs(intervals, step) if usual > (1 + IRREGULAR) * np.median(intervals) else None
        if runs is not None:
            message, hint = f"{what} publishes irregularly: {runs[0]}", runs[1]
            yield Finding(Severity.warning, code, message, hint, frames, who, span[0], span[1], len(arrivals))
            return
        joint = frames in sent_together(scene)  # its rhythm is /joint_states': what robot_state_publisher is sent
        batches = _batches(intervals, step, usual)
        if batches is not None:
            hint = _joint_rhythm(scene) if joint else BATCHED
            found = Finding(
                Severity.warning, code, f"{what} {batches}", hint, frames, who, span[0], span[1], len(arrivals)
            )
            yield with_joint_sources(scene, found)
            return
        message = (
            f"{what} publishes irregularly: {_off_share(intervals, step, usual):.0%} of the intervals between its "
            f"arrivals are more than {IRREGULAR:.0%} off the {duration(usual / NS_PER_S)} it keeps up most of the "
            f"time (from {duration(intervals.min() / NS_PER_S)} to {duration(intervals.max() / NS_PER_S)})"
            f"{_one_stretch(intervals, _off(intervals, step, usual), usual)}"
        )
        hint = (
            _joint_rhythm(scene)
            if joint
            else "interpolation between far-apart samples is coarse: publish on a timer at a steady rate"
        )
    yield with_joint_sources(
        scene, Finding(Severity.warning, code, message, hint, frames, who, span[0], span[1], len(arrivals))
    )


def _joint_rhythm(scene: Scene) -> str:
    """``rate``'s hint for a state publisher's joint: its rhythm is that of the joint states it is sent."""
    return (
        "robot_state_publisher sends a joint's transform for each /joint_states message it gets, so this is "
        "/joint_states' rhythm: two sources of it at different rates (joint_state_publisher beside the driver or "
        f"the simulator), or one publishing irregularly; check who publishes /joint_states "
        f"({scene.list_publishers('/joint_states')})"
    )


#: ``rate``'s hint for samples received, and stamped, a batch at a time (``_batches``).
BATCHED = (
    "a driver that reads its device's samples a batch at a time (a USB or serial packet) and stamps each as it is "
    "read: lookups between them interpolate across stamps that are not the samples' times; stamp each sample with "
    "when it was measured (the device's clock, a driver's time-reference option), or send one per batch"
)


def _batches(intervals: Int64Array, step: int, usual: int) -> str | None:
    """Where most intervals are far shorter than the ``usual`` one and the rest keep it: the samples come a batch
    at a time (a real Xsens IMU's 200 Hz: 5 or 6 stamped within 2 ms, then 26 ms apart), said as such, not as
    intervals "off the period it keeps up most of the time"; None otherwise."""
    off = _off(intervals, step, usual)
    short = off & (intervals < usual)
    if short.mean() <= 0.5 or short.sum() < 0.9 * off.sum():
        return None
    apart = int((~short).sum())
    batches = int(short[0]) + int((short[1:] & ~short[:-1]).sum())  # runs of short intervals
    if batches < max(3, apart // 2):  # a start-up burst, or a few: in a row, not a batch between each interval
        return None
    rate = len(intervals) / (float(intervals.sum()) / NS_PER_S) if intervals.sum() else 0.0
    within = duration(float(intervals[short].max()) / NS_PER_S)
    return (
        f"comes in batches: {short.mean():.0%} of its intervals are under {within} (about "
        f"{len(intervals) / max(apart, 1):.1f} samples at a time), the batches {duration(usual / NS_PER_S)} apart "
        f"({rate:.1f} Hz on average)"
    )


def _steady(stamps: Int64Array) -> bool:
    """Whether samples are stamped at a steady rate (``_off_share`` of their intervals at most
    IRREGULAR_SHARE), or in a steady cycle (``_cyclic``): a real robot's odometry stamped exactly 0.100 s apart but
    received over Wi-Fi in bursts (intervals of 0 to 0.86 s) publishes regularly, and interpolation between its
    samples is fine; so does a real cart's amcl, stamping map -> odom from its lidar's scans (0.13, 0.13, 0.13 then
    0.26 s apart, over and over) but sending them in bursts once its odometry came (0.9 Hz)."""
    intervals: Int64Array = np.diff(distinct(stamps)).astype(np.int64)
    if len(intervals) < IRREGULAR_MIN_INTERVALS:
        return False
    return _off_share(intervals) <= IRREGULAR_SHARE or _cyclic(intervals) or _jittered(intervals)


#: Samples stamped off their places keep the count a period gives to within this share (``_jittered``).
JITTER_COUNT = 0.02


def _jittered(intervals: Int64Array) -> bool:
    """Whether a steady rate's samples are stamped off their places now and then, each one alone: the two intervals
    around such a sample are short and long but add up to two periods (a Gazebo arm's /joint_states every 20 ms, one
    in six stamped 13 ms early: 20, 7, 33, 20 ms), so the sums of neighbouring intervals keep two of the usual
    interval where the intervals do not (a marker seen in bursts, 40 ms apart within them, does not), and there are as
    many samples as that interval gives (a second source's samples among them make more: its rhythm is uneven)."""
    period = float(np.median(intervals))
    kept = abs(float(np.mean(intervals)) - period) <= JITTER_COUNT * period
    return kept and _off_share(intervals[:-1] + intervals[1:], usual=round(2 * period)) <= IRREGULAR_SHARE


def _off_share(intervals: Int64Array, step: int = 0, usual: int | None = None) -> float:
    """The share of intervals more than IRREGULAR off their median (or ``usual``), and beyond the ``step`` of
    the clock that measured them (``_off``)."""
    return float(_off(intervals, step, usual).mean())


def _off(intervals: Int64Array, step: int = 0, usual: int | None = None) -> BoolArray:
    """Per interval, whether it is more than IRREGULAR off their median (or ``usual``), and beyond ``step``."""
    period = float(np.median(intervals)) if usual is None else float(usual)
    off: BoolArray = np.abs(intervals - period) > IRREGULAR * period + step
    return off


def _one_stretch(intervals: Int64Array, off: BoolArray, usual: int) -> str:
    """Where the ``off`` intervals lie when all of them come in a row (``BURST_MIN`` at least): how many, over
    how long, and where (the first or last seconds of the edge); shorter than ``usual``, a burst (a driver
    sending what it had queued at once: a real Neato's 44 samples 10 ms apart in its first 0.44 s, then one
    every 0.41 s). Empty otherwise: irregular throughout."""
    where = np.flatnonzero(off)
    if len(where) < BURST_MIN or where[-1] - where[0] + 1 != len(where):
        return ""
    over = duration(float(intervals[where].sum()) / NS_PER_S)
    place, burst = (
        (f"in its first {over}", "a burst at its start, steady after it")
        if where[0] == 0
        else (f"in its last {over}", "a burst at its end, steady before it")
        if where[-1] == len(intervals) - 1
        else (f"over {over}", "one burst, steady around it")
    )
    said = f", all {len(where)} of them in a row {place}"
    return f"{said}: {burst}" if (intervals[where] < usual).all() else said


def _paused_runs(intervals: Int64Array, step: int) -> tuple[str, str] | None:
    """A rhythm kept by most intervals, broken by pauses spread among them (not one stretch: ``_one_stretch``'s
    start-up burst), said as such, with how often they come where they recur steadily; None otherwise. A student's
    disc-robot simulator (shaheenebrahimi/DDMR, out4) sends every 0.100 s but stops for 0.63-0.70 s once a second
    while it computes its scan: by time the pauses are most of the stream, and 'the 0.637 s it keeps up most of the
    time' named them as its rhythm, 81% of the intervals 'off' it."""
    period = int(np.median(intervals))
    kept = np.abs(intervals - period) <= IRREGULAR * period + step
    paused = np.flatnonzero(intervals > (1 + IRREGULAR) * period + step)
    if kept.mean() < 0.5 or len(paused) < BURST_MIN or paused[-1] - paused[0] + 1 == len(paused):
        return None
    lengths = intervals[paused] / NS_PER_S
    said = (
        f"every {duration(period / NS_PER_S)} in runs, broken {counted(len(paused), 'time')} by pauses of "
        f"{duration(lengths.min())}" + (f" to {duration(lengths.max())}" if lengths.max() > lengths.min() else "")
    )
    starts = np.concatenate(([0], np.cumsum(intervals)))[paused]
    cycles = np.diff(starts)
    cycle = float(np.median(cycles))
    if len(cycles) >= BURST_MIN and np.mean(np.abs(cycles - cycle) <= IRREGULAR * cycle) >= 1 - IRREGULAR_SHARE:
        said += f", about one every {duration(cycle / NS_PER_S)}"
    share = float(lengths.sum()) * NS_PER_S / float(intervals.sum())
    hint = (
        f"lookups inside a pause interpolate across up to {duration(lengths.max())}: something holds the publisher "
        "up between its sends (work in the same thread, a blocking call); publish on a timer nothing blocks"
    )
    return f"{said} ({share:.0%} of its time)", hint


def _cyclic(intervals: Int64Array) -> bool:
    """Whether the intervals repeat with a cycle of 2 to 4 (``CYCLIC_SHARE`` of them within 10% of the mean
    of the one a cycle later): a driver whose phase slips now and then is still regular."""
    tolerance = 0.1 * float(np.mean(intervals))
    return any(
        len(intervals) > 2 * cycle
        and np.mean(np.abs(intervals[cycle:] - intervals[:-cycle]) <= tolerance) >= CYCLIC_SHARE
        for cycle in (2, 3, 4)
    )


def _interleaved(arrivals: Int64Array, step: int) -> bool:
    """Two steady rhythms of one rate taking turns: two publishers, where the bag does not name them."""
    first, second = np.diff(arrivals[0::2]), np.diff(arrivals[1::2])
    if min(len(first), len(second)) < IRREGULAR_MIN_INTERVALS // 2:
        return False
    steady = _off_share(first, step) <= IRREGULAR_SHARE / 2 and _off_share(second, step) <= IRREGULAR_SHARE / 2
    return steady and abs(float(np.median(first)) / float(np.median(second)) - 1) < IRREGULAR / 2


@register("time_backwards", Severity.error, "an edge's stamps going back or repeating")
def time_backwards(scene: Scene) -> Iterator[Finding]:
    """Per frame and publisher: what two publishers do to each other's stamps is theirs to answer for
    (``multiple_authorities``, ``multiple_parents``)."""
    rows = scene.rows
    taking_turns = {child for _, child in inferred_edges(scene)}
    old = _old_data(scene)
    for child, mine in _streams(scene, rows.usable & ~rows.static):
        if child not in taking_turns and not scene.buffer.in_static_cache(child):
            yield from (with_joint_sources(scene, f) for f in _stamps_of(scene, child, mine, old[mine]))


def _old_data(scene: Scene) -> BoolArray:
    """The moving rows tf2 with its 10 s cache refuses as ``TF_OLD_DATA`` (``history.old_data``, per frame: a
    ZED's samples beside an EKF's stamped 5.8 h ahead), never as repeated: ROS 1's and ROS 2's alike (both
    ``TimeCache::insertData``s refuse them before comparing stamps), the frame's /tf_static rows in its caches
    as each tf2 puts them. A whole recording's buffer keeps them all."""
    rows = scene.rows
    old = np.zeros(len(rows), bool)
    keeps_first_cache = dialect(scene.buffer.semantics).keeps_first_cache
    for _, frame_rows in rows.by_child(rows.usable):
        stamps, static = rows.stamp[frame_rows], rows.static[frame_rows]
        old[frame_rows] = old_data(stamps, DEFAULT_CACHE_TIME, static, keeps_first_cache)
    return old & ~rows.static


def _streams(scene: Scene, mask: BoolArray) -> Iterator[tuple[str, IntpArray]]:
    """The ``mask`` rows of each edge from each of its publishers, in arrival order: a child under two parents
    at once is two streams, each judged on its own (aerostack2's Crazyflie: cf0/base_link from Gazebo's bridge
    under cf0 and from the estimator under cf0/odom at each of the same stamps, in one ROS 2 bag that names no
    publisher: each parent's stamps rise, and the stamps repeated across them are ``multiple_parents``')."""
    rows = scene.rows
    for child, frame_rows in rows.by_child(mask):
        for _, theirs in split(frame_rows, rows.authority[frame_rows]):
            for _, under_one_parent in split(theirs, rows.parent[theirs]):
                yield child, under_one_parent


def _behind(stamps: Int64Array) -> tuple[Int64Array, BoolArray]:
    """How far each stamp is behind the newest one before it, and which rows went back: stamped
    earlier, or as early as the newest right after rows that did (the end of a jump back)."""
    before = np.concatenate([stamps[:1], np.maximum.accumulate(stamps)[:-1]])
    back = stamps < before
    back |= (stamps == before) & np.concatenate([[False], back[:-1]])
    return before - stamps, back


def _jumped(scene: Scene) -> set[str]:
    """Child frames whose stamps jumped back in time, by any publisher."""
    rows = scene.rows
    found = set()
    for child, mine in _streams(scene, rows.usable & ~rows.static):
        behind, back = _behind(rows.stamp[mine])
        if back.any() and behind[back].max() >= TIME_JUMP:
            found.add(child)
    return found


def _stamps_of(scene: Scene, child: str, mine: np.ndarray, old: BoolArray) -> Iterator[Finding]:
    """``mine``: one publisher's rows of ``child``, in arrival order; ``old``: which of them tf2 refuses as too
    old (``_old_data``), never as repeated."""
    rows = scene.rows
    stamps = rows.stamp[mine]
    if len(stamps) < 2:
        return
    behind, back = _behind(stamps)
    repeat, same = _repeats(stamps, _values_of(rows, mine))
    repeat &= ~old
    if not (back & (behind >= TIME_JUMP)).any():  # no jump back in time: a sample received again (a link
        back &= ~(repeat & same)  # re-delivering it) is a repeat (ROS 2's tf2 takes it silently), not one out of order
    repeat &= ~back
    arrived, measured = scene.timeline.measurable(child, rows.record_time[mine], rows.flags[mine], stamps)
    late = measured & (delays_of(arrived, stamps, scene.timeline.resolution) > from_sec(scene.thresholds.delay))
    if late.mean() > DELAY_SHARE:  # ``delay`` reports these: arriving late, newer ones overtook them
        back &= ~(late & (behind < TIME_JUMP))
    frames = (rows.names[rows.parent[mine[-1:]][0]], child)
    if back.any():
        yield _went_back(scene, frames, mine, back, behind)
    ros2 = scene.buffer.semantics == "ros2"
    for again, identical in ((repeat & ~same, False), (repeat & same, True)):
        if again.any() and not (ros2 and identical):  # ROS 2's tf2 takes an identical sample again silently
            yield _repeated(scene, frames, mine[again], identical)


def _values_of(rows: Rows, mine: IntpArray) -> Callable[[IntpArray], FloatArray]:
    """The values of some of the rows ``mine`` (their places in it): read when needed, not the whole edge's."""
    return lambda which: rows.values[mine[which]]


def _repeats(stamps: Int64Array, values: Callable[[IntpArray], FloatArray]) -> tuple[BoolArray, BoolArray]:
    """Which rows repeat an earlier row's stamp, and which of those repeat its values too (within
    ``figures.held_apart``'s tolerances: a double computed again differs in its last bits, the SAIL ZED's
    re-sends 7e-12 m apart, not in what it says); ``values``
    gives those of some rows: the repeats' and their first's alone are read (``same`` means nothing elsewhere)."""
    n = len(stamps)
    order = np.argsort(stamps, kind="stable")
    ordered = stamps[order]
    again = np.zeros(n, bool)
    again[1:] = ordered[1:] == ordered[:-1]
    starts = np.maximum.accumulate(np.where(again, 0, np.arange(n)))
    repeat = np.zeros(n, bool)
    repeat[order] = again
    which = order[again]
    first = order[starts[again]]
    same = np.ones(n, bool)
    if len(which):
        moved, turned = held_apart(values(which), values(first))
        same[which] = ~(moved | turned)
    return repeat, same


def _went_back(scene: Scene, frames: tuple[str, str], mine: IntpArray, back: BoolArray, behind: Int64Array) -> Finding:
    """``back`` marks the rows stamped before the newest stamp so far, ``behind`` by how much: a jump
    back in time (an error), or transforms out of order by less, which tf2 sorts into place (a warning)."""
    largest = int(behind[back].max())
    offenders = mine[back]
    name, by, first = edge(*frames), scene.by(scene.authorities_of(offenders)), scene.first_at(offenders)
    if largest >= TIME_JUMP:
        jumps = int((back[1:] & ~back[:-1]).sum() + back[0])
        hint = (
            "time jumped back (a bag replayed in a loop, a restarted simulation, a clock reset): listeners then "
            "mix two timelines and must be reset (tf2_ros clears its buffer when ROS time jumps back)"
        )
        if old_data(scene.rows.stamp[mine], DEFAULT_CACHE_TIME).any():
            hint += "; tf2 refuses samples older than its 10 s cache behind the newest (TF_OLD_DATA)"
        severity = Severity.error
        message = (
            f"stamps of {name}{by} went back {counted(jumps, 'time')}, by up to "
            f"{duration(largest / NS_PER_S)}, first at {first}: {transforms(len(offenders))} stamped before one "
            "already sent"
        )
    else:
        severity = Severity.warning
        stepped = _stepped_back(scene.rows.values[mine], scene.rows.stamp[mine], back)
        copes = "tf2 sorts them into its cache, so lookups cope, but " if not stepped else ""
        hint = (
            f"{copes}something reorders them: the publisher stamps before it sends from several threads, works "
            "through inputs it queued in no order (a localizer's scans held until a late transform came), or the "
            "link reorders; stamp and send in order"
        )
        message = (
            f"{name}{by}: {transforms(len(offenders))} arrived out of order, stamped up to "
            f"{duration(largest / NS_PER_S)} before one already received, first at {first}{stepped}"
        )
    return _when_they_came(scene, severity, message, hint, frames, offenders)


def _when_they_came(
    scene: Scene, severity: Severity, message: str, hint: str, frames: tuple[str, str], offenders: IntpArray
) -> Finding:
    """A ``time_backwards`` finding timed by when its transforms came, as its "first at" says (a stamp already sent
    of 389.647 s came again at 389.769 s): on the stamps' clock, as every finding's, not at the old stamps."""
    return scene.finding(severity, "time_backwards", message, hint, frames, offenders, scene.arrival(offenders))


def _stepped_back(values: FloatArray, stamps: Int64Array, back: BoolArray) -> str:
    """Where samples that arrived out of order (``back``, of one publisher's stream in arrival order) carry another
    value than the newest-stamped one received before them (further apart than two places, 1 cm or 1 degree): how
    many, how far, and what follows; empty where each repeats it. A real cart's amcl sent map -> odom for six queued
    scans in no order, its estimate changing among them: tf2 sorts the newer value before the older one."""
    newest = np.maximum.accumulate(np.where(stamps == np.maximum.accumulate(stamps), np.arange(len(stamps)), 0))
    metres, degrees = apart(values[newest[back]], values[back])
    other = (metres > APART_M) | (degrees > APART_DEG)
    if not other.any():
        return ""
    return (
        f"; {int(other.sum())} of them carry another value than the one already stamped after them (up to "
        f"{float(metres[other].max()):.3f} m and {float(degrees[other].max()):.1f}°): tf2 sorts each before that "
        "one, so lookups between their stamps go from the newer value back to the older"
    )


def _repeated(scene: Scene, frames: tuple[str, str], offenders: IntpArray, same: bool) -> Finding:
    """Stamps sent again: with the same values (ROS 1's tf2 ignores each, logging TF_REPEATED_DATA at WARN
    level, and answers every lookup as before: a warning, as tf2 says it; ROS 2's takes them silently and is not
    asked here), or with other values (ROS 1's drops them, updates lost: an error; ROS 2's keeps both,
    ``semantics``' table: cache.cpp's ``insertData`` puts a sample before the others of its stamp)."""
    sent = f"{edge(*frames)}{scene.by(scene.authorities_of(offenders))} sent {transforms(len(offenders))}"
    first = scene.first_at(offenders)
    other_values = (
        "stamp each update with the time it describes; two publishers or a stamp that does not advance repeat it"
    )
    if same:
        severity, hint = (
            Severity.warning,
            "publish each stamp once (a timer faster than its input republishes the last transform)",
        )
        message = (
            f"{sent} again with a stamp and values it had already sent, first at {first}: tf2 ignores each, logging "
            "TF_REPEATED_DATA (nothing is lost, but the log floods)"
        )
    elif scene.buffer.semantics == "ros2":
        severity, hint = Severity.warning, other_values
        stamps = counted(len(np.unique(scene.rows.stamp[offenders])), "stamp")  # a new value re-sent is one
        message = (
            f"{edge(*frames)}{scene.by(scene.authorities_of(offenders))}: {stamps} it had already sent came again "
            f"with other values ({transforms(len(offenders))}), first at {first}: ROS 2's tf2 keeps every value "
            "(it has no TF_REPEATED_DATA), so lookups at the stamp and up to the next one answer from the one "
            "received last (the first while it is the oldest stamp held), and lookups just before it interpolate "
            "towards the first (ROS 1's would refuse the later ones: TF_REPEATED_DATA)"
        )
    else:  # each row tf2 refuses whose value is not the one it kept (the stamp's first): a value sent twice is two
        severity, hint = Severity.error, other_values
        stamps = counted(len(np.unique(scene.rows.stamp[offenders])), "stamp")
        message = (
            f"{sent} with a stamp it had already sent but other values than it first had ({stamps}), first at "
            f"{first}: tf2 ignores them (TF_REPEATED_DATA), answering from each stamp's first value, so those "
            "updates are lost"
        )
    return _when_they_came(scene, severity, message, hint, frames, offenders)
