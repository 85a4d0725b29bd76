"""A frame with two parents: tf2 keeps one history per frame, ``tfx frames`` shows the frame (its parents, its
samples) and each parent's edge counted as ``tfx monitor``'s row of it (``edge_stats``), the same numbers."""

from __future__ import annotations

from tests.analysis.wtf_scenes import START, _t, recording
from tests.bags import TfMessage
from tftools.analysis.edges import edge_stats
from tftools.analysis.frames import ParentEdge, tree_of

MS = 1_000_000


def test_each_parents_edge_is_monitors_row() -> None:
    messages = [
        TfMessage("/tf", START + i * 100 * MS + MS, [_t("odom", "base_link", START + i * 100 * MS)], "/ekf")
        for i in range(3)
    ] + [
        TfMessage("/tf", START + i * 100 * MS + MS, [_t("map", "base_link", START + i * 100 * MS)], "/amcl")
        for i in range(3, 5)
    ]
    buffer = recording(messages).buffer
    frame = tree_of(buffer).frames["base_link"]
    assert frame.parents == ("odom", "map") and frame.count == 5
    rows = [s for s in edge_stats(buffer) if s.child == "base_link"]
    assert frame.edges == tuple(
        ParentEdge(s.parent, s.count, s.authorities, s.first_stamp, s.last_stamp, s.rate_hz) for s in rows
    )
    assert [(e.parent, e.count, e.authorities) for e in frame.edges] == [("odom", 3, ("/ekf",)), ("map", 2, ("/amcl",))]
    assert frame.edges[0].rate_hz == 10.0


def test_a_frame_with_one_parent_has_no_edge_rows_of_its_own() -> None:
    messages = [TfMessage("/tf", START + i * MS, [_t("odom", "base_link", START + i * MS)], "/ekf") for i in range(3)]
    assert tree_of(recording(messages).buffer).frames["base_link"].edges == ()
