"""``Rows.by_edge`` / ``by_child`` (``Layout.groups``) and ``Column.whole`` (``Layout.whole``): found from the
buffer's segments one edge at a time, they must give what grouping every row's key as one column gave: each
edge's rows in record order, the edges by first arrival, whatever segments the rows lie in (a history that
changed parent, stamps arriving out of order, refused rows, the small histories copied into one)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

from tests.analysis.wtf_scenes import START, _t, recording
from tests.bags import TfMessage
from tftools.analysis.wtf.rows import SMALL_SEGMENT, Rows, Segment, rows_of
from tftools.core.transform import Transform

MS = 1_000_000


def _messages() -> list[TfMessage]:
    messages = []
    for i in range(3 * SMALL_SEGMENT):
        stamp = START + (i if i % 5 else i - 3) * 10 * MS  # now and then a stamp behind the one before
        parent = "map" if i % 7 == 3 else "odom"  # base_link's parent changes within its history
        messages.append(TfMessage("/tf", stamp + MS, [_t(parent, "base_link", stamp, x=0.01 * i)], "/ekf"))
        messages.append(TfMessage("/tf", stamp + 2 * MS, [_t("base_link", "arm", stamp, yaw=0.01 * i)], "/rsp"))
    for k in range(4):  # small histories, copied into one segment
        messages.append(TfMessage("/tf_static", START + k * MS, [_t("base_link", f"sensor{k}", START)], "/static"))
    nan = Transform((float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START + 55 * MS, "odom", "base_link")
    same = Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START + 56 * MS, "odom", "odom")
    messages.insert(20, TfMessage("/tf", START + 57 * MS, [nan, same], "/bad"))  # refused: its own segment
    return sorted(messages, key=lambda m: m.record_time)


def _reference(rows: Rows, mask: np.ndarray, by_parent: bool) -> list[tuple[int, int, list[int]]]:
    """Every row's key at once, grouped, by first arrival."""
    parent, child = rows.parent.whole(), rows.child.whole()
    groups: dict[tuple[int, int], list[int]] = {}
    for row in np.flatnonzero(mask).tolist():
        groups.setdefault((int(parent[row]) if by_parent else 0, int(child[row])), []).append(row)
    return sorted(((p, c, r) for (p, c), r in groups.items()), key=lambda g: g[2][0])


def test_groups_are_every_rows_key_grouped() -> None:
    rows = rows_of(recording(_messages()))
    assert len(rows._layout.segments) == 4  # base_link's (two parents), arm's, the refused, the small ones
    for mask in (rows.usable, ~rows.static, rows.static, rows.usable & ~rows.static, ~rows.usable):
        for by_parent in (True, False):
            got = [(p, c, r.tolist()) for p, c, r in rows._layout.groups(mask, by_parent)]
            assert got == _reference(rows, mask, by_parent)
            assert all(r.dtype == np.intp for _, _, r in rows._layout.groups(mask, by_parent))
    edges = [(p, c) for p, c, _ in rows.by_edge(rows.usable)]
    sensors = [("base_link", f"sensor{k}") for k in range(4)]
    assert edges == [("odom", "base_link"), ("base_link", "arm"), *sensors, ("map", "base_link")]


def test_a_whole_column_is_the_segments_in_record_order() -> None:
    rows = rows_of(recording(_messages()))
    layout = rows._layout
    columns: list[Callable[[Segment], npt.NDArray[Any]]] = [
        lambda s: s.stamp,
        lambda s: s.values,
        lambda s: s.refusals,
        lambda s: s.child,
    ]
    for column in columns:
        expected = np.concatenate([column(segment) for segment in layout.segments])[layout.place]
        got = layout.whole(column)
        assert got.dtype == expected.dtype
        assert np.array_equal(got, expected, equal_nan=got.dtype.kind == "f")
