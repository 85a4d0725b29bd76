"""Which transforms came together in one /tf message: its layout, the set of edges it held. A message is the rows
of one topic received at one instant (the grouping ``static_senders`` tells /tf_static publishers apart by). Where a
recording names no publishers, a layout is evidence of who sent a message: a broadcaster sends the same set of
edges each time (robot_state_publisher the joints of each /joint_states message, a driver its own), so one edge
arriving in two layouts that take turns comes from two senders, or from one fed by two sources."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from tftools.analysis.wtf.rows import Rows
from tftools.analysis.wtf.scene import Scene, edge
from tftools.core.arrays import Int64Array, IntpArray


@dataclass(frozen=True)
class Layouts:
    """``layout[row]``: the layout of the message each row of ``Rows`` came in (-1: on /tf_static, or its
    arrival unknown); ``example[k]``: the rows of one message of layout ``k``."""

    layout: Int64Array
    example: list[IntpArray]

    def edges(self, scene: Scene, k: int) -> list[str]:
        """The edges a message of layout ``k`` holds, in its order ("base_link -> wheel_drop_left")."""
        rows = scene.rows
        rows_of = self.example[k]
        parents, children = rows.parent[rows_of].tolist(), rows.child[rows_of].tolist()
        return [edge(rows.names[p], rows.names[c]) for p, c in zip(parents, children, strict=True)]


def message_layouts(scene: Scene) -> Layouts:
    """Each /tf row's message layout; computed once per scene."""
    return scene.shared("message_layouts", lambda: _layouts(scene))


#: Rows told into messages at once, at most: a span of record times at a time (the rows are in record order), so
#: that a recording of 4.1M transforms holds a few columns of this many rows, not of all of them.
ROWS_AT_ONCE = 1 << 19


def _layouts(scene: Scene) -> Layouts:
    rows = scene.rows
    layout = np.full(len(rows), -1, np.int64)
    static = rows.static
    numbers: dict[int, int] = {}  # a layout's key -> its number
    example: list[IntpArray] = []
    start = 0
    while start < len(rows):
        chosen = np.arange(start, min(start + ROWS_AT_ONCE, len(rows)))
        records = rows.record_time[chosen]
        if chosen[-1] + 1 < len(rows) and records[0] != records[-1]:  # the last instant's rows go with the next span
            chosen = chosen[: int(np.searchsorted(records, records[-1]))]
            records = records[: len(chosen)]
        start = int(chosen[-1]) + 1
        kept = ~static[chosen] & (records > 0)
        keys, firsts, of_rows = _messages(rows, chosen[kept], records[kept])
        for key, first in zip(keys.tolist(), firsts, strict=True):
            if key not in numbers:
                numbers[key] = len(example)
                example.append(first)
        if len(keys):
            layout[chosen[kept]] = np.array([numbers[k] for k in keys.tolist()], np.int64)[of_rows]
    return Layouts(layout, example)


def _messages(
    rows: Rows, chosen: IntpArray, records: Int64Array
) -> tuple[npt.NDArray[np.uint64], list[IntpArray], IntpArray]:
    """Of the /tf rows ``chosen`` (recorded at ``records``): each layout's key, the rows of one message of each, and
    each row's layout (an index into those)."""
    if not len(chosen):
        return np.zeros(0, np.uint64), [], np.zeros(0, np.intp)
    authority = rows.authority[chosen]
    order = np.lexsort((authority, records))  # each message's rows together, in their order
    chosen, records, authority = chosen[order], records[order], authority[order]
    new = np.ones(len(chosen), bool)
    new[1:] = (records[1:] != records[:-1]) | (authority[1:] != authority[:-1])
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], len(chosen))
    # a message's set of edges as one number: a sum of each edge's mixed bits, whatever its order, and its size
    edges = rows.parent[chosen].astype(np.uint64) << np.uint64(32) | rows.child[chosen].astype(np.uint64)
    sizes = (ends - starts).astype(np.uint64)
    keys, first, of_message = np.unique(
        np.add.reduceat(_mixed(edges), starts) ^ _mixed(sizes), return_index=True, return_inverse=True
    )
    of_rows = np.empty(len(chosen), np.intp)
    of_rows[order] = np.repeat(of_message.ravel(), ends - starts)
    return keys, [chosen[starts[m] : ends[m]] for m in first.tolist()], of_rows


def _mixed(x: npt.NDArray[np.uint64]) -> npt.NDArray[np.uint64]:
    """Each value's bits spread over all 64 (splitmix64's finaliser), so that sums of different sets differ."""
    with np.errstate(over="ignore"):
        x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        mixed: npt.NDArray[np.uint64] = x ^ (x >> np.uint64(31))
    return mixed
