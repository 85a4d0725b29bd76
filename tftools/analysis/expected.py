"""A tree's shape (each frame's parent, static edges' values, publishers, rates) as ``tfx wtf --init`` writes
it (``analysis.tree_file``), and the tolerances within which ``--expect`` and ``tfx diff`` compare two."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field, replace

import numpy as np
import numpy.typing as npt

from tftools.analysis.detections import detected
from tftools.analysis.edges import publishers
from tftools.analysis.frames import FrameTree, tree_of
from tftools.core.arrays import Int64Array
from tftools.core.buffer import Buffer
from tftools.core.figures import (
    STOP_FLOOR,
    held_groups,
    held_parts,
    rate_of,
    record_span,
    silence,
    stopped,
    time_base_of,
    time_bases,
)
from tftools.core.history import FROM_STATIC_TOPIC, EdgeHistory
from tftools.core.rotation import Quat, Vec3, angle_between_many
from tftools.core.time import EPOCH_FLOOR, NS_PER_S
from tftools.sources.recording import Recording


@dataclass(frozen=True)
class Tolerances:
    """How far two trees may differ and still count as the same: a static edge's translation (mm)
    and rotation (degrees), a moving edge's rate (percent the slower falls short of the faster, whichever tree
    it is in: ``differences.rates_apart``)."""

    translation_mm: float = 1.0
    rotation_deg: float = 0.1
    rate_percent: float = 20.0

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"tolerance {name} must be a finite number from 0 up, got {value}")


@dataclass(frozen=True)
class StaticValue:
    """One value a static edge was received with on /tf_static: when it first came (seconds into the
    recording on its record clock; None where the recording has no record times), and how many times."""

    translation: Vec3
    rotation: Quat
    at_s: float | None
    times: int


@dataclass(frozen=True)
class SourceRate:
    """One of several sources of a moving edge's samples and its rate (``figures.rate_of`` of its own stamps): a
    node, or where the recording names none, a clock its stamps are on ("clock 1": the earliest stamps')."""

    source: str
    rate_hz: float


@dataclass(frozen=True)
class Motion:
    """How a moving edge that never holds still moves (its samples from its latest parent): its translation where
    it never changes (a turning joint's origin: a wheel's), its rotation where it never changes (a sliding
    joint's), else None; how far its translation spreads (mm from its first value, at most) and how far its
    rotation turns (degrees from its first value, at most)."""

    translation: Vec3 | None
    rotation: Quat | None
    spread_mm: float
    turn_deg: float


@dataclass(frozen=True)
class Tail:
    """How a moving edge's samples end in its recording (its latest parent's, on the record clock): its last
    sample's arrival (ns into the recording) and stamp (ns), the recording's length (ns), and whether it
    stopped (``figures.stopped``: silent at the end longer than ``PERIODS`` periods and ``STOP_FLOOR``)."""

    arrived: int
    stamp: int
    length: int
    stopped: bool

    @property
    def silent(self) -> int:
        """How long (ns) before the recording's end it last arrived."""
        return max(self.length - self.arrived, 0)


@dataclass(frozen=True)
class FrameShape:
    """One frame: its parent (None for a root); a static edge's value, a moving edge's rate (None: any rate, as a
    tree file without ``rate_hz`` or a URDF expects; 0: unknown, fewer than two samples stamped apart);
    its publishers (None where the source does not name them: a ROS 2 bag names topics); where a static edge
    was received with several values, each of them in the order they first came (tf2 keeps the last received)."""

    frame: str
    parent: str | None
    static: bool = False
    rate_hz: float | None = None
    publishers: tuple[str, ...] | None = None
    translation: Vec3 | None = None  # static edges only
    rotation: Quat | None = None
    received: tuple[StaticValue, ...] = ()  # static edges received with more than one value only
    #: A static edge sent on /tf too (ROS 1's tf2 keeps a frame whose first transform came on /tf_static static,
    #: each later one replacing its value for every time): its rate there; 0 for any other edge.
    on_tf_hz: float = 0.0
    #: The time bases a moving edge's stamps are on (``FrameSummary.clocks``); None where not known (a tree file,
    #: a URDF).
    clocks: int | None = None
    #: A moving edge's one value where it never changed (``held``): a fixed transform sent on /tf (ROS 1's
    #: robot_state_publisher before /tf_static), compared between two recordings as a static edge's value is.
    held: StaticValue | None = None
    #: A moving edge's values where they change (``Motion``): what of them stays fixed, compared between two
    #: recordings as a held value is (a wheel's origin beside the same wheel held still); None otherwise.
    motion: Motion | None = None
    #: A moving edge's rate by source where it has several (two nodes, or one unnamed publisher per clock): its
    #: ``rate_hz`` is their sum, the figure of each is theirs; empty where it has one.
    rates: tuple[SourceRate, ...] = ()
    #: Whether a moving edge's stamps count from the epoch (a wall clock: True) or from a start (a simulation's,
    #: a boot's: False); None where some do and some do not, or not known (a tree file, a URDF).
    epoch: bool | None = None
    #: How far a moving edge's stamps advance while it arrives (their span over its record span): 1 where they
    #: are on the record clock or one ticking as fast, 0.067 for a simulation at a fifteenth of real time
    #: recorded on the wall clock; None where not known (no record times, stamps on several clocks).
    pace: float | None = None
    #: How a moving edge's samples end (``Tail``); None where not known (a tree file, a URDF, no record times).
    tail: Tail | None = None
    #: Of a moving edge held still (``held``), what it is by the messages it came in (``joints``): a joint (True),
    #: a fixed part (False), or not known (None: a tree file, a URDF, an edge sent alone or with nothing that moves).
    joint: bool | None = None
    #: Whether a moving edge is a detector's (``detections.detected``: a marker or object a camera sees and loses):
    #: its rate is how often it was seen, its end when it was last seen, no publisher's.
    detection: bool = False


@dataclass(frozen=True)
class TreeShape:
    """Every frame of a tree by name, where it came from (a path), and the tolerances it asks for
    (a tree file may set them; a recording has the defaults)."""

    frames: dict[str, FrameShape]
    source: str
    tolerances: Tolerances = Tolerances()
    #: Why a recording's tree has no frame: it holds no transforms on the topics read (else "").
    empty: str = ""
    #: The moving edges (by child frame) that came in the same messages (``sent_together``), each group of two
    #: or more in the tree's order; empty where not known (a tree file, a URDF).
    together: tuple[tuple[str, ...], ...] = ()
    #: Of the robot's joints that mimic another (a recorded /robot_description's ``<mimic>``), each one's child
    #: frame and the child frame of the joint it follows; empty where the recording holds no description.
    mimics: dict[str, str] = field(default_factory=dict)
    #: The moving edges (by child frame) stamped alike in every sample by one source, each in messages of its own
    #: (``stamped_together``: a driver sending its odometry and each wheel apart, with one stamp), each group of
    #: two or more in the tree's order; empty where not known.
    stamped: tuple[tuple[str, ...], ...] = ()


def shape_of(recording: Recording, tree: FrameTree | None = None) -> TreeShape:
    """The shape of ``recording``'s tree (``tree``: its ``tree_of``, if already made), from its roots
    down: each frame's latest parent, the latest value of its static edges, the rate of its moving ones
    over their span, their publishers where the bag names them."""
    buffer = recording.buffer
    named = publishers_named(recording)
    tree = tree if tree is not None else tree_of(buffer)
    in_order = dict.fromkeys([frame for _, frame, _ in tree.walk()] + list(tree.frames))  # roots down; loops last
    frames: dict[str, FrameShape] = {}
    for name in in_order:
        summary = tree.frames[name]
        translation: Vec3 | None = None
        rotation: Quat | None = None
        received: tuple[StaticValue, ...] = ()
        hist = buffer.history(name)
        moving = hist if not summary.static and hist is not None and len(hist) else None
        if summary.static and hist is not None and len(hist):
            latest = int(np.argmax(hist.sequence))
            translation, rotation = _value(hist.values[latest])
            received = _received(hist.values, hist.sequence, hist.record_times, recording.start)
        frames[name] = FrameShape(
            frame=name,
            parent=summary.parent,
            static=summary.static,
            rate_hz=summary.rate_hz,
            publishers=_publishers(_edge_publishers(buffer, name), recording.contents.topics) if named else None,
            translation=translation,
            rotation=rotation,
            received=received,
            on_tf_hz=_on_tf_hz(hist) if summary.static and hist is not None else 0.0,
            clocks=summary.clocks,
            held=held(moving) if moving is not None else None,
            motion=motion(moving) if moving is not None else None,
            rates=source_rates(buffer, moving, named) if moving is not None else (),
            epoch=_epoch(moving) if moving is not None else None,
            pace=_pace(moving) if moving is not None else None,
            tail=_tail(moving, summary.rate_hz, recording) if moving is not None else None,
            detection=moving is not None and _detected(summary.parent, name, moving),
        )
    together = sent_together(buffer, frames)
    for name, joint in joints(together, frames).items():
        frames[name] = replace(frames[name], joint=joint)
    stamped = stamped_together(buffer, frames)
    return TreeShape(
        frames,
        " + ".join(recording.paths),
        together=tuple(g for g in together if len(g) > 1),
        stamped=tuple(g for g in stamped if len(g) > 1),
    )


def sent_together(buffer: Buffer, frames: dict[str, FrameShape]) -> list[tuple[str, ...]]:
    """The moving edges of ``frames`` (from their latest parents, seen twice or more) grouped by the messages
    they came in, each group in ``frames``' order: edges of one message share its record time, stamp and
    publisher, so edges that came in the same messages share all three in every sample. An edge sent alone is a
    group of one; none where the recording has no record times."""

    def sent(records: Int64Array, stamps: Int64Array, sources: Int64Array) -> Int64Array | None:
        if not len(records) or records.min() <= 0:
            return None
        order = np.lexsort((stamps, records))
        return np.stack([records[order], stamps[order], sources[order]])

    return _grouped(buffer, frames, sent)


def stamped_together(buffer: Buffer, frames: dict[str, FrameShape]) -> list[tuple[str, ...]]:
    """The moving edges of ``frames`` (from their latest parents, seen twice or more) grouped by their stamps and
    sources: edges that share every stamp, each stamp from the same source (the node, or where the recording names
    none, the topic), whether or not they came in the same messages. Each group in ``frames``' order."""

    def stamped(records: Int64Array, stamps: Int64Array, sources: Int64Array) -> Int64Array | None:
        if stamps.min() == stamps.max():  # one stamp throughout (a fixed transform stamped 0) tells no source
            return None
        order = np.lexsort((sources, stamps))
        return np.stack([stamps[order], sources[order]])

    return _grouped(buffer, frames, stamped)


def _grouped(
    buffer: Buffer,
    frames: dict[str, FrameShape],
    samples: Callable[[Int64Array, Int64Array, Int64Array], Int64Array | None],
) -> list[tuple[str, ...]]:
    """The moving edges of ``frames`` (from their latest parents, seen twice or more) grouped where ``samples``
    (of an edge's record times, stamps and sources) gives the same array, each group in ``frames``' order; an
    edge for which it gives None is in no group."""
    groups: dict[tuple[tuple[int, ...], int], list[str]] = {}  # by a hash: an edge's samples are not held twice
    for name, f in frames.items():
        hist = buffer.history(name)
        if f.static or hist is None or len(hist) < 2:
            continue
        mine = hist.parents == hist.latest_parent
        found = samples(hist.record_times[mine], hist.stamps[mine], hist.authorities[mine].astype(np.int64))
        if found is not None:
            groups.setdefault((found.shape, hash(found.tobytes())), []).append(name)
    return [tuple(names) for names in groups.values()]


def joints(together: Sequence[Sequence[str]], frames: dict[str, FrameShape]) -> dict[str, bool]:
    """Which moving edges held still (``held``) are joints and which fixed parts, by the messages they came in
    (``sent_together``): a joint where it came with edges that move (a joint state publisher's joints), a fixed
    part where it came with several edges none of which moves while the recording sends its joints apart from
    them (tf1's robot_state_publisher: its fixed transforms at 50 Hz, its joints at /joint_states' rate). Empty
    where the recording sends no joints so: an arm held still whole (every edge held) tells no joint from a fixed
    part."""
    moves = [[frames[n].held is None for n in names] for names in together]
    if not any(len(m) > 1 and any(m) and not all(m) for m in moves):
        return {}
    return {
        name: any(m)
        for names, m in zip(together, moves, strict=True)
        if len(names) > 1
        for name, moving in zip(names, m, strict=True)
        if not moving
    }


def held(hist: EdgeHistory) -> StaticValue | None:
    """A moving edge's one value, with how many samples from its latest parent carried it, where there are two
    or more and they never change; None otherwise (it moves, or was seen once)."""
    values = hist.values[hist.parents == hist.latest_parent]
    if len(values) < 2 or not all(held_parts(values)):
        return None
    translation, rotation = _value(values[0])
    return StaticValue(translation, rotation, None, len(values))


def motion(hist: EdgeHistory) -> Motion | None:
    """A moving edge's ``Motion`` over its samples from its latest parent; None where it holds still (``held``)
    or has fewer than two."""
    values = hist.values[hist.parents == hist.latest_parent]
    fixed_t, fixed_q = held_parts(values)
    if len(values) < 2 or (fixed_t and fixed_q):
        return None
    translations, rotations = values[:, :3], values[:, 3:]
    first_t, first_q = _value(values[0])
    spread = float(np.linalg.norm(translations - translations[0], axis=1).max())
    turn = float(angle_between_many(rotations, np.broadcast_to(rotations[0], rotations.shape)).max())
    return Motion(first_t if fixed_t else None, first_q if fixed_q else None, 1000.0 * spread, math.degrees(turn))


def source_rates(buffer: Buffer, hist: EdgeHistory, named: bool) -> tuple[SourceRate, ...]:
    """A moving edge's rate by source (``SourceRate``) from its latest parent, where it has several: by node where
    the recording names them (``named``), else by the clock its stamps are on (``figures.time_base_of``)."""
    mine = hist.parents == hist.latest_parent
    stamps, records = hist.stamps[mine], hist.record_times[mine]
    if named:
        ids = hist.authorities[mine]
        groups = sorted(((buffer.authorities[int(a)], ids == a) for a in np.unique(ids)), key=lambda g: g[0])
    else:
        base = time_base_of(stamps, record_span(records))
        groups = [(f"clock {k + 1}", base == k) for k in range(int(base.max()) + 1)] if len(base) else []
    if len(groups) < 2:
        return ()
    return tuple(
        SourceRate(name, rate_of(stamps[rows], record_span(records[rows]), records[rows])) for name, rows in groups
    )


def _epoch(hist: EdgeHistory) -> bool | None:
    """Whether a moving edge's stamps count from the epoch (all of them), from a start (none), or neither."""
    stamps = hist.stamps[hist.parents == hist.latest_parent]
    if not len(stamps):
        return None
    low, high = int(stamps.min()), int(stamps.max())
    return True if low >= EPOCH_FLOOR else False if high < EPOCH_FLOOR else None


def _pace(hist: EdgeHistory) -> float | None:
    """How far a moving edge's stamps advance per ns it takes to arrive (``FrameShape.pace``)."""
    mine = hist.parents == hist.latest_parent
    stamps, records = hist.stamps[mine], hist.record_times[mine]
    span = record_span(records)
    if span <= 0 or time_bases(stamps, span) > 1:
        return None
    return float(stamps.max() - stamps.min()) / span


def _detected(parent: str | None, child: str, hist: EdgeHistory) -> bool:
    """Whether a moving edge from its latest parent is a detector's (``FrameShape.detection``)."""
    mine = hist.parents == hist.latest_parent
    stamps = np.sort(hist.stamps[mine])
    return parent is not None and detected(parent, child, stamps, record_span(hist.record_times[mine])) is not None


def _tail(hist: EdgeHistory, rate: float, recording: Recording) -> Tail | None:
    """How a moving edge's samples from its latest parent end in ``recording`` (``Tail``); None where their
    arrivals or the recording's end are not known on one clock (``figures.silence``), or staleness cannot be
    measured (``Timeline.available``: a simulation's rate on its slow clock against silences on the wall's).
    Whether it stopped is measured as wtf's stale measures it (``Timeline.silence``: in ROS time under /clock, so
    that a simulation paused with its tf at the end stopped nothing); its arrival and silence are said on the record
    clock."""
    if not recording.timeline.available:
        return None
    mine = hist.parents == hist.latest_parent
    records = hist.record_times[mine]
    last = int(np.argmax(records))
    silent = silence(int(records[last]), recording.end)
    if silent is None or recording.start <= 0:
        return None
    stamp = int(hist.stamps[mine][last])
    length = recording.end - recording.start
    on_its_clock = recording.timeline.silence(int(records[last]), recording.end)  # wtf's stale: ROS time
    return Tail(int(records[last]) - recording.start, stamp, length, stopped(on_its_clock, rate, STOP_FLOOR))


def _on_tf_hz(hist: EdgeHistory) -> float:
    """The rate of a static edge's transforms from its latest parent that came on /tf (0 for fewer than two)."""
    mine = (hist.parents == hist.latest_parent) & ((hist.flags & FROM_STATIC_TOPIC) == 0)
    if np.count_nonzero(mine) < 2:
        return 0.0
    return rate_of(np.sort(hist.stamps[mine]), record_span(hist.record_times[mine]))


def _value(row: npt.NDArray[np.float64]) -> tuple[Vec3, Quat]:
    tx, ty, tz, qx, qy, qz, qw = (float(v) for v in row)
    return (tx, ty, tz), (qx, qy, qz, qw)


def _received(
    values: npt.NDArray[np.float64], sequence: Int64Array, record_times: Int64Array, start: int
) -> tuple[StaticValue, ...]:
    """A static edge's different values in the order they first came, each as it first came (none where it had
    one value: values within ``figures.held_groups``' tolerances of one another are one)."""
    order = np.argsort(sequence, kind="stable")
    group = held_groups(values[order])
    kinds, first, times = np.unique(group, return_index=True, return_counts=True)
    if len(kinds) < 2:
        return ()
    found = []
    for k in np.argsort(first, kind="stable").tolist():
        record = int(record_times[order[first[k]]])
        translation, rotation = _value(values[order[first[k]]])
        at_s = (record - start) / NS_PER_S if record > 0 else None
        found.append(StaticValue(translation, rotation, at_s, int(times[k])))
    return tuple(found)


def _edge_publishers(buffer: Buffer, child: str) -> tuple[str, ...]:
    """The nodes that sent ``child``'s edge from its latest parent: not those that sent it under another parent
    (a URDF's base_footprint -> base_link beside a driver's odom -> base_link)."""
    hist = buffer.history(child)
    if hist is None or not len(hist):
        return ()
    return publishers(buffer, hist.authorities[hist.parents == hist.latest_parent])


def _publishers(authorities: Iterable[str], topics: Sequence[str]) -> tuple[str, ...] | None:
    """The nodes that sent a frame; None where one is not named (a ROS 1 bag without callerids gives the
    topic instead: not a publisher to compare), or none sent it (a root)."""
    found = tuple(sorted(authorities))
    return found if found and not set(found) & set(topics) else None


def publishers_named(recording: Recording) -> bool:
    """ROS1 bags and live systems name each publisher; ROS2 bags only the topic, as the authority, and so
    does a ROS 1 bag written by a tool that kept no callerids (every authority is a topic of it)."""
    if not any(f.names_publishers for f in recording.contents.files):
        return False
    heard = recording.buffer.authorities
    topics = {t for f in recording.contents.files for t in f.topics}
    return not heard or not set(heard) <= topics
