"""A message recorded decades from the rest of its file (a recorder's clock reset, damaged bytes): copies of real
recordings of each format with one /tf message's record time moved (made in tmp_path, never in the corpus). The
message is left out and said in one line; the rest is read as in the recording, its span too."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from tests.sources.bag.damaged import copied, record_time_moved
from tests.sources.bag.reading import read_contents
from tftools.core.time import NS_PER_S
from tftools.sources.bag.apart import APART, kept_span
from tftools.sources.stream import stream_recording

YEARS_50 = 50 * 365 * 86_400 * NS_PER_S


def test_the_span_kept_is_the_most_numerous_run_of_record_times() -> None:
    day = 86_400 * NS_PER_S
    run = 1_700_000_000 * NS_PER_S + np.arange(1000, dtype=np.int64) * day // 100  # 10 days of them
    assert kept_span(run) is None
    assert kept_span(np.append(run, run[-1] + APART)) is None  # a year on: still the recording's
    for stray in (run[-1] + APART + 1, -NS_PER_S, 2**63 - 1, -(2**63), run[0] - YEARS_50):
        assert kept_span(np.insert(run, 500, stray)) == (run[0], run[-1])
    assert kept_span(np.array([5, 5 + APART + 1], np.int64)) == (5, 5)  # one each: the first
    assert kept_span(np.zeros(0, np.int64)) is None


#: A real recording of each format, the file in it changed, and where its middle /tf message is moved to.
MOVED: dict[str, tuple[str, Callable[[int], int], str]] = {
    "db3, 50 years on": ("ros2_db3_tb3_gazebo_walker", lambda t: t + YEARS_50, "50.0 years after"),
    "db3, a second before 1970": ("ros2_db3_tb3_gazebo_walker", lambda t: -NS_PER_S, "52.9 years before"),
    "mcap, the last int64": ("ros2_mcap_nav2_turtlebot4.mcap", lambda t: 2**63 - 1, "years or more after"),
    # an MCAP time is a u64: past the last int64, once read as a time before 1970 ("-1 ns, 56.3 years before")
    "mcap, 2**63": ("ros2_mcap_nav2_turtlebot4.mcap", lambda t: 2**63, "or later: 2262 on"),
    "mcap, the last u64": ("ros2_mcap_nav2_turtlebot4.mcap", lambda t: 2**64 - 1, "235.9 years or more after"),
    "ros1, its last second": ("ros1_neato_square_dance.bag", lambda t: 0xFFFFFFFF * NS_PER_S, "years after"),
}


@pytest.mark.parametrize("case", list(MOVED))
def test_a_message_recorded_decades_from_the_rest_is_left_out_and_said(case: str, tmp_path: Path) -> None:
    """Before, the recording spanned the decades (wtf: '1576800013.7 s recorded', edges 'silent for the last
    1576799987 s'; static --repair repeated its statics every 10 s of them, without end)."""
    name, to, said = MOVED[case]
    bag = copied(name, tmp_path)
    changed = next(p for p in sorted(bag.iterdir()) if p.suffix in (".db3", ".mcap")) if bag.is_dir() else bag
    original = read_contents([bag])
    moved = record_time_moved(changed, to)
    read = read_contents([bag])
    (problem,) = read.problems
    held = min(to(moved), 2**63 - 1)  # a time past the last int64 held as it, said as later
    assert re.match(
        rf"1 message recorded [\d.,]+ years (or more )?(before|after) the rest \(record time {held} ns", problem
    )
    assert said in problem and "left out as damaged" in problem
    (info,), (was,) = read.files, original.files
    # its span the recording's; the ends of a topic not read (a .db3's /scan) were the stray's, now those read
    assert was.start <= info.start < info.end <= was.end and info.start - was.start + was.end - info.end < NS_PER_S
    times = np.concatenate([p.record_time for p in read.parts])
    assert times.min() >= was.start and times.max() <= was.end
    lost = sum(len(p) for p in original.parts) - sum(len(p) for p in read.parts)
    assert 1 <= lost <= 20 and info.transform_count == was.transform_count - lost
    # every count said is of what was read: the message left out is counted neither among the file's nor its topic's
    # (before, a command said N messages of /tf while N - 1 were used)
    assert info.message_count == was.message_count - 1
    assert info.tf_messages == {**was.tf_messages, "/tf": (was.tf_messages["/tf"][0] - 1, was.tf_messages["/tf"][1])}
    assert info.tf_empty_from == was.tf_empty_from


@pytest.mark.parametrize("case", [c for c in MOVED if "past" not in c and "u64" not in c])
def test_a_replay_read_window_by_window_leaves_the_message_out_as_a_whole_read_does(case: str, tmp_path: Path) -> None:
    """A replay's windows each hold too few of a file's times to judge: before, none was left out, and a
    replay (tfx monitor --play) of the MCAP whose middle /tf message was recorded in 2262 played on past its
    last message, for the 240 years between (killed after 60 s), said nothing. The windows' times, gathered as
    a few runs, find the stray as a whole read does: its description, counts and line are the whole read's."""
    name, to, _ = MOVED[case]
    bag = copied(name, tmp_path)
    changed = next(p for p in sorted(bag.iterdir()) if p.suffix in (".db3", ".mcap")) if bag.is_dir() else bag
    record_time_moved(changed, to)
    whole = read_contents([bag])
    with stream_recording([bag], window_messages=300) as streamed:
        assert len(streamed.windows) > 3
        (info,), (was,) = streamed.contents.files, whole.files
        assert (info.start, info.end, info.message_count, info.problems) == (
            was.start,
            was.end,
            was.message_count,
            was.problems,
        )
        played = [p for p in streamed.parts()]
        assert sum(len(p) for p in played) == sum(len(p) for p in whole.parts) == info.transform_count
