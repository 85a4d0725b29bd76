"""tf that says nothing: moving edges that all go silent at once (a stall), publishers that sent no message
while recorded, and messages that carry no transform. Only rosbag2 recordings say the last two: metadata.yaml
lists each topic's messages and the QoS of each publisher the recorder found (``offered_qos_profiles``)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import EdgeSamples, Scene, duration, edge, listed
from tftools.core.arrays import BoolArray, Int32Array, Int64Array
from tftools.core.figures import pause_rows, record_span
from tftools.core.time import NS_PER_S, from_sec
from tftools.sources.contents import IN_METADATA, OfferedQos, is_static_topic


@dataclass(frozen=True)
class TopicTally:
    """One tf topic of one rosbag2 file: its messages, those that carried a transform, its publishers."""

    file: str
    topic: str
    messages: int
    transforms: int
    instants: int  # record times of those transforms: messages at one instant cannot be told apart
    publishers: int
    observed: int | None = None  # the messages read that held no transform, where the reader counted them
    listed_in: str = IN_METADATA  # where ``publishers`` were counted (``OfferedQos.source``)

    @property
    def empty(self) -> int:
        """Messages that carry no transform: as read, else at least those that metadata.yaml counts beyond
        the transforms (each other one carries one or more)."""
        return self.observed if self.observed is not None else max(0, self.messages - self.transforms)

    @property
    def empty_at_most(self) -> int:
        return self.observed if self.observed is not None else max(0, self.messages - self.instants)

    @property
    def static(self) -> bool:
        return is_static_topic(self.topic)


def tallies(scene: Scene) -> list[TopicTally]:
    """Each tf topic of each rosbag2 file on disk whose metadata.yaml counts it; computed once per scene."""
    return scene.shared("tf_topic_tallies", lambda: list(_tallies(scene)))


def silent_moving_topics(scene: Scene) -> list[TopicTally]:
    """/tf topics whose publishers (one or more) sent not one message, in a recording without moving transforms."""
    if (~scene.rows.static).any():
        return []
    return [t for t in tallies(scene) if not t.static and t.publishers and not t.messages]


def _tallies(scene: Scene) -> Iterator[TopicTally]:
    """Per file and tf topic: metadata.yaml's counts (a rosbag2 directory), and the empty messages as read
    where the reader counted them (every file read: a bare .db3, an MCAP, a ROS 1 bag)."""
    rows = scene.rows
    records, static = rows.record_time.whole(), rows.static
    for file in scene.recording.contents.files:
        qos = scene.recording.qos.get(file.path)
        listed = _counts(qos, scene.recording.contents.topics) if Path(file.path).is_dir() else {}
        read = file.tf_messages
        inside = (records >= file.start) & (records <= file.end)
        for topic in dict.fromkeys([*listed, *read]):
            messages, publishers = listed.get(topic, (read.get(topic, (0, 0))[0], 0))
            if messages > file.message_count:  # more than the file holds in all: metadata.yaml not of this file
                messages = read.get(topic, (0, 0))[0]
            seen, empty = read.get(topic, (0, 0))
            observed = empty if topic in read and seen == messages else None  # a window read: not all of it
            if topic not in listed and not empty:
                continue  # no metadata to judge by, and nothing empty observed
            mine = inside & (static == is_static_topic(topic))
            transforms, instants = int(mine.sum()), len(np.unique(records[mine]))
            source = qos.source if qos is not None else IN_METADATA
            yield TopicTally(file.path, topic, messages, transforms, instants, publishers, observed, source)


def _counts(qos: OfferedQos | None, topics: tuple[str, ...]) -> dict[str, tuple[int, int]]:
    """Per tf topic: its messages and its publishers, as the recording lists them (metadata.yaml, or without one
    its files' own: ``OfferedQos.source``; read with the bag; nothing
    if unreadable: ``static_volatile`` says so)."""
    counts = qos.counts if qos is not None else {}
    return {topic: counted for topic, counted in counts.items() if topic in topics}


#: Pauses of several edges are one stall when each begins within this long (ns) of the first one.
STALL_WINDOW = NS_PER_S
#: A stall holds this many edges at least, or every moving edge where there are fewer.
STALL_EDGES = 3


@dataclass(frozen=True)
class Pause:
    """One pause of one moving edge (``figures.pause_rows``: what ``rate`` reports): from the stamp before
    it to the stamp after it, and when those two arrived (record clock; 0 where unknown)."""

    edge: tuple[str, str]
    start: int
    end: int
    arrived: tuple[int, int]


def _publishing(scene: Scene) -> list[EdgeSamples]:
    """The moving edges a stall can stop: not a detector's, which it sends only while it sees what it detects (an
    Agri Bot's 44 tomatoes, named by their place in a list, unseen together whenever the camera turned away)."""
    return scene.shared("publishing", lambda: [e for e in scene.dynamic_edges if e.key not in scene.detections])


