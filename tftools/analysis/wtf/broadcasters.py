"""Several broadcasters of one moving edge where the recording does not name publishers (ROS 2 bags,
MCAP), told from what the edge's stream holds: its stamps, values, when each sample arrived, which transforms
came with it in one message (``layouts``), and how many publishers of its topic metadata.yaml (or a bare file's
topics table or channels) lists. Five patterns are told apart:

- a stamp sent again with the same value, the newest stamp each time, as long after the sample before it
  as new samples come: one publisher re-sending its last value (a timer whose input did not change: a
  simulation step not yet taken, no new scan); a note, which counts the stamps it re-valued in between
  (slam_toolbox's first correction of a scan), ``time_backwards``' to report;
- most stamps sent again, each soon after the first (well within the stream's interval): two identical
  publishers (two robot_state_publishers), or two that disagree where the values differ;
- samples in two kinds of message (two sets of transforms) taking turns, whose values contradict each other:
  two publishers, each sending its own set (a TurtleBot 4 simulator's wheels, in messages of 2 transforms with
  the joints' angles and of 4 always at 0), or one robot_state_publisher fed /joint_states by two sources;
- among the samples not sent before, stamps going back and forth or values alternating between two
  places, sample after sample (rotations alternating only where they can be followed as two tracks):
  publishers taking turns;
- anything else is one publisher (intervals alternating on a stepped clock, stamps rising, values smooth,
  a wheel turning nearly half a turn between samples: its rotation comes back near where it was two samples
  before, each time further on, two places nowhere)."""

from __future__ import annotations

import bisect
import dataclasses
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.listed import listed_publishers
from tftools.analysis.wtf.layouts import Layouts, message_layouts
from tftools.analysis.wtf.scene import Scene, and_joined, duration, edge, listed, transforms
from tftools.core.arrays import BoolArray, FloatArray, Int64Array, IntpArray
from tftools.core.figures import (
    Disagreement,
    apart,
    largest_disagreement,
    median_ns,
    period,
    record_span,
    time_base_of,
)
from tftools.core.time import NS_PER_S
from tftools.sources.codecs.gather import first_and_inverse

#: A sign must show in this many samples, and this share of them, to tell two broadcasters.
TURNS_MIN = 5
TURNS_SHARE = 0.1
#: Publishers taking turns whose stamps may go back where the recording lists fewer (one started after recording
#: began): stamps needing more rising streams than this, and than those listed, are one publisher's, out of order.
TURNS_PUBLISHERS = 2
#: Two values this far apart (m, degrees) are two places; coming back within a quarter of it, the same one.
APART_M = 0.01
APART_DEG = 1.0
#: A sample that went out and came back is a motion's turning point when the one two before it is this many
#: times its step away: the value came on from further back, as a motion does, not from where it returns to.
TURNING = 1.5
#: A value that goes out and comes back is two places where it goes this many times further than samples two apart
#: usually are from each other (a publisher's own step, or its noise): a face detector's depth, 64 mm a sample either
#: way, goes out and back by as much, one stream (ros4hri's faces in a ROS 2 bag: 3 false errors); two odometries
#: taking turns, 0.18 m apart, each moving 12 mm in two samples, are far beyond it (the real JetAcker's).
BEYOND_NOISE = 4
#: Two identical broadcasters: at least this share of an edge's stamps sent twice (or more), each about as many
#: times (the most at most this many times the fewest): k publishers send each stamp k times, where one publisher
#: whose stamp does not advance sends a stamp as often as it publishes before its clock ticks (2 to 24 times: a
#: Gazebo ground truth stamped from a coarse simulation clock).
TWINS_SHARE = 0.5
TWINS_SPREAD = 2
#: A copy that comes at least this share of the stream's usual interval after the sample before it is a
#: re-send on the publisher's own timer; one that comes sooner, a second publisher's copy of the same input.
RESEND_SHARE = 0.5
#: Edges named in one finding; the rest are counted.
LISTED = 6
#: Re-sends of the last value: at least this share of the copies carry the newest stamp sent so far.
NEWEST_SHARE = 0.9
#: A sample this many times two places' distance (5 cm, 5 degrees) from every track's last value begins
#: another track (``_tracks_apart``): more than a robot moves between two samples, less than two odometries
#: part (the real JetAcker's: 0.13 m and 6 degrees).
TRACK_APART = 5
#: Tracks a sample may join (those extended last), the largest tracks compared, and the samples told into
#: tracks (the first ones): bounds on the work (a sample at a time, in Python).
TRACKS_HELD = 4
TRACKS_COMPARED = 4
TRACKED_SAMPLES = 20_000
#: Publishers' values closer than this (m, degrees) are said to be the same (to the figures shown).
NIL_M = 5e-5
NIL_DEG = 5e-3
#: A change of one edge's value this small (m, degrees) may be noise: ``jump``'s floor for a step its motion does not
#: explain, and what two publishers of one edge at once may differ by beyond the edge's own step (``AtOnce``).
FLOOR_M = 0.05
FLOOR_DEG = 3.0


