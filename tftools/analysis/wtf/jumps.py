"""Checks of moving edges' values: steps further than the edge's own motion explains (a localization
correction, an odometry reset), and REP 105's layout (map -> odom -> base_link) where its frames exist."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from itertools import pairwise

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from tftools.analysis.detections import DETECTION
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.frames import FrameTree
from tftools.analysis.wtf.broadcasters import FLOOR_DEG, FLOOR_M, inferred_edges
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.rows import Rows
from tftools.analysis.wtf.scene import EdgeSamples, Scene, base_name, edge
from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, IntpArray
from tftools.core.figures import apart, held_apart, seconds_in_words, unseen_between
from tftools.core.time import NS_PER_S

#: What "its own motion explains" means, defined once: a step may be this many times the speed its
#: neighbours moved at (the median over ``NEIGHBOURS`` steps either side, the step itself left out)
#: times its interval, plus a floor for noise and the first motion from rest (``FLOOR_M``, ``FLOOR_DEG``).
JUMP_FACTOR = 5.0
NEIGHBOURS = 3
#: An edge sent in messages with other edges this often is a joint (``_joints``).
JOINT_SHARE = 0.9
#: A moving edge below the robot's base whose origin never moves further than this turns about a fixed point: a
#: revolute joint, however it is sent (``_turning_in_place``). Looser than ``figures.HELD_M`` (a value's rounding):
#: a joint's origin, computed again at each angle, may wobble more than a value re-sent.
FIXED_ORIGIN_M = 1e-6
WINDOWS_AT_ONCE = 65536
#: A step no faster than ``JUMP_FACTOR`` times either step beside it, or than the edge's usual speed (the
#: median of its steps that moved, where at least this many did), is its own motion too, unless it comes back
#: (``comes_back``: a spike or a toggle). Real Neatos' odometry and wheels at 5.5 Hz move in pulses of two or
#: three samples (teleop) and restart from rest with a step that the neighbours' median (0 around a pulse or a
#: start) does not explain.
USUAL_MIN_STEPS = 10
#: A step comes back (``comes_back``) when the edge is near where it began within this many samples after it,
#: having held where the step took it (a spike, or two sources taking turns), or the step ends near where the
#: edge was within this many samples before it (the way back of one); a step that stays is a jump.
BACK_WITHIN = NEIGHBOURS

#: REP 105's frames, by their name without a namespace prefix.
ODOM, MAP, BASES = "odom", "map", ("base_link", "base_footprint")


@dataclass(frozen=True)
class Jumps:
    """The steps of one edge that its motion does not explain: where (sample index of the step's
    end), how far (m, degrees)."""

    at: IntpArray
    metres: FloatArray
    degrees: FloatArray

    def __len__(self) -> int:
        return len(self.at)

    def only(self, kept: BoolArray) -> Jumps:
        """The steps where ``kept``."""
        return Jumps(self.at[kept], self.metres[kept], self.degrees[kept])

    @property
    def largest(self) -> int:
        """The largest step's index (a metre weighs as much as 100 degrees)."""
        return int(np.argmax(self.metres + self.degrees / 100))


def jumps(stamps: np.ndarray, values: FloatArray) -> Jumps:
    """The unexplained steps of samples sorted by stamp (``values``: N x 7, tx ty tz qx qy qz qw)."""
    return edges_jumps([(stamps, values)])[0]


#: Samples of several edges checked in one pass at most (their values copied together): a tree of 20,000
#: moving edges of a few samples each cost 1.2 ms an edge in numpy's per-call overhead when checked one by one;
#: a pass holds ~0.3 kB a sample, and a million at once raised ``wtf``'s peak on 4.1M transforms by 0.3 GB.
SAMPLES_AT_ONCE = 1 << 18


def edges_jumps(edges: Sequence[tuple[np.ndarray, FloatArray]], usual: bool = True) -> list[Jumps]:
    """``jumps`` of each edge's (stamps, values), several edges in one pass: their steps laid end to end with
    ``NEIGHBOURS`` NaN speeds between two edges, so that no step's neighbours are another edge's. ``usual``:
    a step at the edge's usual speed is explained (``USUAL_MIN_STEPS``); otherwise its neighbours' alone."""
    found: list[Jumps] = []
    start = 0
    while start < len(edges):
        end, size = start + 1, len(edges[start][0])
        while end < len(edges) and size + len(edges[end][0]) <= SAMPLES_AT_ONCE:
            size += len(edges[end][0])
            end += 1
        found += _jumps_in_one_pass(edges[start:end], usual)
        start = end
    return found


