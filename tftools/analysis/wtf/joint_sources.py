"""A state publisher fed joint states by two sources, from the shapes of its messages: robot_state_publisher sends,
for each /joint_states message it gets, one /tf message of that message's moving joints; two sources of
/joint_states (joint_state_publisher beside a simulator or a driver, two controllers) make messages of two kinds
that carry some joints alike, each kind at its own rate, their stamps taking turns on those joints."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from tftools.analysis.findings import Finding, counted
from tftools.analysis.wtf.jumps import sent_together
from tftools.analysis.wtf.scene import Scene
from tftools.core.arrays import IntpArray
from tftools.core.figures import rate_hz

#: A kind of message is a source's where it is at least this many of a publisher's messages, and this share:
#: fewer are a joint's message now and then (a driver adding a joint once), not a source.
KIND_MIN_MESSAGES, KIND_MIN_SHARE = 20, 0.05


@dataclass(frozen=True)
class MessageKind:
    """Messages of a publisher that carry the same joints: how many joints, how many messages, at what rate."""

    joints: int
    messages: int
    rate_hz: float


@dataclass(frozen=True)
class JointSources:
    """A publisher's joints that came in messages of two kinds or more (``kinds``, most first), the ``shared``
    joints in each: two sources of its joint states, taking turns on those joints."""

    publisher: str
    kinds: tuple[MessageKind, ...]
    shared: int

    def in_words(self, scene: Scene) -> str:
        """'/robot_state_publisher sent its joints in messages of 2 kinds: 3,172 of 12 joints at 49.9 Hz and 790 of
        16 at 9.9 Hz, the same 12 in each'."""
        kinds = [
            f"{k.messages:,} of {counted(k.joints, 'joint') if i == 0 else k.joints} at {k.rate_hz:.1f} Hz"
            for i, k in enumerate(self.kinds)
        ]
        listed = ", ".join(kinds[:-1]) + f" and {kinds[-1]}"
        who = scene.publisher(self.publisher)
        return f"{who} sent its joints in messages of {len(self.kinds)} kinds: {listed}, the same {self.shared} in each"


def joint_sources(scene: Scene) -> dict[tuple[str, str], JointSources]:
    """Each joint (``sent_together``) sent in messages of two kinds or more by its publisher, found once per scene;
    none where publishers are not named (one topic's messages may be several nodes')."""
    return scene.shared("joint sources", lambda: _joint_sources(scene))


def _joint_sources(scene: Scene) -> dict[tuple[str, str], JointSources]:
    wanted = sent_together(scene)
    if not scene.publishers_known or len(wanted) < 2:
        return {}
    rows = scene.rows
    joints: list[tuple[str, str]] = []
    parts: list[IntpArray] = []  # one pass over the rows, not one per joint
    for parent, child, mine in rows.by_edge(~rows.static):  # refused ones too: every message sent
        if (parent, child) in wanted:
            joints.append((parent, child))
            parts.append(mine)
    if len(joints) < 2:
        return {}
    which = np.concatenate(parts)
    edge_of = np.repeat(np.arange(len(joints)), [len(part) for part in parts])
    authority, record, stamp = rows.authority[which], rows.record_time[which], rows.stamp[which]
    order = np.lexsort((edge_of, stamp, record, authority))
    authority, record, stamp, edge_of = authority[order], record[order], stamp[order], edge_of[order]
    place = np.arange(len(edge_of))
    group = np.ones(len(edge_of), bool)  # one publisher, record time and stamp: a message, or several alike
    group[1:] = (authority[1:] != authority[:-1]) | (record[1:] != record[:-1]) | (stamp[1:] != stamp[:-1])
    run = group.copy()
    run[1:] |= edge_of[1:] != edge_of[:-1]
    # a joint's n-th row at one record time and stamp is in its n-th message there (two sent in one tick of a
    # simulated clock's record times, 1 ms apart, are two messages: 3,172 of one kind, not 3,168)
    nth = place - np.maximum.accumulate(np.where(run, place, 0))
    message = np.cumsum(group) * (int(nth.max(initial=0)) + 1) + nth
    order = np.argsort(message, kind="stable")
    authority, stamp, edge_of, message = authority[order], stamp[order], edge_of[order], message[order]
    starts = np.flatnonzero(np.concatenate(([True], message[1:] != message[:-1])))
    # a message's kind: the sum of its joints' random keys (wrapping), one number for the set of joints it carries
    keys = np.random.default_rng(0).integers(0, np.iinfo(np.int64).max, len(joints), dtype=np.int64).view(np.uint64)
    with np.errstate(over="ignore"):
        kind = np.add.reduceat(keys[edge_of], starts)
    found: dict[tuple[str, str], JointSources] = {}
    message_authority, message_stamp = authority[starts], stamp[starts]
    for publisher in np.unique(message_authority).tolist():
        theirs = message_authority == publisher
        kinds, first, counts = np.unique(kind[theirs], return_index=True, return_counts=True)
        big = (counts >= KIND_MIN_MESSAGES) & (counts >= KIND_MIN_SHARE * int(theirs.sum()))
        if big.sum() < 2:
            continue
        at = np.flatnonzero(theirs)
        by_count = np.argsort(-counts[big], kind="stable")
        chosen = [(kinds[big][i], int(at[first[big][i]]), int(counts[big][i])) for i in by_count]
        sets = [_joints_of(edge_of, starts, message) for _, message, _ in chosen]
        shared = set.intersection(*sets)
        if not shared:  # an arm's and a gripper's joints in messages of their own: one source each
            continue
        stamps = message_stamp[theirs]
        described = tuple(
            MessageKind(len(joints_in), n, _rate(stamps[kind[theirs] == k]))
            for (k, _, n), joints_in in zip(chosen, sets, strict=True)
        )
        sources = JointSources(rows.authorities[publisher], described, len(shared))
        found.update({joints[j]: sources for j in shared})
    return found


def _joints_of(edge_of: np.ndarray, starts: np.ndarray, message: int) -> set[int]:
    """The joints (their places in the list) the ``message``-th message carries."""
    end = starts[message + 1] if message + 1 < len(starts) else len(edge_of)
    return set(edge_of[starts[message] : end].tolist())


def _rate(stamps: np.ndarray) -> float:
    """A kind's messages' rate: how many over their stamps' span."""
    ordered = np.sort(stamps)
    return rate_hz(len(ordered), int(ordered[-1] - ordered[0])) if len(ordered) > 1 else 0.0


#: The figure that names the publisher whose joints came in messages of two kinds (``JointSources``): findings on
#: its joints share one cause (``causes``).
JOINT_SOURCES = "joint_sources_of"


def with_joint_sources(scene: Scene, finding: Finding) -> Finding:
    """``finding`` about a joint sent in messages of two kinds (``joint_sources``), with those kinds said after what
    it observed and a hint about two sources of joint states; others as they are."""
    sources = joint_sources(scene).get(finding.frames[:2]) if len(finding.frames) == 2 else None
    if sources is None:
        return finding
    hint = (
        f"{scene.publisher(sources.publisher)} sends each joint stamped as the joint states message it came in: "
        "messages of two kinds carrying the same joints are two sources of joint states (joint_state_publisher "
        "beside the simulator or the driver, or two controllers), their stamps taking turns on those joints; have "
        f"one source send each joint; check who publishes /joint_states ({scene.list_publishers('/joint_states')})"
    )
    figures = {**finding.figures, JOINT_SOURCES: sources.publisher}
    return replace(finding, message=f"{finding.message}; {sources.in_words(scene)}", hint=hint, figures=figures)