def _pauses(scene: Scene) -> list[Pause]:
    floor = from_sec(scene.thresholds.max_gap)
    found = []
    for e in _publishing(scene):
        if len(e.stamps) < 3:
            continue
        for r in pause_rows(e.stamps, floor, record_span(e.record_times))[2].tolist():
            arrived = (int(e.record_times[r]), int(e.record_times[r + 1]))
            found.append(Pause(e.key, int(e.stamps[r]), int(e.stamps[r + 1]), arrived))
    return sorted(found, key=lambda p: p.start)


def stalls(scene: Scene) -> list[list[Pause]]:
    """Pauses of several moving edges that begin within ``STALL_WINDOW`` of the first of them, one per edge
    (its first there), at least ``STALL_EDGES`` of them or every moving edge, and not all from one message
    stream (edges sent together pause together: that is one publisher's pause, which ``rate`` says)."""
    pauses = _pauses(scene)
    moving = len({e.key for e in _publishing(scene)})
    found, i = [], 0
    while i < len(pauses):
        window = [p for p in pauses[i:] if p.start - pauses[i].start <= STALL_WINDOW]
        together = list({p.edge: p for p in reversed(window)}.values())[::-1]
        streams = {(p.start, p.end, p.arrived) for p in together}
        if len(together) >= min(STALL_EDGES, moving) and len(streams) > 1:
            found.append(together)
            i += len(window)
        else:
            i += 1
    return found


class Stall(NamedTuple):
    """One stall (``stalls``) and what the record clock saw meanwhile (``_meanwhile``): said, and which of
    ``_LOOK`` it points to."""

    pauses: list[Pause]
    meanwhile: str
    look: str


@register("stall", Severity.warning, "many moving edges going silent at once: one stop, said once")
def stall(scene: Scene) -> Iterator[Finding]:
    """One finding for the stalls of the same edges that the record clock saw alike (a robot's link dropping out
    again and again is one problem), said with its own figures where one stands alone."""
    moving = {e.key for e in _publishing(scene)}
    seen = [Stall(pauses, *_meanwhile(scene, pauses, len(pauses) == len(moving))) for pauses in stalls(scene)]
    runs: dict[tuple[frozenset[tuple[str, str]], str], list[Stall]] = {}
    for one in seen:
        runs.setdefault((frozenset(p.edge for p in one.pauses), one.look), []).append(one)
    for run in runs.values():
        pauses = [p for one in run for p in one.pauses]
        first = run[0].pauses
        start, end = min(p.start for p in pauses), max(p.end for p in pauses)
        lengths = sorted((p.end - p.start) / NS_PER_S for p in pauses)
        spread = max((max(p.start for p in one.pauses) - min(p.start for p in one.pauses)) / NS_PER_S for one in run)
        every = len(first) == len(moving)
        meanwhile, look = run[0].meanwhile, run[0].look
        which = f"all {len(first)} moving edges" if every else f"{len(first)} of {len(moving)} moving edges"
        which = "both moving edges" if every and len(first) == 2 else which
        if len(run) > 1:
            longest = max(run, key=lambda one: max(p.end - p.start for p in one.pauses))
            meanwhile = longest.meanwhile.replace(" for ", " for up to ", 1) if look == "nothing" else meanwhile
            began = min(p.start for p in longest.pauses)
            when = f"at once {len(run)} times (each time {_together(spread)}), the first from {scene.at(start)}" + (
                f", the longest from {scene.at(began)}" if began != start else ""
            )
        else:
            when = f"{_together(spread)}, from {scene.at(start)}"
        yield Finding(
            Severity.warning,
            "stall",
            f"{which} went silent {when}, for {_range(lengths[0], lengths[-1])} "
            f"({listed([edge(*p.edge) for p in first])}){meanwhile}: "
            f"{'everything on /tf' if every and look not in _KEPT_COMING else 'they'} stopped at once",
            f"{_LOOK[look]}; lookups inside the stall interpolate across it",
            tuple(f for p in first for f in p.edge),
            first_time=start,
            last_time=end,
            count=len(pauses),
        )