def _jumps_in_one_pass(edges: Sequence[tuple[np.ndarray, FloatArray]], usual: bool) -> list[Jumps]:
    counts = np.array([len(stamps) for stamps, _ in edges], np.intp)
    steps_of = np.maximum(counts - 1, 0)
    if not steps_of.any():
        return [Jumps(np.zeros(0, np.intp), np.zeros(0), np.zeros(0)) for _ in edges]
    # one edge's samples read where they are: a copy of a long edge's values is 27 MB a 480k samples
    stamps = edges[0][0] if len(edges) == 1 else np.concatenate([stamps for stamps, _ in edges])
    values = (edges[0][1] if len(edges) == 1 else np.concatenate([values for _, values in edges])).reshape(-1, 7)
    first = np.cumsum(counts) - counts  # each edge's first sample
    edge_of_step = np.repeat(np.arange(len(edges)), steps_of)
    local = np.arange(len(edge_of_step)) - np.repeat(np.cumsum(steps_of) - steps_of, steps_of)
    begin = first[edge_of_step] + local  # each step from sample ``begin`` to the next
    metres, degrees = _steps_apart(values, begin)
    seconds = (stamps[begin + 1] - stamps[begin]).astype(np.float64) / NS_PER_S
    at = np.arange(len(begin)) + NEIGHBOURS * (edge_of_step + 1)  # where each step's speed is laid
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):  # infinite metres (values near 1e308)
        speed_m, speed_deg = (np.where(seconds > 0, steps / seconds, np.nan) for steps in (metres, degrees))
        own_m, own_deg = _neighbour_speed(speed_m, at), _neighbour_speed(speed_deg, at)
        beyond_m = metres > JUMP_FACTOR * own_m * seconds + FLOOR_M
        beyond_deg = degrees > JUMP_FACTOR * own_deg * seconds + FLOOR_DEG
        unexplained = beyond_m | beyond_deg
        if usual and unexplained.any():
            # the edge's usual pace, and the steps beside: flips explain nothing (judged where they matter: the
            # steps the neighbours leave unexplained, the steps beside them, and those that could make a
            # sustained run that explains one: a real ArUco marker's pose toggling between its two solutions
            # each sample, 11-12 degrees in 18-45 ms, was a run of 234 degrees a second that excused 7 of its 8
            # flips too far for their interval, 8.6-12.3 degrees in 9-27 ms)
            odd = np.flatnonzero(unexplained)
            around = np.clip(odd[:, None] + np.arange(-1, 2), 0, len(begin) - 1)
            runs = _could_run(speed_m, metres > FLOOR_M, beyond_m, edge_of_step, len(edges)) | _could_run(
                speed_deg, degrees > FLOOR_DEG, beyond_deg, edge_of_step, len(edges)
            )
            near = np.union1d(
                around[edge_of_step[around] == edge_of_step[odd, None]],  # not the next edge's steps
                np.flatnonzero(runs),
            )
            back = np.zeros(len(begin), bool)
            back[near] = comes_back(
                values, begin[near], local[near], steps_of[edge_of_step[near]], metres[near], degrees[near]
            ).out  # a step's way back is judged by the pace it comes back at
            pace_m, pace_deg = (
                _pace(v, back, at, edge_of_step, len(edges))
                for v in (np.where(back, np.nan, speed_m), np.where(back, np.nan, speed_deg))
            )
            # a pace is motion, not noise: the floor is its least, not an allowance on top (a real Neato's
            # odometry sustaining 0.04 m a sample stepped 0.238 m between standstills: 5 x 0.04 + 0.05 let it by)
            unexplained &= (metres > np.fmax(JUMP_FACTOR * pace_m * seconds, FLOOR_M)) | (
                degrees > np.fmax(JUMP_FACTOR * pace_deg * seconds, FLOOR_DEG)
            )
            unexplained &= back | _beyond_neighbours_steps(metres, degrees, at)
    bounds = np.searchsorted(edge_of_step, np.arange(len(edges) + 1))
    return [
        Jumps(local[a:b][unexplained[a:b]] + 1, metres[a:b][unexplained[a:b]], degrees[a:b][unexplained[a:b]])
        for a, b in pairwise(bounds.tolist())
    ]


def _steps_apart(values: FloatArray, begin: IntpArray) -> tuple[FloatArray, FloatArray]:
    """``apart`` of each step, from sample ``begin`` of ``values`` to the next: a block of ``WINDOWS_AT_ONCE``
    steps at a time, whose two ends' values are copied (all at once, 0.1 GB a million steps)."""
    metres, degrees = np.empty(len(begin)), np.empty(len(begin))
    for start in range(0, len(begin), WINDOWS_AT_ONCE):
        block = begin[start : start + WINDOWS_AT_ONCE]
        metres[start : start + WINDOWS_AT_ONCE], degrees[start : start + WINDOWS_AT_ONCE] = apart(
            values[block], values[block + 1]
        )
    return metres, degrees


def _usual(speed: FloatArray, edge_of_step: IntpArray, edges: int) -> FloatArray:
    """Per step, its edge's median speed over the steps that moved (finite, above 0), 0 where fewer than
    ``USUAL_MIN_STEPS`` did: one sort by (edge, speed) for all, not a call per edge."""
    moved = np.isfinite(speed) & (speed > 0)
    owner = edge_of_step[moved]
    ordered = speed[moved][np.lexsort((speed[moved], owner))]
    counts = np.bincount(owner, minlength=edges)
    first = np.cumsum(counts) - counts
    usual: FloatArray = np.zeros(edges)
    some = counts >= USUAL_MIN_STEPS
    low, high = first[some] + (counts[some] - 1) // 2, first[some] + counts[some] // 2
    usual[some] = ordered[low] / 2 + ordered[high] / 2
    return usual[edge_of_step]


