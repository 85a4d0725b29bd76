"""What a repaired copy (``tfx static --repair``) sends at its start and at each repeat: the static transforms tf2
holds at that instant of the recording, not the recording's messages replayed. tf2 keeps one value of each static
frame, the latest it was sent (within one message, the last): replaying messages that disagree sent every frame
that moved between parents or values across them back and forth at each repeat (the create3's two URDFs: 21
changes of value in the recording, 441 in its copy)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from itertools import groupby

import numpy as np

from tftools.core.arrays import Int32Array, Int64Array, IntpArray
from tftools.core.transform import Transform
from tftools.sources.contents import is_static_topic

#: Messages as a copy writes them: each (who sends it, its transforms).
Messages = list[tuple[str, list[Transform]]]


@dataclass(frozen=True)
class StaticRows:
    """The recording's /tf_static transforms in the order tf2 takes them (by record time, each message in its own
    order): row ``k`` sets frame ``children[k]`` at record time ``times[k]``, in message ``messages[k]`` (one
    sender at one instant), sent by ``senders[messages[k]]``; ``transform(k)`` is its transform as sent."""

    times: Int64Array
    children: Int32Array
    messages: IntpArray
    senders: Sequence[str]
    transform: Callable[[int], Transform]

    def message_times(self) -> list[int]:
        """When the recording holds each message (record time, ns)."""
        starts = np.flatnonzero(np.r_[True, np.diff(self.messages) != 0])
        return [int(t) for t in self.times[starts]]


class HeldStatics:
    """The static transforms tf2 holds as a copy is written, asked at increasing record times (``at``): each frame's
    first transform until the recording sends it (the copy's start gave it that), then the latest the recording
    sent before that instant. Sending them again changes no parent and no value."""

    def __init__(self, rows: StaticRows) -> None:
        self.rows = rows
        self._children: list[int] = rows.children.tolist()
        self._held: dict[int, int] = {}  # frame -> its row tf2 holds
        for k, child in enumerate(self._children):
            self._held.setdefault(child, k)
        self._applied = 0
        pairs = np.unique(np.stack([rows.messages.astype(np.int64), rows.children.astype(np.int64)]), axis=1)
        self._frames = np.bincount(pairs[0], minlength=len(rows.senders))  # of each message, a frame sent twice once

    def at(self, time: int) -> Messages:
        """What tf2 holds just before record time ``time``, as messages: the rows of each recorded message that tf2
        still holds, in the recording's order, each on its sender's connection and with its own stamps (as a
        StaticTransformBroadcaster sends again). A message of which tf2 holds only some transforms (another
        overrode the rest) is sent in part where the recording names its sender (a ROS 1 callerid). Where it names
        none, tfx tells publishers apart by their messages, and a message lacking transforms of an earlier one
        reads as another publisher's: what tf2 still holds of it goes out in the latest message of its topic
        (sent whole: nothing later overrode it), stamped as that one, which reads as that message's publisher
        sending them all; tf2's values are unchanged, and no frame is lost to a split of the copy (the URDF-first
        Neato's 9 links of its robot_state_publisher, overridden in one transform by a lone
        static_transform_publisher; sent apart, they read as a third publisher's; whole, they flipped the laser's
        value at each repeat). A part with
        no later whole message of its topic (the copy's start, which holds each frame's first transform) is left
        out: tf2 gets it when the recording sends it."""
        rows = self.rows
        end = int(np.searchsorted(rows.times, time, side="left"))
        for k in range(self._applied, max(end, self._applied)):
            self._held[self._children[k]] = k
        self._applied = max(end, self._applied)
        held = sorted(self._held.values())  # rows are in message order: each message's rows run together
        runs = [(int(m), list(run)) for m, run in groupby(held, key=lambda k: int(rows.messages[k]))]
        whole = {rows.senders[m]: i for i, (m, mine) in enumerate(runs) if len(mine) == self._frames[m]}
        sent = [[rows.transform(k) for k in mine] for _, mine in runs]
        for i, (message, mine) in enumerate(runs):
            sender = rows.senders[message]
            if len(mine) == self._frames[message] or not is_static_topic(sender):
                continue
            if (j := whole.get(sender, -1)) > i:
                stamp = sent[j][0].stamp
                sent[j] += [replace(t, stamp=stamp) for t in sent[i]]
            sent[i] = []
        return [(rows.senders[m], transforms) for (m, _), transforms in zip(runs, sent, strict=True) if transforms]
