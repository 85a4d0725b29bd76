"""A live peer inventing frame names (issue 32, M3): the frames passed on are bounded, said once."""

from __future__ import annotations

import itertools

import pytest

from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.sources.live import base


def _chain(names: list[str], stamp: int = 1) -> TransformBatch:
    builder = BatchBuilder()
    for parent, child in itertools.pairwise(names):
        builder.add(parent, child, stamp, (0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    return builder.take()


class _Source(base.LiveSource):
    format = "test"

    def __init__(self) -> None:
        self.notices: list[str] = []
        super().__init__(None, False, self.notices.append)


def test_frames_past_the_limit_are_dropped_with_one_notice(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(base, "MAX_LIVE_FRAMES", 5)
    source = _Source()
    passed: list[TransformBatch] = []
    source._pass_on(passed.append, _chain(["map", "odom", "base_link"]))
    source._pass_on(passed.append, _chain(["base_link", "a", "b", "c", "d"]))
    source._pass_on(passed.append, _chain(["base_link", "e", "f"]))
    source._pass_on(passed.append, _chain(["map", "odom", "base_link", "a"], stamp=2))  # known frames still pass
    pairs = [(b.frame_names[p], b.frame_names[c]) for b in passed for p, c in zip(b.parent, b.child, strict=True)]
    assert pairs == [
        ("map", "odom"),
        ("odom", "base_link"),
        ("base_link", "a"),
        ("a", "b"),  # c and d would be frames 6 and 7
        ("map", "odom"),
        ("odom", "base_link"),
        ("base_link", "a"),
    ]
    assert source.notices == [
        "more than 5 frames heard: transforms naming further frames are dropped (a publisher inventing frame names?)"
    ]