@dataclass(frozen=True)
class AtOnce:
    """Publishers of one edge sending at once: how far apart their values are at the same times
    (``figures.disagreement``), and the edge's own step from one sample of one publisher to its next (the larger of
    their median steps, m and degrees): how far a lookup moves between two samples of one of them."""

    apart: Disagreement
    step_m: float
    step_deg: float
    contradicting: int  # at how many of the times compared further apart than that step plus noise

    @property
    def contradict(self) -> bool:
        """Further apart than the edge's own step plus noise at some of the times compared: tf2 keeps both in one
        cache, so lookups a sample apart land on one, then the other, and the pose jumps further than it moves."""
        return self.contradicting > 0

    @property
    def severity(self) -> Severity:
        """An error where they contradict each other; a warning where they agree within noise."""
        return Severity.error if self.contradict else Severity.warning

    def said(self, scene: Scene) -> str:
        """What was observed: how far apart (``apart_said``), and where they contradict each other, how far the
        edge's own step moves it."""
        told = apart_said(scene, self.apart)
        if not self.contradict:
            return told
        return (
            f"{told}, while each publisher's own value moves a median of at most {self.step_m * 1000:.1f} mm and "
            f"{self.step_deg:.2f}° from one sample to its next"
        )

    def follows(self) -> str:
        """What follows where they contradict each other (said after what was observed); nothing where they agree."""
        if not self.contradict:
            return ""
        return (
            f"; at {self._how_many()} further apart than that plus noise "
            f"({FLOOR_M * 100:.0f} cm, {FLOOR_DEG:.0f}°), they contradict each "
            "other: tf2 keeps both in one cache, so lookups a sample apart land on one, then the other, or between "
            f"them, and the pose jumps by up to {_far(self.apart)} between them"
        )

    def _how_many(self) -> str:
        """ "358 of the 995", "every one of the 1512": of the times compared, those further apart than the
        edge's own step plus noise."""
        many = "every one" if self.contradicting == self.apart.instants else str(self.contradicting)
        return f"{many} of the {self.apart.instants}"

    def figures(self) -> dict[str, float | int | str]:
        """``said``'s figures, for JSON."""
        return apart_figures(self.apart) | {
            "own_step_m": self.step_m,
            "own_step_deg": self.step_deg,
            "contradict": int(self.contradict),
            "samples_contradicting": self.contradicting,
        }


def at_once(streams: Sequence[tuple[Int64Array, FloatArray]]) -> AtOnce | None:
    """How far several publishers' streams of one edge (sorted stamps, N x 7 values each) are apart at the same times
    (``figures.largest_disagreement``) against the edge's own step; None where no two overlap in time."""
    found = largest_disagreement(streams)
    if found is None:
        return None
    steps = [apart(values[:-1], values[1:]) for _, values in streams if len(values) > 1]
    step_m = max((float(np.median(m)) for m, _ in steps), default=0.0)
    step_deg = max((float(np.median(d)) for _, d in steps), default=0.0)
    return AtOnce(found, step_m, step_deg, found.beyond(step_m + FLOOR_M, step_deg + FLOOR_DEG))


def _far(apart_: Disagreement) -> str:
    """ "1.71 m and 69.6°"."""
    return f"{apart_.metres:.2f} m and {apart_.degrees:.1f}°" if apart_.metres >= 0.01 else f"{apart_.degrees:.1f}°"


def inferred_broadcasters(scene: Scene) -> list[Finding]:
    """One ``multiple_authorities`` finding per moving edge that several broadcasters seem to send (a warning, an
    error where they contradict each other: ``AtOnce``), where the recording names no publishers (none elsewhere);
    computed once per scene."""
    return [f for f in _inferred(scene) if f.severity is not Severity.info]


def inferred_edges(scene: Scene) -> set[tuple[str, str]]:
    """The (parent, child) edges ``inferred_broadcasters`` speaks of (a finding's ``frames`` pair them)."""
    return {(f.frames[i], f.frames[i + 1]) for f in inferred_broadcasters(scene) for i in range(0, len(f.frames), 2)}


def resent_notes(scene: Scene) -> list[Finding]:
    """A ``resent`` note per edge one publisher re-sends (the same stamp and value again, on its own timer),
    where the recording names no publishers; computed with ``inferred_broadcasters``."""
    return [f for f in _inferred(scene) if f.severity is Severity.info]


def _inferred(scene: Scene) -> list[Finding]:
    return scene.shared("inferred_broadcasters", lambda: list(_infer(scene)))


@dataclass(frozen=True)
class Repeats:
    """The samples of one edge's stream (in arrival order) that carry a stamp sent before, as observed."""

    again: BoolArray  # per sample: its stamp was sent before
    identical: BoolArray  # per sample: its stamp and value were sent before
    stamps: int  # distinct stamps
    stamps_again: int  # distinct stamps sent more than once
    times: tuple[int, int]  # fewest and most times one of those came
    apart: float  # median ns between a repeat and the sample before it
    interval: float  # median ns between a new sample and the sample before it
    newest: float  # share of the repeats that carry the newest stamp sent so far

    @property
    def resent(self) -> bool:
        """Repeats as long after the sample before them as new samples come: one publisher's timer."""
        return self.apart >= RESEND_SHARE * self.interval > 0

    @property
    def alike(self) -> bool:
        """Each stamp sent again about as many times (``TWINS_SPREAD``): copies from a number of publishers."""
        return self.times[1] <= TWINS_SPREAD * self.times[0]

    def said(self, whose: str = "its") -> str:
        """ "182 of its 598 stamps arrived again (2 times each)"."""
        low, high = self.times
        each = f"{low} times each" if low == high else f"{low} to {high} times each"
        return f"{self.stamps_again} of {whose} {self.stamps} stamps arrived again ({each})"

    def timing(self) -> str:
        """ "21 ms after the sample before them (new samples: every 20 ms)"."""
        return f"{_ms(self.apart)} after the sample before them (new samples come every {_ms(self.interval)})"

    def figures(self) -> dict[str, float | int | str]:
        return {
            "stamps": self.stamps,
            "stamps_sent_again": self.stamps_again,
            "times_min": self.times[0],
            "times_max": self.times[1],
            "repeat_after_s": self.apart / NS_PER_S,
            "new_sample_interval_s": self.interval / NS_PER_S,
            "newest_share": round(self.newest, 3),
        }


