"""A live source keeps at most ``MAX_LIVE_FRAMES`` frames, each at most ``MAX_FRAME_ID`` characters long:
a peer sending megabyte names gets its transforms dropped with one notice, not gigabytes held."""

from __future__ import annotations

from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.sources.codecs.wire import MAX_FRAME_ID
from tftools.sources.live.base import FrameLimit


def batch(*edges: tuple[str, str]) -> TransformBatch:
    builder = BatchBuilder()
    for parent, child in edges:
        builder.add(parent, child, 1, (0, 0, 0), (0, 0, 0, 1), record_time=1, authority="/p")
    return builder.take()


def test_a_name_past_the_limit_drops_its_rows_and_is_said_once() -> None:
    notices: list[str] = []
    limit = FrameLimit(100, notices.append)
    huge = "x" * (1 << 20)
    kept = limit.admit(batch(("odom", "base_link"), ("odom", huge), (huge, "laser")))
    assert [(kept.frame_names[p], kept.frame_names[c]) for p, c in zip(kept.parent, kept.child, strict=True)] == [
        ("odom", "base_link")
    ]
    assert huge not in limit.names
    assert notices == [f"frame names longer than {MAX_FRAME_ID:,} characters heard: transforms naming them are dropped"]


def test_a_name_at_the_limit_is_a_name() -> None:
    limit = FrameLimit(100, lambda _: None)
    longest = "y" * MAX_FRAME_ID
    assert len(limit.admit(batch(("odom", longest)))) == 1 and longest in limit.names


def test_the_count_limit_still_holds_beside_it() -> None:
    notices: list[str] = []
    limit = FrameLimit(3, notices.append)
    kept = limit.admit(batch(("a", "b"), ("b", "c"), ("c", "d"), ("a", "z" * (MAX_FRAME_ID + 1))))
    assert len(kept) == 2 and len(notices) == 2  # a -> b and b -> c: d is past the count, z.. past the length