def _together(spread: float) -> str:
    """How far apart (s) the edges of a stall went silent, in words: "within 0.450 s of each other"; never "within
    0.000 s" (a real Neato's driver sends its three edges with one stamp: they stop at the same instant)."""
    if spread == 0:
        return "at the same instant"
    return "less than 1 ms apart" if spread < 0.0005 else f"within {duration(spread)} of each other"


#: The looks where transforms kept arriving during the stall: not everything on /tf stopped, the edges did.
_KEPT_COMING = ("old stamps", "late")

#: What to look at, by what the record clock saw during a stall (``_meanwhile``).
_LOOK = {
    "nothing": "nothing reached the recorder, so what stopped is what the publishers and the recorder share: the "
    "machine (its load, a suspend), the network or DDS, or the recorder itself",
    "old stamps": "transforms kept coming, stamped no later than before: the clock they are stamped with stood "
    "still (a paused simulation, a driver's clock)",
    "late": "transforms kept coming, new samples but none stamped inside the stall (those stamped before it came "
    "late): the samples in between were held back or lost between the publishers and the recorder (a congested or "
    "lossy network or WiFi, DDS, the recorder falling behind), not a clock that stood still",
    "others": "the other edges went on: look for what these publishers share (one node, one machine, one link)",
    "unknown": "look for what the publishers share: the machine's load or a suspend, the network or DDS, a paused "
    "simulation clock, the recorder falling behind",
}


def _meanwhile(scene: Scene, pauses: list[Pause], every: bool) -> tuple[str, str]:
    """What the record clock saw during the stall, said, and which of ``_LOOK`` it points to: no transform at all
    on /tf, transforms that did not move the stopped edges on (stamps sent again: a clock that stood still; or new
    samples stamped outside it: a link that held them back), or the other edges."""
    begin, finish = min(p.arrived[0] for p in pauses), max(p.arrived[1] for p in pauses)
    if not begin:
        return "", "unknown"
    rows = scene.rows
    moving = ~rows.static
    order = np.argsort(rows.record_time[moving], kind="stable")
    records = rows.record_time[moving][order]
    within = (records >= begin) & (records <= finish)
    inside = records[within]
    silent = int(np.diff(inside).max()) if len(inside) > 1 else finish - begin
    if silent > from_sec(scene.thresholds.max_gap) and silent * 2 >= min(p.arrived[1] - p.arrived[0] for p in pauses):
        return f"; the recorder received no transform on /tf for {duration(silent / NS_PER_S)}", "nothing"
    if not every:
        return "; the other moving edges went on", "others"
    if len(inside) > len(pauses) * 2:
        upto = order[: int(np.searchsorted(records, finish, side="right"))]  # a stamp re-sent came before it
        new = _new_samples(rows.parent[moving][upto], rows.child[moving][upto], rows.stamp[moving][upto])
        if np.count_nonzero(new[within[: len(upto)]]) * 2 > len(inside):  # a real JetAcker's WiFi: no clock stopped
            return (
                f"; {len(inside):,} transforms arrived on /tf meanwhile, new samples but none stamped inside it",
                "late",
            )
        return f"; {len(inside):,} transforms arrived on /tf meanwhile, stamped no later than before", "old stamps"
    return "", "unknown"


def _new_samples(parents: Int32Array, children: Int32Array, stamps: Int64Array) -> BoolArray:
    """Of transforms in arrival order, those whose edge and stamp had not arrived before (a stamp re-sent is not)."""
    keys = np.stack([parents.astype(np.int64), children.astype(np.int64), stamps], axis=1)
    new = np.zeros(len(stamps), dtype=bool)
    new[np.unique(keys, axis=0, return_index=True)[1]] = True
    return new