def repeats_of(stamps: Int64Array, values: FloatArray, arrivals: Int64Array) -> Repeats:
    """What the stream of one edge (``stamps``, ``values``, ``arrivals`` in arrival order) sent again."""
    again = sent_before(stamps)
    identical = sent_before(stamps, values)
    distinct, counts = np.unique(stamps, return_counts=True)
    more = counts[counts > 1]
    gaps = np.diff(arrivals).astype(np.float64)
    repeat_gaps, new_gaps = gaps[again[1:]], gaps[~again[1:]]
    newest_before = np.maximum.accumulate(stamps)
    return Repeats(
        again,
        identical,
        len(distinct),
        len(more),
        (int(more.min()), int(more.max())) if len(more) else (1, 1),
        float(np.median(repeat_gaps)) if len(repeat_gaps) else 0.0,
        float(np.median(new_gaps)) if len(new_gaps) else 0.0,
        float((stamps[again] == newest_before[again]).mean()) if again.any() else 0.0,
    )


def _listed_said(scene: Scene, topics: tuple[str, ...]) -> tuple[str, int | None]:
    """ "; metadata.yaml lists 2 publishers of /tf when recording began" where it does."""
    listed_counts = [(listing, t) for t in topics if (listing := listed_publishers(scene.recording.qos, t)) is not None]
    if not listed_counts:
        return "", None
    listing, topic = max(listed_counts)
    return f"; {listing.said(topic)} when recording began", listing.publishers


def _infer(scene: Scene) -> list[Finding]:
    if scene.publishers_known:
        return []
    rows = scene.rows
    found = []
    twins: dict[tuple[str, ...], list[tuple[tuple[str, str], IntpArray, Repeats]]] = {}
    shaped: dict[tuple[int, int], list[tuple[tuple[str, str], IntpArray, Split]]] = {}
    layouts = message_layouts(scene)
    for parent, child, mine in rows.by_edge(rows.usable & ~rows.static):
        frames = (parent, child)
        repeats = repeats_of(rows.stamp[mine], rows.values[mine], scene.received(mine))
        if _enough(repeats.stamps_again, repeats.stamps):
            if repeats.resent and repeats.newest >= NEWEST_SHARE:
                found.append(_resent(scene, frames, mine, repeats))
                continue
            if not repeats.resent and repeats.stamps_again >= TWINS_SHARE * repeats.stamps and repeats.alike:
                twins.setdefault(scene.authorities_of(mine), []).append((frames, mine, repeats))
                continue
        split = _in_two_layouts(scene, layouts, mine)
        if split is not None:
            shaped.setdefault(split.layouts, []).append((frames, mine, split))
            continue
        new = mine[~repeats.again]  # a publisher re-sending an old stamp is one publisher, not a turn
        clocks = _two_clocks(scene, new)
        if clocks is not None:  # each clock's stamps rise on their own: turns between clocks, no stamp going back
            found.append(_replayed_beside(scene, frames, mine, new, clocks))
            continue
        back = _back_and_forth(rows.stamp[new])
        if back and _more_rising_streams(rows.stamp[new], max(TURNS_PUBLISHERS, _listed_count(scene, mine))):
            back = 0  # more publishers than listed would each have to rise: one sends out of order (time_backwards)
        alternating = _alternating(rows.values[new])
        if not (_enough(back, len(new)) or _enough(alternating, len(new))):
            continue
        apart_ = _tracks_apart(rows.stamp[new], rows.values[new])
        if apart_ is None:  # no two places to follow: a rotation turning about as far as it comes back (a wheel
            alternating = _alternating(rows.values[new], turns=False)  # half a turn a sample) is one value
        signs = [
            f"its stamps went back {back} times" if _enough(back, len(new)) else "",
            f"its value alternated between two places {alternating} times" if _enough(alternating, len(new)) else "",
        ]
        if not any(signs):
            continue
        authorities = scene.authorities_of(mine)
        metadata, _ = _listed_said(scene, authorities)
        finding = scene.finding(
            apart_.severity if apart_ is not None else Severity.warning,
            "multiple_authorities",
            f"{edge(*frames)}{scene.by(authorities)}: {listed([s for s in signs if s])} in {len(new)} new samples"
            f"{'; ' + apart_.said(scene) if apart_ is not None else ''}"
            f"{metadata}: several broadcasters taking turns, it seems (this recording does not name publishers)"
            f"{apart_.follows() if apart_ is not None else ''}",
            "tf2 takes every sample as it comes, so lookups mix the broadcasters' values: find them "
            f"({scene.list_publishers('/tf')}) and turn the transform off in all but one",
            frames,
            mine,
            scene.arrival(mine),
        )
        figures: dict[str, float | int | str] = {"samples": len(mine), "new_samples": len(new)}
        figures |= {"stamps_back": back, "values_alternating": alternating}
        figures |= apart_.figures() if apart_ is not None else {}
        found.append(dataclasses.replace(finding, figures=figures))
    return found + [_twins(scene, edges) for edges in twins.values()] + [_shaped(scene, e) for e in shaped.values()]