def _pace(speed: FloatArray, back: BoolArray, at: IntpArray, edge_of_step: IntpArray, edges: int) -> FloatArray:
    """Per step, the pace that explains it: its edge's usual speed, a step beside it or its fastest sustained
    motion; for a flip and back (``back``, whose ``speed`` is NaN), the sustained motion alone: a heading that
    wobbles 5 degrees for a sample on a robot turning tens of degrees a sample is its own motion, a wheel
    flipping 180 degrees on a joint that never turns is not."""
    sustained = _sustained(speed, edge_of_step, edges)
    moving = np.fmax(np.fmax(_usual(speed, edge_of_step, edges), _beside(speed, at)), sustained)
    paced: FloatArray = np.where(back, sustained, moving)
    return paced


def _sustained(speed: FloatArray, edge_of_step: IntpArray, edges: int) -> FloatArray:
    """Per step, the fastest its edge moved for ``NEIGHBOURS`` steps in a row (the slowest step of the
    fastest such run), 0 where it never did: an odometry heading that turns 8-9 degrees a sample for a
    second elsewhere explains a 10 degree step after a stalled sample (a real Raspberry Pi Mouse under
    gmapping), where the neighbours, at rest, do not. A flip between two sources (NaN: ``comes_back``) is no
    run; a jump is alone, so it never makes a run of its own."""
    fastest: FloatArray = np.full(edges, np.nan)
    if len(speed) >= NEIGHBOURS:
        runs = sliding_window_view(speed, NEIGHBOURS)
        owner = sliding_window_view(edge_of_step, NEIGHBOURS)
        whole = (owner[:, 0] == owner[:, -1]) & np.isfinite(runs).all(axis=1)
        np.fmax.at(fastest, owner[whole, 0], runs[whole].min(axis=1))
    per_step: FloatArray = np.nan_to_num(fastest[edge_of_step], nan=0.0)
    return per_step


def _could_run(speed: FloatArray, moved: BoolArray, odd: BoolArray, edge_of_step: IntpArray, edges: int) -> BoolArray:
    """Per step, whether it ``moved`` at least 1 / ``JUMP_FACTOR`` the speed of one of its edge's ``odd`` steps:
    the steps a sustained run that explains one is made of (``_sustained``); the others' flips need no looking
    for (a wheel turning 10 degrees a sample, a million samples, costs 5 s of ``comes_back``)."""
    need: FloatArray = np.full(edges, np.inf)
    np.fmin.at(need, edge_of_step[odd], speed[odd] / JUMP_FACTOR)
    fast: BoolArray = moved & (speed >= need[edge_of_step])
    return fast


def _beyond_neighbours_steps(metres: FloatArray, degrees: FloatArray, at: IntpArray) -> BoolArray:
    """Per step, whether it is further than ``JUMP_FACTOR`` times the steps around it (their median over
    ``NEIGHBOURS`` either side), whatever its interval: a sample whose stamp came early or late (a real
    Neato's driver stamps each wheel reading as its serial packet arrives: two 8 ms apart, the next 185 ms
    later) moves by a sample's usual step in a short interval, which its speed takes for a jump."""
    beyond: BoolArray = (metres > JUMP_FACTOR * _neighbour_speed(metres, at) + FLOOR_M) | (
        degrees > JUMP_FACTOR * _neighbour_speed(degrees, at) + FLOOR_DEG
    )
    return beyond


def _beside(speed: FloatArray, at: IntpArray) -> FloatArray:
    """Per step, the faster of the steps just before and after it on its edge (0 where neither is)."""
    laid = np.full(int(at[-1]) + NEIGHBOURS + 1, np.nan)
    laid[at] = speed
    faster: FloatArray = np.nan_to_num(np.fmax(laid[at - 1], laid[at + 1]), nan=0.0)
    return faster


@dataclass(frozen=True)
class Back:
    """Per step, how it comes back (``comes_back``)."""

    out: BoolArray  # the edge is near where the step began at one of its next ``BACK_WITHIN`` samples
    returns: BoolArray  # the step ends near where the edge was at one of the ``BACK_WITHIN`` samples before it

    @property
    def either(self) -> BoolArray:
        """The steps that go out to, or come back from, a place the edge does not stay at."""
        both: BoolArray = self.out | self.returns
        return both


