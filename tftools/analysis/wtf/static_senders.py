"""Who sent each /tf_static transform: the publisher a ROS 1 bag names, or, where the recording names none
(ROS 2 bags, MCAP), one told from the messages. C++'s StaticTransformBroadcaster (robot_state_publisher's,
static_transform_publisher's) re-sends all of its transforms in every message, so a message that lacks
transforms of an earlier one comes from another publisher (Python's sends only those it is given: a node
that changes one of its transforms that way is taken for two publishers, which disagree all the same);
and metadata.yaml (or a bare file's topics table or channels) lists how many publishers /tf_static had when
recording began, so where it lists
several, a message whose values differ from an earlier one's is taken for another publisher's. So is one
that differs where both were sent long before the recording began: a late subscriber gets only the latest
message of each static broadcaster (its history holds one, QoS depth 1), so two such messages are two
publishers' (a real Neato's driver and robot_state_publisher, the second found after metadata.yaml listed one);
so are two with the same values and other stamps (static_transform_publisher processes left running, each
stamped at its start), and, where metadata.yaml lists more publishers than were told apart, one with another's
values and other stamps."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tftools.analysis.findings import counted
from tftools.analysis.listed import listed_publishers
from tftools.analysis.wtf.scene import Scene
from tftools.core.arrays import Int32Array, IntpArray
from tftools.core.time import NS_PER_S

#: Beyond this many different /tf_static messages, publishers are not told apart (each topic is one).
MESSAGES_COMPARED = 1000
#: A /tf_static message stamped this long before the recording's first message was sent before the recorder
#: subscribed (it came from its publisher's history): more than a recorder takes to start.
LATCHED_BEFORE = 10 * NS_PER_S


@dataclass(frozen=True)
class Sender:
    """One publisher of /tf_static: how a finding names it, and what was seen of it."""

    name: str
    messages: int = 0
    transforms: int = 0  # in its first message
    first: int = 0  # when its first message arrived (``Scene.arrival``)
    evidence: str = ""  # why it is not the publisher of an earlier message, said of it ("lacks ..."; "": none)
    number: int = 0  # told from the messages: 1 for the first to send
    #: Of its ``messages``, those the same as its first (that one counted): the rest hold more transforms
    #: (``most``: the most in one) or other values of its first's (``revalued``) (a copy ``tfx static --repair``
    #: wrote: the merged latest transforms re-sent every 5 s)
    alike: int = 0
    most: int = 0
    revalued: bool = False


@dataclass(frozen=True)
class StaticSenders:
    """``sender[row]`` indexes ``senders`` for each /tf_static row of ``Rows`` (-1 for the others);
    ``inferred``: told from the messages, the recording naming no publishers."""

    sender: Int32Array
    senders: list[Sender]
    inferred: bool

    def of(self, rows: IntpArray) -> tuple[int, ...]:
        """The senders of ``rows``, in order of first appearance."""
        return tuple(dict.fromkeys(self.sender[rows].tolist()))

    def names(self, ids: tuple[int, ...]) -> list[str]:
        return [self.senders[i].name for i in ids]


def static_senders(scene: Scene) -> StaticSenders:
    """Who sent each /tf_static row; computed once per scene."""
    return scene.shared("static_senders", lambda: _senders(scene))


def _senders(scene: Scene) -> StaticSenders:
    rows = scene.rows
    static = rows.static & rows.usable
    sender = np.full(len(rows), -1, np.int32)
    named = rows.authority.whole()
    sender[static] = named[static]
    by_name = StaticSenders(sender, [Sender(scene.publisher(a)) for a in rows.authorities], False)
    if scene.publishers_known or not static.any():
        return by_name
    told = _told_apart(scene, np.flatnonzero(static))
    if told is None:
        return by_name
    sender[told[0]] = told[1]
    return StaticSenders(sender, told[2], True)


@dataclass
class _Publisher:
    """A publisher being told apart: the transforms of its latest message (edge -> value bytes)."""

    latest: dict[tuple[int, int], bytes]
    messages: int
    transforms: int
    first: int
    evidence: str
    latched: bool  # its latest message was sent before the recording began (``LATCHED_BEFORE``)
    stamps: tuple[int, int] = (0, 0)  # its latest message's earliest and latest stamps
    key: bytes = b""  # its first message's ``seen`` key: later messages of that key are the same
    alike: int = 1  # its messages the same as its first, that one counted
    most: int = 0  # the most transforms in one of its messages
    revalued: bool = False  # a later message holds another value for a transform of its first

    def add(self, key: bytes, edges: dict[tuple[int, int], bytes] | None, first: dict[tuple[int, int], bytes]) -> None:
        """One more message of it, seen under ``key``: ``edges``, its transforms, or None for a key seen
        before (what it holds already counted); ``first``: its first message's transforms."""
        self.messages += 1
        self.alike += key == self.key
        if edges is not None:
            self.most = max(self.most, len(edges))
            self.revalued |= any(e in edges and edges[e] != v for e, v in first.items())