@dataclass(frozen=True)
class Split:
    """One edge's samples in two message layouts (``layouts``) that take turns, and how far apart the two are."""

    layouts: tuple[int, int]  # the two layouts (``Layouts.layout``), the smaller number first
    rows: tuple[IntpArray, IntpArray]  # the edge's rows in each, in arrival order
    turns: int  # samples (of those two layouts, in arrival order) in another layout than the one before
    compared: AtOnce
    both: int  # stamps sent in both layouts with other values
    both_apart: tuple[float, float]  # how far apart at those stamps, at most (m, degrees)


def _in_two_layouts(scene: Scene, layouts: Layouts, mine: IntpArray) -> Split | None:
    """The edge's samples (``mine``, in arrival order) in the two layouts it came in most, where each holds
    ``TURNS_MIN`` of them and ``TURNS_SHARE`` at least, they take turns sample after sample, and their values
    contradict each other at ``TURNS_SHARE`` of the times compared (``at_once``): a sender of one layout does not
    send the other's values. None otherwise: one layout, or one sender whose messages vary (a tracker sending the
    objects in view) and whose values agree."""
    of = layouts.layout[mine]
    known = of >= 0
    ids, counts = np.unique(of[known], return_counts=True)
    large = ids[np.argsort(-counts, kind="stable")[:2]]
    if len(large) < 2 or any(not _enough(int(c), len(mine)) for c in np.sort(counts)[-2:]):
        return None
    pair = (int(min(large)), int(max(large)))
    inside = np.isin(of, pair)
    turns = int(np.count_nonzero(np.diff(of[inside])))
    if not _enough(turns, int(np.count_nonzero(inside))):
        return None
    rows = scene.rows
    each = tuple(mine[of == k] for k in pair)
    streams = []
    for part in each:
        ordered = part[np.argsort(rows.stamp[part], kind="stable")]
        streams.append((rows.stamp[ordered], rows.values[ordered]))
    compared = at_once(streams)
    if compared is None or not _enough(compared.contradicting, compared.apart.instants):
        return None
    (a_stamps, a_values), (b_stamps, b_values) = streams
    _, at_a, at_b = np.intersect1d(a_stamps, b_stamps, assume_unique=False, return_indices=True)
    metres, degrees = apart(a_values[at_a], b_values[at_b])
    other = (metres >= NIL_M) | (degrees >= NIL_DEG)
    if not other.any():  # one stamp sent in both kinds with other values: what one publisher never does
        return None
    both_apart = (float(metres.max(initial=0.0)), float(degrees.max(initial=0.0)))
    return Split(pair, (each[0], each[1]), turns, compared, int(np.count_nonzero(other)), both_apart)


def _shaped(scene: Scene, edges: list[tuple[tuple[str, str], IntpArray, Split]]) -> Finding:
    """Edges that come in two message layouts taking turns, whose values contradict each other: two senders, each
    sending its own set of transforms (or one robot_state_publisher fed /joint_states by two sources)."""
    rows = scene.rows
    layouts = message_layouts(scene)
    largest = max((split.compared for _, _, split in edges), key=lambda c: (c.apart.metres, c.apart.degrees))
    apart_ = dataclasses.replace(largest.apart, instants=sum(s.compared.apart.instants for _, _, s in edges))
    compared = dataclasses.replace(
        largest, apart=apart_, contradicting=sum(s.compared.contradicting for _, _, s in edges)
    )
    _, _, first = edges[0]
    named = [edge(*frames) for frames, _, _ in edges]
    kinds = []
    sides = sorted((0, 1), key=lambda side: int(first.rows[side][0]))  # in order of first arrival
    for side in sides:
        held = layouts.edges(scene, first.layouts[side])
        others = [e for e in held if e not in named]
        mine = first.rows[side]
        stamps = np.sort(rows.stamp[mine])
        still = all(bool(np.ptp(rows.values[split.rows[side]], axis=0).max() == 0.0) for _, _, split in edges)
        held_at = _held_at(
            [(name, rows.values[split.rows[side][:1]][0]) for name, (_, _, split) in zip(named, edges, strict=True)]
        )
        kinds.append(
            f"{len(mine)} messages of {transforms(len(held))} "
            f"({_with(others)}), every {_ms(period(np.diff(stamps)))}{held_at if still else ''}"
        )
    every = np.sort(np.concatenate([mine for _, mine, _ in edges]))
    authorities = scene.authorities_of(every)
    metadata, listed_count = _listed_said(scene, authorities)
    both = _each([split.both for _, _, split in edges], "stamp")
    both_m = max(split.both_apart[0] for _, _, split in edges)
    both_deg = max(split.both_apart[1] for _, _, split in edges)
    again = (
        f"; {both} came in both, with other values up to {_far_as(both_m, both_deg)} apart ({_held_twice(scene)})"
        if any(split.both for _, _, split in edges)
        else ""
    )
    turns = sum(split.turns for _, _, split in edges)
    samples = sum(len(split.rows[0]) + len(split.rows[1]) for _, _, split in edges)
    each = {(s.turns, len(s.rows[0]) + len(s.rows[1])) for _, _, s in edges}
    if len(edges) > 1 and len(each) == 1:
        taking = "{} turns in {} samples, each".format(*each.pop())
    else:
        taking = f"{turns} turns in {samples} samples"
    names = and_joined(named, LISTED)
    finding = scene.finding(
        compared.severity,
        "multiple_authorities",
        f"{names}{scene.by(authorities)} {'come' if len(edges) > 1 else 'comes'} in two kinds of message taking turns "
        f"({taking}): {kinds[0]}, and {kinds[1]}{again}; {compared.said(scene)}"
        f"{metadata}: two publishers, it seems, each sending its own set of transforms (or one "
        f"robot_state_publisher fed /joint_states by two sources); this recording does not name publishers"
        f"{compared.follows()}",
        f"tf2 takes every sample as it comes, so lookups mix the two: find them ({scene.list_publishers('/tf')}; "
        f"where robot_state_publisher sends both, {scene.list_publishers('/joint_states')}) and stop the one that "
        "should not send these transforms",
        tuple(f for frames, _, _ in edges for f in frames),
        every,
        scene.arrival(every),
    )
    figures: dict[str, float | int | str] = {"edges": len(edges), "samples": samples, "layouts": 2, "turns": turns}
    figures |= {"messages_first_kind": len(first.rows[sides[0]]), "messages_second_kind": len(first.rows[sides[1]])}
    figures |= {
        "stamps_in_both_with_other_values": sum(split.both for _, _, split in edges),
        "both_apart_m_max": both_m,
        "both_apart_deg_max": both_deg,
    }
    figures |= compared.figures()
    if listed_count is not None:
        figures["publishers_listed"] = listed_count
    return dataclasses.replace(finding, figures=figures)


