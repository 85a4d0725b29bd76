"""A live source keeps at most ``MAX_LIVE_FRAMES`` frames, each at most ``MAX_FRAME_ID`` characters long:
a peer sending megabyte names gets its transforms dropped with one notice, not gigabytes held."""

from __future__ import annotations

from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.sources.codecs.wire import MAX_FRAME_ID
from tftools.sources.live.base import FrameLimit
from tftools.sources.live.notices import NoticeOnce


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


def test_the_characters_of_names_are_bounded_in_all_and_said_once() -> None:
    """Issue 44: 20,000 new names of 4 KiB, each a name, held 1.2 GB in tfx wtf --ros2 (96 s)."""
    notices: list[str] = []
    limit = FrameLimit(20_000, NoticeOnce(notices.append), chars=10 * MAX_FRAME_ID)  # as a live source says them
    names = [f"{i}_".ljust(MAX_FRAME_ID, "n") for i in range(30)]
    kept = [limit.admit(batch(*(("root", n) for n in names[k : k + 10]))) for k in range(0, 30, 10)]
    assert [len(k) for k in kept] == [9, 0, 0]  # "root" and 9 names fill the 10 names' worth
    assert len(limit.names) == 10 and sum(map(len, limit.names)) <= 10 * MAX_FRAME_ID
    assert notices == [
        f"frame names of more than {10 * MAX_FRAME_ID:,} characters in all heard: transforms naming further frames"
        " are dropped (a publisher inventing long frame names?)"
    ]


def test_rows_kept_hold_only_the_names_they_use() -> None:
    """The names of the rows dropped (a megabyte each) do not stay in the kept rows' table."""
    limit = FrameLimit(100, lambda _: None)
    huge = "x" * (1 << 20)
    kept = limit.admit(batch(("odom", "base_link"), ("odom", huge), ("base_link", "laser")))
    assert sorted(kept.frame_names) == ["base_link", "laser", "odom"]
    pairs = [(kept.frame_names[p], kept.frame_names[c]) for p, c in zip(kept.parent, kept.child, strict=True)]
    assert pairs == [("odom", "base_link"), ("base_link", "laser")]