def comes_back(
    values: FloatArray, begin: IntpArray, local: IntpArray, steps: IntpArray, metres: FloatArray, degrees: FloatArray
) -> Back:
    """The one rule of a step that comes back, per step (``metres`` and ``degrees`` long) from sample ``begin``
    of ``values`` to the next, ``local`` of its edge's ``steps`` (samples ``begin - local`` to ``begin - local +
    steps`` are the edge's): within ``BACK_WITHIN`` samples the edge is near where the step began, having stayed
    near where the step took it in between (a spike, or a toggle between two sources' values); or the step ends
    near where the edge was that many samples before, having stayed near where the step began since (the way
    back of one). Near is within half the step (``FLOOR_M``, ``FLOOR_DEG`` at least; past 90° within
    ``FLOOR_DEG``, as a rotation's way back is not told from a wheel turning on: the shortest rotation between
    samples wraps). A step that stays, or moves on (a pulse of motion, a wheel turning faster than its samples
    follow), does not come back."""
    near_m = np.maximum(FLOOR_M, metres / 2)
    near_deg = np.where(degrees <= 90.0, np.maximum(FLOOR_DEG, degrees / 2), FLOOR_DEG)

    def near(a: IntpArray, b: IntpArray) -> BoolArray:
        m, d = apart(values[a], values[b])
        close: BoolArray = (m <= near_m) & (d <= near_deg)
        return close

    out, returns = np.zeros(len(begin), bool), np.zeros(len(begin), bool)
    held_out, held_in = np.ones(len(begin), bool), np.ones(len(begin), bool)
    end = begin + 1
    for later in range(1, BACK_WITHIN + 1):
        there = local + 1 + later <= steps
        sample = np.where(there, end + later, end)
        out |= there & held_out & near(begin, sample)
        held_out &= near(end, sample)
        there = local - later >= 0
        sample = np.where(there, begin - later, begin)
        returns |= there & held_in & near(end, sample)
        held_in &= near(begin, sample)
    return Back(out, returns)


def _neighbour_speed(speed: FloatArray, at: IntpArray) -> FloatArray:
    """Per step, the median ``speed`` of the ``NEIGHBOURS`` steps on each side (not itself); ``at``: where each
    step's speed is laid in the row of all (the gaps NaN), which ends ``NEIGHBOURS`` after the last."""
    laid = np.full(int(at[-1]) + NEIGHBOURS + 1, np.nan)
    laid[at] = speed
    windows = sliding_window_view(laid, 2 * NEIGHBOURS + 1)
    median: FloatArray = np.empty(len(speed))
    for start in range(0, len(speed), WINDOWS_AT_ONCE):  # the windows copied a block at a time: bounded memory
        around = np.delete(windows[at[start : start + WINDOWS_AT_ONCE] - NEIGHBOURS], NEIGHBOURS, axis=1)
        median[start : start + WINDOWS_AT_ONCE] = _nan_median(around)
    return median