def _with(others: list[str]) -> str:
    """ "with a -> b and c -> d", "with a -> b, ... and 3 more", "nothing else": the other edges of a message."""
    if not others:
        return "nothing else"
    return "with " + (and_joined(others) if len(others) <= LISTED else listed(others, LISTED))


def _each(counts: list[int], thing: str) -> str:
    """ "15 stamps of each" where every edge counts the same, else their sum: "31 stamps"."""
    if len(counts) > 1 and len(set(counts)) == 1:
        return f"{counted(counts[0], thing)} of each"
    return counted(sum(counts), thing)


def _held_twice(scene: Scene) -> str:
    """What tf2 does with a stamp it holds sent again with another value (``semantics``' table)."""
    if scene.buffer.semantics == "ros2":
        return (
            "ROS 2's tf2 keeps both: at that stamp it answers with the one received last, the first while it is the "
            "oldest stamp held"
        )
    return "ROS 1's tf2 keeps the first and refuses the other (TF_REPEATED_DATA)"


def _held_at(values: list[tuple[str, FloatArray]]) -> str:
    """Where the edges of one kind of message never change, their one value each from its parent: ", in which
    a -> b and c -> d never change, each always at 0.0 mm and 0.00° (the identity)"."""
    names = and_joined([name for name, _ in values])
    identity = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]])
    far = [apart(identity, value.reshape(1, 7)) for _, value in values]
    said = [f"{float(m[0]) * 1000:.1f} mm and {float(d[0]):.2f}°" for m, d in far]
    nil = all(float(m[0]) < NIL_M and float(d[0]) < NIL_DEG for m, d in far)
    if len(set(said)) == 1:
        at = f"{'each ' if len(values) > 1 else ''}always at {said[0]} from its parent"
    else:
        at = "always at " + and_joined([f"{s} ({name})" for (name, _), s in zip(values, said, strict=True)])
    changing = "never changes" if len(values) == 1 else "never change"
    return f", in which {names} {changing}, {at}{' (the identity)' if nil else ''}"


def _far_as(metres: float, degrees: float) -> str:
    """ "84.27°", "12.3 mm and 1.20°": what was seen apart, nothing said where it is nil."""
    said = [f"{metres * 1000:.1f} mm" if metres >= NIL_M else "", f"{degrees:.2f}°" if degrees >= NIL_DEG else ""]
    return " and ".join(s for s in said if s) or "nothing"


@dataclass(frozen=True)
class Clocks:
    """One edge's new samples (in arrival order) on two time bases, taking turns (``_two_clocks``)."""

    base: IntpArray  # per sample: 0 on the older time base (the one further behind its arrival), 1 on the newer
    turns: int  # samples on another base than the one before them
    behind: int  # how far (ns) the older base's stamps are behind the newer's, at arrival (medians)
    offsets: tuple[int, int]  # arrival minus stamp (ns, medians) on the older base, then on the newer
    counts: tuple[int, int]  # samples on each base
    periods: tuple[int, int]  # the usual interval between stamps on each base (ns)


def _two_clocks(scene: Scene, new: IntpArray) -> Clocks | None:
    """Stamps of one stream on two time bases further apart than the stream took to arrive (``figures.
    time_base_of`` over arrival minus stamp), sample after sample, each base's stamps rising on their own:
    two publishers on two clocks (a recording replayed with its own /tf beside live nodes); None otherwise."""
    rows = scene.rows
    stamps, arrived = rows.stamp[new], scene.received(new)
    offsets = arrived - stamps
    base = time_base_of(offsets, record_span(rows.record_time[new]))
    if int(base.max(initial=0)) != 1:
        return None
    turns = int(np.count_nonzero(np.diff(base)))
    each = [stamps[base == b] for b in (0, 1)]
    if not _enough(turns, len(new)) or any(len(e) < TURNS_MIN or bool(np.any(np.diff(e) < 0)) for e in each):
        return None
    older = np.where(base == 1, 0, 1)  # base 0 holds the smaller offsets: the newer clock
    medians = [median_ns(offsets[base == b]) for b in (0, 1)]
    counts = (int(np.count_nonzero(base == 1)), int(np.count_nonzero(base == 0)))
    periods = (period(np.diff(each[1])), period(np.diff(each[0])))
    return Clocks(older, turns, medians[1] - medians[0], (medians[1], medians[0]), counts, periods)


