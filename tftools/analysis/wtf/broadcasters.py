"""Several broadcasters of one moving edge where the recording does not name publishers (ROS 2 bags,
MCAP), told from what the edge's stream holds: its stamps, values, when each sample arrived, and how many
publishers of its topic metadata.yaml lists. Four patterns are told apart:

- a stamp sent again with the same value, the newest stamp each time, as long after the sample before it
  as new samples come: one publisher re-sending its last value (a timer whose input did not change: a
  simulation step not yet taken, no new scan); a note, which counts the stamps it re-valued in between
  (slam_toolbox's first correction of a scan), ``time_backwards``' to report;
- most stamps sent again, each soon after the first (well within the stream's interval): two identical
  publishers (two robot_state_publishers), or two that disagree where the values differ;
- among the samples not sent before, stamps going back and forth or values alternating between two
  places, sample after sample: publishers taking turns;
- anything else is one publisher (intervals alternating on a stepped clock, stamps rising, values smooth)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.wtf.scene import Scene, and_joined, duration, edge, listed
from tftools.core.arrays import BoolArray, FloatArray, Int64Array, IntpArray
from tftools.core.rotation import angle_between_many
from tftools.core.time import NS_PER_S

#: A sign must show in this many samples, and this share of them, to tell two broadcasters.
TURNS_MIN = 5
TURNS_SHARE = 0.1
#: Two values this far apart (m, degrees) are two places; coming back within a quarter of it, the same one.
APART_M = 0.01
APART_DEG = 1.0
#: Two identical broadcasters: at least this share of an edge's stamps sent twice (or more).
TWINS_SHARE = 0.5
#: A copy that comes at least this share of the stream's usual interval after the sample before it is a
#: re-send on the publisher's own timer; one that comes sooner, a second publisher's copy of the same input.
RESEND_SHARE = 0.5
#: Edges named in one finding; the rest are counted.
LISTED = 6
#: Re-sends of the last value: at least this share of the copies carry the newest stamp sent so far.
NEWEST_SHARE = 0.9


def inferred_broadcasters(scene: Scene) -> list[Finding]:
    """One ``multiple_authorities`` finding (a warning) per moving edge that several broadcasters seem to
    send, where the recording names no publishers (none elsewhere); computed once per scene."""
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


def listed_publishers(scene: Scene, topic: str) -> int | None:
    """How many publishers of ``topic`` the recording's metadata.yaml lists (one per publisher the recorder
    found when it began: ``offered_qos_profiles``); None where no file says."""
    found = [qos.counts[topic][1] for qos in scene.recording.qos.values() if topic in qos.counts]
    return max(found) if found else None


def _listed_said(scene: Scene, topics: tuple[str, ...]) -> tuple[str, int | None]:
    """ "; metadata.yaml lists 2 publishers of /tf" where it does."""
    listed_counts = [(n, t) for t in topics if (n := listed_publishers(scene, t)) is not None]
    if not listed_counts:
        return "", None
    n, topic = max(listed_counts)
    return f"; metadata.yaml lists {counted(n, 'publisher')} of {topic} when recording began", n


def _infer(scene: Scene) -> list[Finding]:
    if scene.publishers_known:
        return []
    rows = scene.rows
    found = []
    twins: dict[tuple[str, ...], list[tuple[tuple[str, str], IntpArray, Repeats]]] = {}
    for parent, child, mine in rows.by_edge(rows.usable & ~rows.static):
        frames = (parent, child)
        repeats = repeats_of(rows.stamp[mine], rows.values[mine], scene.received(mine))
        if _enough(repeats.stamps_again, repeats.stamps):
            if repeats.resent and repeats.newest >= NEWEST_SHARE:
                found.append(_resent(scene, frames, mine, repeats))
                continue
            if not repeats.resent and repeats.stamps_again >= TWINS_SHARE * repeats.stamps:
                twins.setdefault(scene.authorities_of(mine), []).append((frames, mine, repeats))
                continue
        new = mine[~repeats.again]  # a publisher re-sending an old stamp is one publisher, not a turn
        back = _back_and_forth(rows.stamp[new])
        alternating = _alternating(rows.values[new])
        signs = [
            f"its stamps went back {back} times" if _enough(back, len(new)) else "",
            f"its value alternated between two places {alternating} times" if _enough(alternating, len(new)) else "",
        ]
        if not any(signs):
            continue
        authorities = scene.authorities_of(mine)
        metadata, _ = _listed_said(scene, authorities)
        finding = scene.finding(
            Severity.warning,
            "multiple_authorities",
            f"{edge(*frames)}{scene.by(authorities)}: {listed([s for s in signs if s])} in {len(new)} new samples"
            f"{metadata}: several broadcasters taking turns, it seems (this recording does not name publishers)",
            "tf2 takes every sample as it comes, so lookups mix the broadcasters' values: find them "
            f"({scene.list_publishers('/tf')}) and turn the transform off in all but one",
            frames,
            mine,
            scene.arrival(mine),
        )
        figures: dict[str, float | int | str] = {"samples": len(mine), "new_samples": len(new)}
        figures |= {"stamps_back": back, "values_alternating": alternating}
        found.append(dataclasses.replace(finding, figures=figures))
    return found + [_twins(scene, edges) for edges in twins.values()]


def _enough(count: int, samples: int, share: float = TURNS_SHARE) -> bool:
    return count >= TURNS_MIN and count >= share * samples


def sent_before(stamps: Int64Array, values: FloatArray | None = None) -> BoolArray:
    """Which samples (in arrival order) carry a stamp an earlier one of the same stream carried (and its
    value too, if ``values`` are given: a clock reset that replays old stamps elsewhere is new data)."""
    keys: np.ndarray = stamps
    if values is not None:
        table = np.empty(len(stamps), [("stamp", np.int64), ("value", np.float64, (7,))])
        table["stamp"], table["value"] = stamps, values
        keys = table.view(np.dtype((np.void, table.dtype.itemsize)))
    first = np.zeros(len(stamps), bool)
    first[np.unique(keys, return_index=True)[1]] = True
    return ~first


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
    metres, degrees = 0.0, 0.0
    for _, mine, repeats in edges:
        stamps, values = rows.stamp[mine], rows.values[mine]
        first = np.unique(stamps, return_index=True)
        originals = values[first[1][np.searchsorted(first[0], stamps[repeats.again])]]
        m, d = apart(originals, values[repeats.again])
        metres, degrees = max(metres, float(m.max())), max(degrees, float(d.max()))
    if metres == 0 and degrees == 0:
        values_said = "identical values"
        effect = "tf2 drops the exact copies, so lookups are right, but every sample costs twice"
    else:
        values_said = f"values up to {metres * 1000:.1f} mm and {degrees:.2f}° apart"
        effect = "tf2 keeps both where they differ, so lookups mix the two publishers' values"
    every = np.sort(np.concatenate([mine for _, mine, _ in edges]))
    together = _together([repeats for _, _, repeats in edges])
    authorities = scene.authorities_of(every)
    metadata, listed_count = _listed_said(scene, authorities)
    if listed_count == 1:
        conclusion = "one publisher sending each sample twice, or a second one started after recording began"
    else:
        conclusion = "two identical publishers, it seems (two robot_state_publishers, or one launched twice)"
    named = [edge(*frames) for frames, _, _ in edges]
    names = and_joined(named) if len(named) <= LISTED else listed(named, LISTED)
    finding = scene.finding(
        Severity.warning,
        "multiple_authorities",
        f"{names}{scene.by(authorities)} {'arrive' if len(edges) > 1 else 'arrives'} twice: "
        f"{together.said('their' if len(edges) > 1 else 'its')}, "
        f"with {values_said}, {together.timing()}{metadata}: {conclusion}; this recording does not name publishers",
        f"{effect}: find them ({scene.list_publishers('/tf')}) and stop the one that should not run",
        tuple(f for frames, _, _ in edges for f in frames),
        every,
        scene.arrival(every),
    )
    figures = together.figures() | {"edges": len(edges), "apart_m": metres, "apart_deg": degrees}
    if listed_count is not None:
        figures["publishers_listed"] = listed_count
    return dataclasses.replace(finding, figures=figures)


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


def _back_and_forth(stamps: Int64Array) -> int:
    """Stamps (in arrival order) earlier than the one before them, each followed by a later one again:
    one late message, or a clock jumped back once, is not a turn."""
    steps = np.sign(np.diff(stamps))
    return int(((steps[:-1] < 0) & (steps[1:] > 0)).sum())


def _alternating(values: FloatArray) -> int:
    """Samples (in arrival order) far from the one before and the one after, which are close to each
    other: a value that goes somewhere else and comes back, sample after sample."""
    if len(values) < 3:
        return 0
    out_m, out_deg = apart(values[:-2], values[1:-1])
    back_m, back_deg = apart(values[1:-1], values[2:])
    round_m, round_deg = apart(values[:-2], values[2:])
    moved = ((out_m > APART_M) & (back_m > APART_M) & (round_m < out_m / 4)) | (
        (out_deg > APART_DEG) & (back_deg > APART_DEG) & (round_deg < out_deg / 4)
    )
    return int(moved.sum())


def apart(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """How far each value of ``b`` is from the one of ``a`` (N x 7 each): metres, and degrees of rotation."""
    with np.errstate(over="ignore"):  # values near 1e308 are apart by an infinity of metres
        metres: FloatArray = np.linalg.norm(b[:, :3] - a[:, :3], axis=1)
    return metres, np.degrees(angle_between_many(a[:, 3:], b[:, 3:]))
