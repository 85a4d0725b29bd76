"""``Rows.edge_publishers``: one edge's /tf rows by publisher, the one helper ``jump`` (each publisher's own
samples) and ``future`` (who sent the early ones) read, instead of regrouping every /tf row per edge."""

from __future__ import annotations

from tests.analysis.wtf_scenes import START, _t, recording
from tests.bags import TfMessage
from tftools.analysis.wtf.rows import rows_of

MS = 1_000_000


def _rows() -> tuple[list[TfMessage], list[tuple[str, list[int]]]]:
    """odom -> base_link from /ekf and /zed taking turns, base_link's other parent (map) from /amcl, and a
    /tf_static row of the edge: only the turns' rows are the edge's on /tf."""
    messages = []
    for i in range(6):
        who = "/ekf" if i % 2 == 0 else "/zed"
        stamp = START + i * 100 * MS
        messages.append(TfMessage("/tf", stamp + MS, [_t("odom", "base_link", stamp, x=0.1 * i)], who))
    messages.insert(3, TfMessage("/tf", START + 250 * MS, [_t("map", "base_link", START + 250 * MS)], "/amcl"))
    messages.insert(0, TfMessage("/tf_static", START, [_t("odom", "base_link", START)], "/static"))
    return messages, [("/ekf", [1, 3, 6]), ("/zed", [2, 5, 7])]


def test_an_edges_rows_by_publisher_in_record_order() -> None:
    messages, expected = _rows()
    rows = rows_of(recording(messages))
    got = [(rows.authorities[p], own.tolist()) for p, own in rows.edge_publishers("odom", "base_link")]
    assert got == expected
    stamps = [rows.stamp[own].tolist() for _, own in rows.edge_publishers("odom", "base_link")]
    assert stamps == [[START + i * 100 * MS for i in (0, 2, 4)], [START + i * 100 * MS for i in (1, 3, 5)]]


def test_the_other_parents_edge_is_its_own() -> None:
    messages, _ = _rows()
    rows = rows_of(recording(messages))
    got = [(rows.authorities[p], own.tolist()) for p, own in rows.edge_publishers("map", "base_link")]
    assert got == [("/amcl", [4])]