def _told_apart(scene: Scene, static: IntpArray) -> tuple[IntpArray, Int32Array, list[Sender]] | None:
    """The /tf_static rows, the publisher each is told to come from, and those publishers; None where there
    are too many different messages to compare."""
    messages = _Messages(scene, static)
    keys: list[bytes] = []
    distinct: set[bytes] = set()
    for k in range(len(messages)):
        keys.append(messages.fingerprint(k))
        distinct.add(keys[-1])
        if len(distinct) > MESSAGES_COMPARED:
            return None
    qos = scene.recording.qos
    found = [(n, t) for t in scene.authorities_of(static) if (n := listed_publishers(qos, t)) is not None]
    listed, topic = max(found, default=(None, ""))
    listing = listed.publishers if listed is not None else 0
    said = listed.said(topic) if listed is not None else ""
    several = listing >= 2
    began = _recording_began(scene)
    publishers: list[_Publisher] = []
    firsts: list[dict[tuple[int, int], bytes]] = []  # each publisher's first message's transforms
    chosen = np.empty(len(messages), np.int32)
    seen: dict[bytes, int] = {}
    for m in messages.in_arrival_order():
        low, high = messages.stamps(m)
        latched = began is not None and low > 0 and high <= began - LATCHED_BEFORE
        # Sent before the recording began, a message reached the recorder from its publisher's history, which
        # holds one: the same transforms with other stamps are another publisher's, not a re-send.
        key = keys[m] + (messages.stamp_bytes(m) if latched else b"")
        if key in seen:  # the same transforms again: a re-send
            k = seen[key]
            publishers[k].add(key, None, firsts[k])
            chosen[m] = k
            continue
        edges = messages.transforms(m)
        # Where the recording lists more publishers than are told apart, the same values with other stamps
        # are taken for one of those not yet heard, as where both were sent before the recording began.
        held = latched or len(publishers) < listing
        earlier, evidence = _publisher_of(scene, publishers, edges, several, said, (held, low, high))
        if earlier is None:
            first = messages.arrival(m)
            publishers.append(
                _Publisher(edges, 1, len(edges), first, evidence, latched, (low, high), key, most=len(edges))
            )
            firsts.append(edges)
            k = len(publishers) - 1
        else:
            k = earlier
            publishers[k].add(key, edges, firsts[k])
            publishers[k].latest = edges
            publishers[k].latched = latched
            publishers[k].stamps = (low, high)
        seen[key] = k
        chosen[m] = k
    senders = [_sender(k, p) for k, p in enumerate(publishers, 1)]
    return messages.rows, np.repeat(chosen, np.diff(messages.bounds)), senders