def _replayed_beside(scene: Scene, frames: tuple[str, str], mine: IntpArray, new: IntpArray, c: Clocks) -> Finding:
    """Two publishers of one edge on two clocks taking turns: the root cause, said from what was observed."""
    authorities = scene.authorities_of(mine)
    metadata, _ = _listed_said(scene, authorities)
    behind = duration(c.behind / NS_PER_S)
    play = "ros2 bag play" if scene.ros2 else "rosbag play"
    finding = scene.finding(
        Severity.warning,
        "multiple_authorities",
        f"{edge(*frames)}{scene.by(authorities)}: its stamps take turns between two time bases {behind} apart "
        f"({c.turns} turns in {len(new)} new samples), each rising on its own: {c.counts[0]} samples every "
        f"{_ms(c.periods[0])} stamped {behind} further behind their arrival than the {c.counts[1]} others, every "
        f"{_ms(c.periods[1])}{metadata}: two publishers on two clocks, one of them sending old data (a "
        "recording replayed with its own /tf beside live nodes, it seems)",
        f"tf2 takes both, and refuses the older one's samples once the newer arrived (TF_OLD_DATA): replay the "
        f"recording without this transform (filter it out of its /tf), or with {play} --clock and "
        f"use_sim_time for every node; or stop the live publisher ({scene.list_publishers('/tf')})",
        frames,
        mine,
        scene.arrival(mine),
    )
    figures: dict[str, float | int | str] = {"samples": len(mine), "new_samples": len(new), "time_bases": 2}
    figures |= {"turns": c.turns, "behind_s": c.behind / NS_PER_S, "older_samples": c.counts[0]}
    figures |= {"older_period_s": c.periods[0] / NS_PER_S, "newer_period_s": c.periods[1] / NS_PER_S}
    figures |= {"older_offset_s": c.offsets[0] / NS_PER_S, "newer_offset_s": c.offsets[1] / NS_PER_S}
    return dataclasses.replace(finding, figures=figures)


def _enough(count: int, samples: int, share: float = TURNS_SHARE) -> bool:
    return count >= TURNS_MIN and count >= share * samples


def sent_before(stamps: Int64Array, values: FloatArray | Callable[[IntpArray], FloatArray] | None = None) -> BoolArray:
    """Which samples (in arrival order) carry a stamp an earlier one of the same stream carried (and its
    value too, if ``values`` are given, or the function giving those of some samples: a clock reset that
    replays old stamps elsewhere is new data)."""
    if values is None:
        again = np.ones(len(stamps), bool)
        again[first_and_inverse(stamps)[0]] = False
        return again
    # only a stamp carried more than once can carry its value again: those samples' values alone are read
    inverse = first_and_inverse(stamps)[1]
    shared = np.flatnonzero(np.bincount(inverse)[inverse] > 1)
    del inverse
    again = np.zeros(len(stamps), bool)
    if not len(shared):
        return again
    sub = values(shared) if callable(values) else np.asarray(values)[shared]
    # the same stamp and value bit for bit (a value's 64 bits as an integer: -0.0 is not 0.0, a NaN is its bits),
    # by a stable sort of integers: not a 64-byte record a sample sorted as bytes (0.1 GB and seconds a 1M)
    bits = np.ascontiguousarray(sub, np.float64).reshape(len(shared), 7).view(np.int64)
    columns = [bits[:, i] for i in range(6, -1, -1)] + [np.asarray(stamps[shared], np.int64)]  # the stamp sorts first
    order = np.lexsort(columns)
    new = np.zeros(len(shared), bool)  # a row unlike the one before it in that order: its stamp and value's first
    new[:1] = True
    for column in columns:
        ordered = column[order]
        new[1:] |= ordered[1:] != ordered[:-1]
    first = np.zeros(len(shared), bool)
    first[order[new]] = True
    again[shared] = ~first
    return again


def _resent(scene: Scene, frames: tuple[str, str], mine: IntpArray, repeats: Repeats) -> Finding:
    """One publisher re-sending its last sample on its own timer: the newest stamp again, its value the same
    but where the publisher changed it in between (slam_toolbox's first correction of a scan); those stamps
    are ``time_backwards``' to report, as they change what tf2 answers."""
    authorities = scene.authorities_of(mine)
    metadata, listed_count = _listed_said(scene, authorities)
    revalued = mine[repeats.again & ~repeats.identical]
    if scene.buffer.semantics == "ros2":
        copies = "ROS 2's tf2 takes an identical sample again without a word"
    else:
        copies = "ROS 1's tf2 refuses each copy (TF_REPEATED_DATA), which changes nothing but the log"
    values, effect = "with identical values", f"nothing to fix: {copies}"
    if len(revalued):
        stamps = counted(len(np.unique(scene.rows.stamp[revalued])), "stamp")
        values += f" but {stamps} that came again with another value, first at {scene.first_at(revalued)}"
        effect = f"the copies: {copies}; the {stamps} re-valued: time_backwards says which value tf2 answers"
    finding = scene.finding(
        Severity.info,
        "resent",
        f"{edge(*frames)}{scene.by(authorities)}: {repeats.said()}, {values}, {repeats.timing()}, each time the "
        f"newest stamp sent so far{metadata}: one publisher re-sending its last value, not two",
        f"{effect}; a publisher on a timer sends its last transform again when its input has not changed "
        "(a simulation step not yet taken, no new scan)",
        frames,
        mine[repeats.again],
        scene.arrival(mine[repeats.again]),
    )
    figures = repeats.figures() | {"stamps_revalued": len(np.unique(scene.rows.stamp[revalued]))}
    figures |= {"publishers_listed": listed_count} if listed_count is not None else {}
    return dataclasses.replace(finding, figures=figures)