def _empty_messages(tally: TopicTally) -> str:
    """How many of a topic's messages carry no transform: all of them said so, not '1 of 1 ... (0 transforms in
    the others)'."""
    exactly = "" if tally.empty == tally.empty_at_most else "at least "
    if tally.empty == tally.messages:
        every = "its only message" if tally.messages == 1 else f"all {tally.messages:,} messages"
        return f"{every} on {tally.topic} {'carries' if tally.messages == 1 else 'carry'} no transform"
    others = f"({counted(tally.transforms, 'transform')} in the others)"
    return f"{exactly}{tally.empty:,} of {tally.messages:,} messages on {tally.topic} carry no transform {others}"


def _no_fixed_joint(scene: Scene, tally: TopicTally) -> str | None:
    """Why /tf_static's messages are empty where the robot's description has no fixed joint: robot_state_publisher
    sends its fixed joints there, none (a student's disc-robot simulator, PlaidTrack/CSCE-452-Project-4: a URDF of
    base_link alone, its one /tf_static message empty); None otherwise."""
    robot = scene.robot
    if not tally.static or tally.transforms or robot is None or any(not j.moving for j in robot.description.joints):
        return None
    return (
        f"robot_state_publisher sends the fixed joints on {tally.topic}, and {robot.description.source} has none "
        f"(its links: {listed(list(robot.description.links), 5)}): an empty message, harmless itself; a sensor "
        "mounted on the robot needs its link and a fixed joint in the URDF"
    )


def _empty_senders(scene: Scene, tally: TopicTally) -> str:
    """Who sent a tf topic's empty messages, where its file names them (a ROS 1 bag's connections: a real PR2's 13
    empty /tf messages all /dynamic_tf_publisher's, jsk_pr2eus's pr1012_sensors.bag), each with how many; "" where
    the file does not name them all."""
    file = next((f for f in scene.recording.contents.files if f.path == tally.file), None)
    senders = file.tf_empty_from.get(tally.topic, {}) if file is not None else {}
    if sum(senders.values()) != tally.empty:
        return ""
    ranked = sorted(senders.items(), key=lambda kv: (-kv[1], kv[0]))
    return listed([f"{p} sent {n:,}" for p, n in ranked], 3)


def _range(shortest: float, longest: float) -> str:
    if duration(shortest) == duration(longest):
        return duration(longest)
    return f"{duration(shortest)} to {duration(longest)}"


@register("silent_tf", Severity.warning, "tf publishers that sent nothing, tf messages without transforms")
def silent_tf(scene: Scene) -> Iterator[Finding]:
    silent = silent_moving_topics(scene)
    for tally in tallies(scene):
        said = []
        if tally in silent:
            said.append(
                f"{tally.topic} had {counted(tally.publishers, 'publisher')} when recording began ({tally.listed_in}'s "
                "offered QoS) and not one message was recorded: nothing in this recording moves"
            )
        if tally.empty:
            said.append(_empty_messages(tally))
        if not said:
            continue
        fixed_none = _no_fixed_joint(scene, tally)
        # mostly empty: a publisher gone wrong; robot_state_publisher's static message with no fixed joint is not
        warning = tally in silent or (tally.empty * 2 > tally.messages and fixed_none is None)
        hints = []
        if tally in silent:
            hints.append(
                "the moving transforms' publishers ran but sent nothing while recorded (their input never came: "
                "joint states, odometry, a clock), or the recorder missed them: lookups through them all fail"
            )
        if tally.empty and fixed_none is not None:
            hints.append(fixed_none)
        elif tally.empty and (senders := _empty_senders(scene, tally)):
            hints.append(
                f"{senders}: a node sending tf messages without transforms has nothing to send; check its setup"
            )
        elif tally.empty:
            named = scene.list_publishers(tally.topic)
            hints.append(f"a node sending tf messages without transforms is misconfigured: {named} names them")
        yield Finding(
            Severity.warning if warning else Severity.info,
            "silent_tf",
            f"{tally.file}: {'; '.join(said)}",
            "; ".join(hints),
            (),
            (tally.topic,),
            count=tally.empty or tally.publishers,
        )