def _publisher_of(
    scene: Scene,
    publishers: list[_Publisher],
    edges: dict[tuple[int, int], bytes],
    several: bool,
    listed: str,
    sent: tuple[bool, int, int],
) -> tuple[int | None, str]:
    """Which earlier publisher could have sent a message of ``edges`` (None: another), and if another, why.
    A publisher's next message holds every transform of its last; where the recording lists ``several``
    publishers, or both messages were sent before the recording began (``sent``: whether it was, and its
    earliest and latest stamps; a static broadcaster's history holds one), one whose values differ from this
    message's is taken for another, and so, both sent before, is one with the same values and other stamps.
    ``listed``: what the recording lists of the topic's publishers (``Listed.said``; "": nothing)."""
    latched, low, high = sent
    could: list[tuple[bool, int]] = []
    differ: list[int] = []
    stamped: list[int] = []
    for k, p in enumerate(publishers):
        if not p.latest.keys() <= edges.keys():
            continue
        same = all(edges[e] == v for e, v in p.latest.items())
        if same and latched and (p.latched or several) and p.stamps != (low, high):
            stamped.append(k)
        elif same or not (several or (latched and p.latched)):
            could.append((same, k))
        else:
            differ.append(k)
    if could:
        return max(could)[1], ""  # the same values first, then the latest
    if stamped and not differ:
        why = (
            f"while {listed}"
            if several and listed
            else "both sent before the recording began: a late subscriber gets only the latest message of each "
            "static broadcaster, whose history holds one"
        )
        return None, f"has publisher {stamped[-1] + 1}'s values with other stamps, {why}"
    overlapping = [k for k, p in enumerate(publishers) if p.latest.keys() & edges.keys()]
    if not overlapping:
        return None, ""
    if differ and several and listed:
        return None, f"differs in value from publisher {differ[-1] + 1}'s while {listed}"
    if differ:
        return None, (
            f"differs in value from publisher {differ[-1] + 1}'s, both sent before the recording began (a late "
            "subscriber gets only the latest message of each static broadcaster: its history holds one)"
        )
    last = publishers[overlapping[-1]]
    missing = len(last.latest.keys() - edges.keys())
    return None, (
        f"lacks {missing} of publisher {overlapping[-1] + 1}'s {counted(len(last.latest), 'transform')} (C++'s "
        "StaticTransformBroadcaster, robot_state_publisher's and static_transform_publisher's, re-sends all of its "
        "transforms in every message)"
    )


def _sender(number: int, p: _Publisher) -> Sender:
    name = f"/tf_static publisher {number} (unnamed)"
    return Sender(name, p.messages, p.transforms, p.first, p.evidence, number, p.alike, p.most, p.revalued)


class _Messages:
    """The /tf_static rows grouped into messages (those of one topic received at one instant), each a
    slice of ``rows``: message ``k`` is ``rows[bounds[k]:bounds[k + 1]]``."""

    def __init__(self, scene: Scene, static: IntpArray) -> None:
        rows = scene.rows
        keys = np.stack([rows.authority[static].astype(np.int64), rows.record_time[static]], axis=1)
        _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        inverse = inverse.ravel()
        order = np.argsort(inverse, kind="stable")  # by message, each in record order
        self.rows: IntpArray = static[order]
        self.bounds = np.concatenate([[0], np.flatnonzero(np.diff(inverse[order])) + 1, [len(order)]])
        self._first = first
        self._parent, self._child = rows.parent[self.rows], rows.child[self.rows]
        self._values = np.ascontiguousarray(rows.values[self.rows])
        self._arrival = scene.arrival(self.rows)
        self._stamp = rows.stamp[self.rows]

    def __len__(self) -> int:
        return len(self.bounds) - 1

    def in_arrival_order(self) -> list[int]:
        return np.argsort(self._first, kind="stable").tolist()  # type: ignore[no-any-return]

    def _slice(self, k: int) -> slice:
        return slice(int(self.bounds[k]), int(self.bounds[k + 1]))

    def fingerprint(self, k: int) -> bytes:
        """Message ``k``'s transforms (frames and values, in its order): equal for a re-send of it."""
        s = self._slice(k)
        return self._parent[s].tobytes() + self._child[s].tobytes() + self._values[s].tobytes()

    def transforms(self, k: int) -> dict[tuple[int, int], bytes]:
        """Message ``k``'s transforms: (parent id, child id) -> value bytes."""
        s = self._slice(k)
        return {
            (int(p), int(c)): v.tobytes()
            for p, c, v in zip(self._parent[s], self._child[s], self._values[s], strict=True)
        }

    def arrival(self, k: int) -> int:
        return int(self._arrival[self._slice(k)].min())

    def stamp_bytes(self, k: int) -> bytes:
        """Message ``k``'s stamps, in its order."""
        return self._stamp[self._slice(k)].tobytes()

    def stamps(self, k: int) -> tuple[int, int]:
        """Message ``k``'s earliest and latest stamps."""
        stamps = self._stamp[self._slice(k)]
        return int(stamps.min()), int(stamps.max())


def _recording_began(scene: Scene) -> int | None:
    """The recording's first message's arrival on the stamps' clock (None where unknown)."""
    timeline = scene.timeline
    if timeline.record_start <= 0:
        return None
    began, known = timeline.ros_time(np.array([timeline.record_start], np.int64))
    return int(began[0]) if known[0] else None
