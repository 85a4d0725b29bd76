"""Fuzzing the streamed read (``tfx echo/monitor --play``): mutated bags of every format read window by
window, windows of a few messages so that every window's edge is crossed. Every outcome is rows that a
whole read gives too, each once, or tftools' own one-line error, in bounded time; never another
exception. (A stream trusts the file's index to find a window: where damage made the index lie, it
can miss rows that a whole read, scanning, still finds.)"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest
from hypothesis import given

from tests.fuzz.test_bag_fuzz import FUZZ, KINDS, mutated, mutations, seed
from tftools.core.batch import TransformBatch, concat_batches
from tftools.core.errors import TfToolsError
from tftools.sources import read_recording
from tftools.sources.stream import stream_recording


def stream_anything(path: Path) -> None:
    try:
        streamed = stream_recording([path], window_messages=4)
        rows = concat_batches(list(streamed.parts()))
    except TfToolsError as e:
        assert "\n" not in str(e), str(e)
        return
    whole = read_recording([path]).transforms
    assert row_keys(rows) <= row_keys(whole)


def row_keys(rows: TransformBatch) -> Counter[tuple[int, bytes]]:
    """Each row as its stamp and translation's bytes (NaN equal to NaN), counted."""
    return Counter(zip(rows.stamp.tolist(), (t.tobytes() for t in rows.translation), strict=True))


@pytest.mark.parametrize("kind", KINDS)
def test_mutated_bags_streamed(kind: str, tmp_path_factory: pytest.TempPathFactory) -> None:
    suffix, data = seed(kind)
    where = tmp_path_factory.mktemp("stream_fuzz")

    @FUZZ
    @given(mutations(len(data)))
    def check(ops: list[tuple[str, int, int]]) -> None:
        path = where / f"bag{suffix}"
        path.write_bytes(mutated(data, ops))
        stream_anything(path)

    check()