def _twins(scene: Scene, edges: list[tuple[tuple[str, str], IntpArray, Repeats]]) -> Finding:
    """Most stamps of ``edges`` (of the same topics) sent again, soon after the first: two broadcasters of
    the same transforms, each sending every sample (two robot_state_publishers fed the same joint states)."""
    rows = scene.rows
    each = [_copies_apart(rows.stamp[mine], rows.values[mine], repeats.again) for _, mine, repeats in edges]
    found = [d for d in each if d is not None]
    largest = max(found, key=lambda d: (d.apart.metres, d.apart.degrees))  # every edge here has copies: one at least
    apart_ = dataclasses.replace(largest.apart, instants=sum(d.apart.instants for d in found))
    compared = dataclasses.replace(largest, apart=apart_, contradicting=sum(d.contradicting for d in found))
    most = max(repeats.times[1] for _, _, repeats in edges)
    times = "twice" if most <= 2 else f"{most} times"
    if _nil(apart_):
        effect = f"tf2 drops the exact copies, so lookups are right, but every sample costs {times}"
    else:
        effect = "tf2 keeps both where they differ, so lookups mix the two publishers' values"
    every = np.sort(np.concatenate([mine for _, mine, _ in edges]))
    together = _together([repeats for _, _, repeats in edges])
    authorities = scene.authorities_of(every)
    metadata, listed_count = _listed_said(scene, authorities)
    if listed_count == 1:
        more = "a second one" if most <= 2 else "more"
        conclusion = f"one publisher sending each sample {times}, or {more} started after recording began"
    else:
        several = "two" if most <= 2 else str(most)
        conclusion = f"{several} identical publishers, it seems ({several} robot_state_publishers, or one launched "
        conclusion += f"{times})"
    named = [edge(*frames) for frames, _, _ in edges]
    names = and_joined(named, LISTED)
    finding = scene.finding(
        compared.severity,
        "multiple_authorities",
        f"{names}{scene.by(authorities)} {'arrive' if len(edges) > 1 else 'arrives'} {times}: "
        f"{together.said('their' if len(edges) > 1 else 'its')}, {together.timing()}; {compared.said(scene)}"
        f"{metadata}: {conclusion}; this recording does not name publishers{compared.follows()}",
        f"{effect}: find them ({scene.list_publishers('/tf')}) and stop the one that should not run",
        tuple(f for frames, _, _ in edges for f in frames),
        every,
        scene.arrival(every),
    )
    figures = together.figures() | {"edges": len(edges)} | compared.figures()
    if listed_count is not None:
        figures["publishers_listed"] = listed_count
    return dataclasses.replace(finding, figures=figures)


def apart_said(scene: Scene, apart_: Disagreement) -> str:
    """How far several publishers of one edge are apart (``figures.disagreement``), in the one wording every
    multiple_authorities finding uses: "at the same times their values are up to 10.2 mm (at +0.6 s) apart,
    over 254 samples compared"; each largest figure with when it was seen, none said where it is nil."""
    said = [
        f"{value} (at {scene.rel(at)})"
        for value, at, seen in (
            (f"{apart_.metres * 1000:.1f} mm", apart_.metres_at, apart_.metres >= NIL_M),
            (f"{apart_.degrees:.2f}°", apart_.degrees_at, apart_.degrees >= NIL_DEG),
        )
        if seen
    ]
    values = f"are up to {' and '.join(said)} apart" if said else "are the same"
    return f"at the same times their values {values}, over {apart_.instants} samples compared"


def apart_figures(apart_: Disagreement) -> dict[str, float | int | str]:
    """``apart_said``'s figures, for JSON."""
    return {"apart_m_max": apart_.metres, "apart_deg_max": apart_.degrees, "samples_compared": apart_.instants}


def _nil(apart_: Disagreement) -> bool:
    return apart_.metres < NIL_M and apart_.degrees < NIL_DEG


def _copies_apart(stamps: Int64Array, values: FloatArray, again: BoolArray) -> AtOnce | None:
    """How far the copies of an edge's stamps (``again``) are from the first sample of each: at those very
    stamps only (a stamp sent once is not interpolated against the copies around it)."""
    copied = np.unique(stamps[again])
    first_rows = np.flatnonzero(~again & np.isin(stamps, copied))
    firsts = first_rows[np.argsort(stamps[first_rows], kind="stable")]
    copies = np.flatnonzero(again)
    copies = copies[np.argsort(stamps[copies], kind="stable")]
    return at_once([(stamps[firsts], values[firsts]), (stamps[copies], values[copies])])