def _nan_median(rows: FloatArray) -> FloatArray:
    """``np.nanmedian(rows, axis=1)``, 0 for a row of NaNs (no motion to explain); sorted at once, as
    numpy's own goes through masked arrays, 2 ms a call: most of ``wtf`` on a tree of 5,000 moving edges."""
    ordered = np.sort(rows, axis=1)  # NaNs last
    counts = (~np.isnan(rows)).sum(axis=1)
    low = np.take_along_axis(ordered, np.maximum((counts - 1) // 2, 0)[:, None], axis=1)[:, 0]
    high = np.take_along_axis(ordered, np.maximum(counts // 2, 0)[:, None], axis=1)[:, 0]
    return np.where(counts > 0, low / 2 + high / 2, 0.0)


def _edge_jumps(scene: Scene, corrections: bool) -> Iterator[tuple[EdgeSamples, Jumps, Int64Array]]:
    """Each moving edge of one publisher, a localizer's corrections (into odom, or a map of its own under odom:
    ``map_under_odom``) or not (``corrections``), with its unexplained steps and the stamps they end at. Where
    several named publishers take turns, each one's own samples: their values alternate
    (``multiple_authorities`` says so), but an EKF's GPS steps beside a camera's odometry are the EKF's jumps
    all the same. Not where the publishers are only inferred (one topic, no names to part them)."""
    contested = inferred_edges(scene)
    checked = [
        own
        for samples in scene.dynamic_edges
        if samples.key not in contested
        and (base_name(samples.child) == ODOM or map_under_odom(scene, samples) is not None) is corrections
        for own in ((samples,) if len(samples.authorities) == 1 else _each_publishers(scene, samples))
    ]
    # map -> odom moves by its corrections alone: its usual speed is a correction's, and each one is counted
    found_in = edges_jumps([(s.stamps, s.values) for s in checked], usual=not corrections)
    for samples, found in zip(checked, found_in, strict=True):
        if len(found):
            yield samples, found, samples.stamps[found.at]


#: An edge that changes at most this share of its samples holds its value between steps: a localizer's output
#: re-sent between its updates (a real AGV's laser localizer: 101 values in 5,305 samples at 208 Hz).
HELD_SHARE = 0.5


def map_under_odom(scene: Scene, samples: EdgeSamples) -> str | None:
    """What shows ``samples``' edge to be a localizer's map of its own hung under odom, whose steps are its
    corrections (as map -> odom's are): a leaf under odom, not a base, holding its value between steps, where odom
    has its parent already (it can have one: the localizer hangs its map below it instead, a real AGV's laser
    localizer's ``map_contours_nav`` beside map -> odom); None where it is not one."""
    if base_name(samples.parent) != ODOM or base_name(samples.child) in BASES or len(samples.values) < 2:
        return None
    above = scene.tree.ancestors(samples.parent)
    if not above or scene.tree.children.get(samples.child):
        return None
    moved, turned = held_apart(samples.values[1:], samples.values[:-1])
    changes = int(np.count_nonzero(moved | turned))
    if changes > HELD_SHARE * (len(samples.values) - 1):
        return None
    return (
        f"it holds its value between steps (it changed value {changes:,} times in {len(samples.values):,} samples) "
        f"and no frame hangs under it, while {samples.parent} has its parent already ({above[0]} -> "
        f"{samples.parent}): a localizer's own map under {samples.parent}, it seems"
    )


def _each_publishers(scene: Scene, samples: EdgeSamples) -> Iterator[EdgeSamples]:
    """``samples``' edge as each of its publishers sent it: its transforms on /tf by stamp, a stamp sent again
    counted once (tf2 keeps the first)."""
    rows = scene.rows
    for authority, own in rows.edge_publishers(samples.parent, samples.child):
        stamps, first = np.unique(rows.stamp[own], return_index=True)
        own = own[first]
        yield replace(
            samples,
            stamps=stamps,
            record_times=rows.record_time[own],
            values=rows.values[own],
            flags=rows.flags[own],
            authorities=(rows.authorities[authority],),
        )


#: ``jump``'s hint for a detection's steps (``detections.detection``): its estimate's, not a localization's.
DETECTION_JUMP = (
    "a detector's pose estimate steps, not the object: a planar marker's pose is ambiguous (two solutions mirrored "
    "about its plane, between which it flips at a distance or a steep view) and noisy far from the camera; filter "
    "the poses (reject a step no motion explains, or keep the solution nearest the last one) or use a larger "
    "marker or a board of them"
)


#: ``jump``'s hint for a detection whose rotation never changes (a detector that gives a position alone): no flip
#: of a marker's pose, a step in where it found the object.
DETECTION_POSITION_JUMP = (
    "a detector's position estimate steps, not the object: its rotation never changes (the detector gives a "
    "position alone), so the step is in where it found the object: another object taken for it (two alike in "
    "view), or a bad depth reading; filter the positions (reject a step no motion explains) or tell the objects "
    "apart"
)


#: ``jump``'s hint for a detection sent at its camera's origin now and then: the detector's value for nothing found.
DETECTION_AT_ORIGIN = (
    "a detector sending its camera's origin where it found nothing (no depth, no object): tf2 takes each such "
    "transform as the object at the camera, and a lookup between one and a real sighting lands halfway; send "
    "nothing where nothing was found"
)


def _detection_hint(samples: EdgeSamples, at_origin: int) -> str:
    """A detection's steps in words: the origin sent for nothing found (``at_origin`` samples), a marker's ambiguous
    pose where its rotation moves, else its position's."""
    if at_origin:
        return DETECTION_AT_ORIGIN
    rotations = samples.values[:, 3:]
    held = len(rotations) > 1 and bool(np.ptp(rotations, axis=0).max() == 0.0)
    return DETECTION_POSITION_JUMP if held else DETECTION_JUMP


def _at_origin(samples: EdgeSamples) -> int:
    """How many of an edge's samples put its child exactly at its parent's origin (a translation of 0, 0, 0)."""
    return int(np.all(samples.values[:, :3] == 0.0, axis=1).sum())


def _origin_in_words(samples: EdgeSamples, at_origin: int) -> str:
    """'; 188 of its 293 transforms exactly at camera_link2's origin (0, 0, 0), stepping there or back 33 times',
    where ``at_origin`` is any: each such step is a jump to the camera and back that its pace, learnt from them,
    may not single out (Agri Bot's obj2 'jumped once')."""
    if not at_origin:
        return ""
    there = np.all(samples.values[:, :3] == 0.0, axis=1)
    steps = int(np.count_nonzero(there[1:] != there[:-1]))
    said = f"; {at_origin} of its {len(samples.values)} transforms exactly at {samples.parent}'s origin (0, 0, 0)"
    return said + (f", stepping there or back {_times(steps)}" if steps else "")


@register("jump", Severity.warning, "an edge stepping further than its own motion explains")
def jump(scene: Scene) -> Iterator[Finding]:
    """Not map -> odom, whose corrections REP 105 allows (``map_corrections``). A warning, on odom -> base_link
    too: every lookup through a jump works (an error breaks lookups), and a step is a correction (GPS fused
    into odom) as often as a reset; REP 105's advice says what it does to what is planned in odom."""
    joints = joint_edges(scene) - set(scene.detections)  # a marker turning in view
    for samples, found, when in _edge_jumps(scene, corrections=False):
        if samples.key in joints:
            found, when = _back_and_forth(samples.values, found, when)
            if not len(found):
                continue
        detected = scene.detections.get(samples.key)
        if detected is not None:  # where it went while unseen is no step of its estimate's (seen again elsewhere)
            seen_through = ~unseen_between(samples.stamps)[found.at - 1]
            found, when = found.only(seen_through), when[seen_through]
            if not len(found):
                continue
        at_origin = _at_origin(samples) if detected is not None else 0
        continuous = base_name(samples.parent) == ODOM and _carries_robot(scene, samples.child)
        why = (
            "REP 105 wants odom -> base continuous (odometry that never jumps): a reset odometry, or a "
            "localizer or GPS fused into odom, makes everything planned in odom leap; publish corrections as "
            "map -> odom"
            if continuous
            else "a joint whose position steps (it turns in place, or comes in messages with other edges, as "
            "robot_state_publisher sends a robot's joints): /joint_states from two sources taking turns "
            "(joint_state_publisher's defaults beside the driver's or the simulator's readings), or a driver "
            "resetting the joint; check who publishes /joint_states"
            if samples.key in joints
            else _detection_hint(samples, at_origin)
            if detected is not None
            else _correction_hint(scene, samples)
        )
        what = f", a detection ({detected[0]})," if detected is not None else ""
        largest = int(found.at[found.largest])
        # a step is judged by its speed: without its interval, "the largest 12.9 degrees" (in 9 ms) beside a
        # real ArUco marker's 22.8 degrees in 79 ms (five times the 90 degrees a second it turned for 0.4 s
        # explains that) read as a wrong figure
        took = seconds_in_words(int(samples.stamps[largest]) - int(samples.stamps[largest - 1]))
        found_jump = samples.finding(
            Severity.warning,
            "jump",
            f"{edge(*samples.key)}{scene.by(samples.authorities)}{what} jumped {_excursions(samples.values, found)} "
            f"further than its own motion explains in the time {'each' if len(found) > 1 else 'it'} took: the "
            f"largest {_largest(found)} in {took} at "
            f"{scene.at(int(when[found.largest]), samples.recorded_at(int(when[found.largest])))}, the first at "
            f"{scene.at(int(when[0]), samples.recorded_at(int(when[0])))}" + _origin_in_words(samples, at_origin),
            why,
            when,
        )
        yield replace(found_jump, figures={DETECTION: 1}) if detected is not None else found_jump


def _correction_hint(scene: Scene, samples: EdgeSamples) -> str:
    """``jump``'s hint for an edge that is neither the robot's base, a joint nor a detection: publish a correction
    as map -> odom (REP 105), or where odom has its parent already and the edge hangs under it, under that parent."""
    above = scene.tree.ancestors(samples.parent) if base_name(samples.parent) == ODOM else []
    if not above and not _carries_robot(scene, samples.child):
        return (
            f"{samples.child} carries no frame and is named as no robot's base: an estimate of something tracked (a "
            "person, an object: a tracker's or a detector's steps, to filter) or of the robot localized (a "
            "correction or a reset: publish it as map -> odom, REP 105, so that odom stays continuous)"
        )
    if not above:
        return (
            "a localization correction or a reset published as this edge's motion: if it is a correction, publish "
            "it as map -> odom (REP 105), so that odom stays continuous"
        )
    return (
        f"a localization correction or a reset published as this edge's motion: {above[0]} -> {samples.parent} is "
        f"sent already, so if it corrects where {samples.child} lies, send {samples.child} under {above[0]}, where "
        "it stays put, or say why it moves in odom"
    )


def _carries_robot(scene: Scene, frame: str) -> bool:
    """Whether ``frame`` under odom is the robot's base, which REP 105 wants continuous: named so, or with frames
    under it. Not a leaf of another name: a real AGV's laser localizer hangs its map (``map_contours_nav``) under
    odom, whose steps are corrections."""
    return base_name(frame) in BASES or bool(scene.tree.children.get(frame))


def _back_and_forth(values: FloatArray, found: Jumps, when: Int64Array) -> tuple[Jumps, Int64Array]:
    """The steps of a joint that come back (``comes_back``): what two /joint_states sources taking turns leave
    in its samples, or a one-sample glitch. A joint's step that stays is motion its samples were too
    sparse to follow: a wheel spinning faster than half a turn a sample (each angle seen modulo a turn), or
    starting and stopping between two samples at 4 Hz (a real TurtleBot2's wheels, a Unity robot's wheels and
    its body tipping over an obstacle)."""
    begin = found.at - 1  # each step goes from sample ``begin`` to the next
    steps = np.full(len(begin), len(values) - 1)
    kept = comes_back(values, begin, begin, steps, found.metres, found.degrees).either
    return found.only(kept), when[kept]


#: Transforms whose messages ``_joints`` compares at once, at most: a message is of one record time, so the
#: recording is compared a span of record times at a time (4.1M transforms' message keys held 0.4 GB at once).
MESSAGES_AT_ONCE = 1 << 19


def joint_edges(scene: Scene) -> set[tuple[str, str]]:
    """A state publisher's joints (``_sent_together``) and those turning in place (``_turning_in_place``), found once
    per scene."""
    return scene.shared("joints", lambda: sent_together(scene) | _turning_in_place(scene))


def sent_together(scene: Scene) -> set[tuple[str, str]]:
    """The moving edges sent in messages with others (``_sent_together``: a state publisher's joints, whose rhythm is
    its /joint_states'), found once per scene."""
    return scene.shared("sent together", lambda: _sent_together(scene))


def _sent_together(scene: Scene) -> set[tuple[str, str]]:
    """The moving edges sent in messages that carry other edges too (one publisher, one record time and
    stamp), at least ``JOINT_SHARE`` of the time: a state publisher's joints, not a localizer's output. Not an
    edge under odom that shares its messages with edges under map alone: a localizer sending map -> odom and
    odom -> base in one message (cartographer providing the odom frame), whose steps are corrections, not a state
    publisher's joints sampled too sparsely."""
    rows = scene.rows
    moving = rows.usable & ~rows.static
    records = rows.record_time.whole()
    if not (records > 0).all():
        return set()
    spans = _record_spans(records, int(np.count_nonzero(moving)))
    del records  # each edge's own record times instead: the whole column beside every edge's rows held 66 MB
    edges: list[tuple[str, str, int]] = []  # each edge and its count of rows
    parts: list[list[Int32Array]] = [[] for _ in spans]  # of each span, each edge's rows recorded in it
    for p, c, mine in rows.by_edge(moving):
        edges.append((p, c, len(mine)))
        times = rows.record_time[mine] if len(spans) > 1 else None
        for span, (lo, hi) in zip(parts, spans, strict=True):
            span.append(_recorded_in(times, mine, lo, hi).astype(np.int32))
    if len(edges) < 2:
        return set()
    beyond_map = np.array([base_name(p) != MAP for p, _, _ in edges])
    shared = np.zeros(len(edges), np.int64)  # each edge's transforms in messages that carry other edges too
    beside = np.zeros(len(edges), bool)  # sent in a message with another edge not under map
    for span in parts:
        mine_shared, mine_beside = _messages_shared(rows, span, beyond_map)
        shared += mine_shared
        beside |= mine_beside
        span.clear()
    return {
        (p, c)
        for i, (p, c, count) in enumerate(edges)
        if int(shared[i]) / count >= JOINT_SHARE and (base_name(p) != ODOM or bool(beside[i]))
    }


def _messages_shared(rows: Rows, parts: list[Int32Array], beyond_map: BoolArray) -> tuple[Int64Array, BoolArray]:
    """Of each edge's rows ``parts``: how many are in a message (one publisher, record time and stamp) that
    carries another edge too; and whether one is in a message with another edge not under map
    (``beyond_map`` says which edges are not)."""
    counts = np.array([len(part) for part in parts], np.intp)
    which = np.concatenate(parts)
    edge_of = np.repeat(np.arange(len(parts)), counts)
    authority, record, stamp = rows.authority[which], rows.record_time[which], rows.stamp[which]
    del which
    order = np.lexsort((edge_of, stamp, record, authority))  # each message's rows together, by edge
    authority, record, stamp, edge_of = authority[order], record[order], stamp[order], edge_of[order]
    del order
    new = np.ones(len(edge_of), bool)  # a message's first row
    new[1:] = (authority[1:] != authority[:-1]) | (record[1:] != record[:-1]) | (stamp[1:] != stamp[:-1])
    del authority, record, stamp
    message = np.cumsum(new) - 1
    first = new.copy()  # an edge's first row in a message
    first[1:] |= edge_of[1:] != edge_of[:-1]
    messages = int(message[-1]) + 1 if len(message) else 0
    edges_in = np.bincount(message[first], minlength=messages)
    shared = np.bincount(edge_of[edges_in[message] >= 2], minlength=len(parts))
    beyond_in = np.bincount(message[first & beyond_map[edge_of]], minlength=messages)
    # another edge not under map: two of them in the message where the edge is one, one where it is not
    beside = np.bincount(edge_of[beyond_in[message] >= 1 + beyond_map[edge_of]], minlength=len(parts)) > 0
    return shared.astype(np.int64), beside


def _record_spans(records: Int64Array, count: int) -> list[tuple[int | None, int | None]]:
    """Spans of record times [lo, hi) (None: open) of about ``MESSAGES_AT_ONCE`` of ``count`` transforms each,
    cut at the record times of evenly spaced rows of ``records`` (in record order)."""
    if count <= MESSAGES_AT_ONCE:
        return [(None, None)]
    spans = -(-count // MESSAGES_AT_ONCE)
    cuts: list[int | None] = np.unique(records[:: -(-len(records) // spans)]).tolist()[1:]
    return list(pairwise([None, *cuts, None]))


def _recorded_in(times: Int64Array | None, mine: IntpArray, lo: int | None, hi: int | None) -> IntpArray:
    """Those of the rows ``mine`` (recorded at ``times``) recorded in [lo, hi) (None: open)."""
    if lo is None and hi is None:
        return mine
    assert times is not None
    inside = np.ones(len(mine), bool) if lo is None else times >= lo
    if hi is not None:
        inside &= times < hi
    return mine[inside]


def _turning_in_place(scene: Scene) -> set[tuple[str, str]]:
    """The moving edges whose origin never moves (``FIXED_ORIGIN_M``) while they turn, not under odom or map: a
    wheel or a pan joint, whose angle is seen modulo a turn, sent in messages of its own (a real Neato's driver
    sends each wheel alone). Under odom or map a heading that only turns is a localizer's: its steps jump."""
    return {
        samples.key
        for samples in scene.dynamic_edges
        if base_name(samples.parent) not in (ODOM, MAP)
        and len(samples.values) > 1
        and bool(np.ptp(samples.values[:, :3], axis=0).max() <= FIXED_ORIGIN_M)
    }


@register(
    "map_corrections",
    Severity.info,
    "map -> odom's corrections, or a localizer's own map's under odom (REP 105 lets them step): how many, how far",
)
def map_corrections(scene: Scene) -> Iterator[Finding]:
    """map -> odom's steps, and those of a localizer's own map hung under odom (``map_under_odom``)."""
    for samples, found, when in _edge_jumps(scene, corrections=True):
        seconds = (int(samples.stamps[-1]) - int(samples.stamps[0])) / NS_PER_S
        own = map_under_odom(scene, samples)
        yield samples.finding(
            Severity.info,
            "map_corrections",
            f"{edge(*samples.key)}{scene.by(samples.authorities)}{': ' + own + '; it' if own else ''} was corrected "
            f"{_times(len(found))} in {seconds:.1f} s: typically {np.median(found.metres):.3f} m and "
            f"{np.median(found.degrees):.1f}°, at most {_largest(found)} at "
            f"{scene.at(int(when[found.largest]), samples.recorded_at(int(when[found.largest])))}",
            (
                f"nothing to fix: REP 105 lets a localizer's map step, as map -> odom does; data in {samples.child} "
                "steps with it; large or frequent corrections are worth a look at that localizer (its map, its "
                "sensor data)"
            )
            if own
            else "REP 105 lets localization step map -> odom; large or frequent corrections are worth a look at the "
            "localizer (its map, its sensor data)",
            when,
        )


def _excursions(values: FloatArray, found: Jumps) -> str:
    """How often an edge jumped, a step out and the step back (``comes_back``) counted once: a joint at 180°
    for one sample jumped "once, out and back", not "2 times" (the JetAcker's steering)."""
    begin = found.at - 1
    back = comes_back(values, begin, begin, np.full(len(begin), len(values) - 1), found.metres, found.degrees)
    # a step back from where the step just before went out to: the two are one excursion
    paired = back.returns[1:] & back.out[:-1] & (np.diff(found.at) <= BACK_WITHIN)
    excursions, taken = 0, -1
    for k in np.flatnonzero(paired).tolist():  # a step is in one excursion at most: A B A B is two
        if k > taken:
            excursions, taken = excursions + 1, k + 1
    jumps = len(found) - excursions
    if not excursions:
        return _times(jumps)
    if excursions == jumps:
        return f"{_times(jumps)}, {'each ' if jumps > 1 else ''}out and back,"
    return f"{_times(jumps)} ({excursions} of them out and back)"


def _times(n: int) -> str:
    return "once" if n == 1 else f"{n} times"


def _largest(found: Jumps) -> str:
    return f"{found.metres[found.largest]:.3f} m and {found.degrees[found.largest]:.1f}°"


@register("rep105", Severity.warning, "REP 105's layout broken: map -> odom -> base_link where those frames exist")
def rep105(scene: Scene) -> Iterator[Finding]:
    """Per namespace (a prefix like robot1/), where odom exists: map, if present, above it, and the
    base frames below it. Frames in separate trees are ``disconnected``'s to report."""
    tree = scene.tree
    for name in tree.frames:
        if base_name(name) != ODOM:
            continue
        prefix = name[: -len(ODOM)]
        if _together(tree, prefix + MAP, name) and prefix + MAP not in tree.ancestors(name):
            yield _layout(tree, prefix + MAP, name, f"{prefix + MAP} is not above it")
        for base in (prefix + b for b in BASES):
            if _together(tree, name, base) and name not in tree.ancestors(base):
                yield _layout(tree, name, base, f"{base} is not under it")


def _together(tree: FrameTree, a: str, b: str) -> bool:
    """Both frames exist, in one tree."""
    return a in tree.frames and b in tree.frames and [a, *tree.ancestors(a)][-1] == [b, *tree.ancestors(b)][-1]


def _layout(tree: FrameTree, upper: str, lower: str, what: str) -> Finding:
    chain = " -> ".join(reversed([lower, *tree.ancestors(lower)]))
    return Finding(
        Severity.warning,
        "rep105",
        f"{upper} and {lower} are both in the tree, but {what}: {lower} hangs as {chain}",
        "REP 105 chains map -> odom -> base_link: localization publishes map -> odom, odometry odom -> base_link; "
        "tools that assume it (navigation, RViz's fixed frame) get lost otherwise",
        (upper, lower),
    )