def _tracks_apart(stamps: Int64Array, values: FloatArray) -> AtOnce | None:
    """How far two broadcasters taking turns are apart: the samples (in arrival order; the first
    ``TRACKED_SAMPLES``) told into tracks, each to the nearest of the ``TRACKS_HELD`` tracks extended last (by
    its last value), a new one where none is within ``TRACK_APART`` times two places' distance (``APART_M``,
    ``APART_DEG``); then the two largest tracks that overlap in time (of the ``TRACKS_COMPARED`` largest)
    compared at the same times (``at_once``). None where no two do (stamps going back with the
    same values, or values too scattered to follow)."""
    stamps, values = stamps[:TRACKED_SAMPLES], values[:TRACKED_SAMPLES]
    track = np.zeros(len(stamps), np.intp)
    rows = values.tolist()  # a sample at a time, in plain floats: numpy's per-call cost would dominate
    held = [0]  # the tracks a sample may join, the one extended last at the end
    last = {0: rows[0]}
    for i in range(1, len(rows)):
        far = [_distance(last[t], rows[i]) for t in held]
        nearest = min(range(len(held)), key=far.__getitem__)
        joined = held.pop(nearest) if far[nearest] <= TRACK_APART else len(last)
        held = [*held, joined][-TRACKS_HELD:]
        last[joined] = rows[i]
        track[i] = joined
    sizes = np.bincount(track)
    large = [int(t) for t in np.argsort(-sizes, kind="stable")[:TRACKS_COMPARED] if sizes[t] >= TURNS_MIN]
    for a, b in sorted(itertools.combinations(large, 2), key=lambda p: -(sizes[p[0]] + sizes[p[1]])):
        streams = []
        for t in (a, b):
            mine = np.flatnonzero(track == t)
            mine = mine[np.argsort(stamps[mine], kind="stable")]
            streams.append((stamps[mine], values[mine]))
        found = at_once(streams)
        if found is not None:
            return found
    return None


def _distance(a: list[float], b: list[float]) -> float:
    """How far two values (x y z qx qy qz qw) are, in units of two places' distance (``APART_M``, ``APART_DEG``):
    ``apart``'s metres and rotation angle, for one pair."""
    metres = math.dist(a[:3], b[:3])
    norms = math.hypot(*a[3:]) * math.hypot(*b[3:])
    cosine = min(1.0, abs(sum(x * y for x, y in zip(a[3:], b[3:], strict=True))) / norms) if norms > 0 else 1.0
    return max(metres / APART_M, math.degrees(2.0 * math.acos(cosine)) / APART_DEG)


def _together(each: list[Repeats]) -> Repeats:
    """The repeats of several edges counted as one: stamps added up, intervals their median."""
    if len(each) == 1:
        return each[0]
    return Repeats(
        np.concatenate([r.again for r in each]),
        np.concatenate([r.identical for r in each]),
        sum(r.stamps for r in each),
        sum(r.stamps_again for r in each),
        (min(r.times[0] for r in each), max(r.times[1] for r in each)),
        float(np.median([r.apart for r in each])),
        float(np.median([r.interval for r in each])),
        float(np.mean([r.newest for r in each])),
    )


def _ms(ns: float) -> str:
    """A short interval: "40 us", "20.5 ms", "1.2 s"."""
    if ns < 1e6:
        return f"{ns / 1e3:.0f} us"
    return f"{ns / 1e6:.1f} ms" if ns < NS_PER_S else duration(ns / NS_PER_S)


def _listed_count(scene: Scene, mine: IntpArray) -> int:
    """How many publishers of ``mine``'s topics the recording lists (0 where no file says)."""
    return _listed_said(scene, scene.authorities_of(mine))[1] or 0


def _more_rising_streams(stamps: Int64Array, limit: int) -> bool:
    """Whether ``stamps`` (in arrival order) need more than ``limit`` streams of rising stamps: a run of ever earlier
    stamps among them longer than that (patience sorting), more publishers than ``limit`` each sending in order.
    A real cart's amcl sends map -> odom for six queued scans at once, in no order (six in a row stamped ever
    earlier), after each odometry sample that came at 0.9 Hz: one publisher out of order, not six taking turns."""
    tails: list[int] = []  # per run length, the latest possible last stamp of a falling run that long
    for stamp in (-stamps).tolist():
        at = bisect.bisect_left(tails, stamp)
        tails[at : at + 1] = [stamp]
        if len(tails) > limit:
            return True
    return False


def _back_and_forth(stamps: Int64Array) -> int:
    """Stamps (in arrival order) earlier than the one before them, each followed by a later one again:
    one late message, or a clock jumped back once, is not a turn."""
    steps = np.sign(np.diff(stamps))
    return int(((steps[:-1] < 0) & (steps[1:] > 0)).sum())


def _alternating(values: FloatArray, turns: bool = True) -> int:
    """Samples (in arrival order) far from the one before and the one after, which are close to each
    other: a value that goes somewhere else and comes back, sample after sample (by its place, and by its
    rotation where ``turns``: a rotation of nearly half a turn a sample also comes back near where it was).
    Not the turning point of a motion, where the sample two before lies further back still (``TURNING``): a
    Gazebo Neato's heading wobbling 1.1 degrees a sample either way (a wall follower's oscillation) turns at
    every crest. Not noise, out and back no further than the stream's own step (``BEYOND_NOISE``)."""
    if len(values) < 3:
        return 0
    out_m, out_deg = apart(values[:-2], values[1:-1])
    back_m, back_deg = apart(values[1:-1], values[2:])
    round_m, round_deg = apart(values[:-2], values[2:])
    came_m, came_deg = np.zeros(len(out_m)), np.zeros(len(out_m))  # from the sample two before each to it
    came_m[1:], came_deg[1:] = apart(values[:-3], values[2:-1])
    # beyond the noise: further out than samples two apart usually are from each other (one publisher's own step)
    noise_m, noise_deg = BEYOND_NOISE * float(np.median(round_m)), BEYOND_NOISE * float(np.median(round_deg))
    moved = (out_m > max(APART_M, noise_m)) & (back_m > APART_M) & (round_m < out_m / 4) & (came_m <= TURNING * out_m)
    if turns:
        moved |= (
            (out_deg > max(APART_DEG, noise_deg))
            & (back_deg > APART_DEG)
            & (round_deg < out_deg / 4)
            & (came_deg <= TURNING * out_deg)
        )
    return int(moved.sum())
