"""ROS 1 mode against ROS 1's tf2 in C++ (Debian's libtf2), which keeps every nanosecond of a stamp.

tf2_py (``tests/oracle/tf2_harness.py``) rounds each stamp through a double, so near 1.7e9 s it
moves stamps by up to ~120 ns: an extrapolation's duration then differs from C++ tf2's (a roscpp
node's) by a nanosecond or more. tf2 subtracts ``ros::Time``s as integers and prints the
``ros::Duration`` with ``%.09f`` of its ``toSec()``; so does tftools.
"""

from __future__ import annotations

import math
import random
import re

import pytest

from tests.oracle import run_cpp_core
from tftools.core import Buffer, Transform, TransformError

S = 1_000_000_000


pytestmark = pytest.mark.usefixtures("tf2_cpp")


def _answers(rows: list[tuple[str, str, int]], queries: list[tuple[str, str, int]]) -> tuple[list[str], list[str]]:
    """tf2's and tftools' answers: ``rows`` (parent, child, stamp) inserted, then each lookup."""
    lines = [f"set {p} {c} {stamp} 0 0 0 0 0 0 1 0 x" for p, c, stamp in rows]
    lines += [f"lookup {target} {source} {time}" for target, source, time in queries]
    theirs = [line for line in run_cpp_core(lines)[0] if line not in ("0", "1")]
    buffer = Buffer()
    for p, c, stamp in rows:
        buffer.set_transform(Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, p, c), "x")
    ours = []
    for target, source, time in queries:
        try:
            found = buffer.lookup(target, source, time)
            ours.append(f"T {found.stamp}")
        except TransformError as e:
            ours.append(f"E {type(e).__name__} {e}")
    theirs = [f"T {line.split()[1]}" if line.startswith("T ") else line for line in theirs]
    theirs = [line.replace("E ExtrapolationException", "E ExtrapolationError") for line in theirs]
    return theirs, ours


def test_extrapolation_duration_to_the_nanosecond() -> None:
    """Issue 29's case: data ending at 1700000007.990000009 (printed ...010), a request at
    1700000020: tf2 says 12.009999991s (tf2_py, having moved the stamp to ...010, 12.009999990s)."""
    for last, amount in (
        (990_000_009, "12.009999991s"),
        (990_000_010, "12.009999990s"),
        (990_000_011, "12.009999989s"),
    ):
        rows = [("a", "b", 1_700_000_007 * S + 980_000_000), ("a", "b", 1_700_000_007 * S + last)]
        theirs, ours = _answers(rows, [("a", "b", 1_700_000_020 * S)])
        assert ours == theirs
        assert f"extrapolation {amount} into the future" in ours[0]
        assert "latest data is at time 1700000007.990000010," in ours[0]


def test_extrapolation_messages_off_the_binding_grid() -> None:
    """Random stamps near 1.7e9 s at any nanosecond: every message identical to C++ tf2's."""
    rng = random.Random(29)
    rows, queries = [], []
    for k in range(40):
        parent, child = f"p{k}", f"c{k}"
        first = 1_700_000_000 * S + rng.randrange(10 * S)
        for stamp in sorted({first, first + rng.randrange(1, 3 * S)}):
            rows.append((parent, child, stamp))
        for _ in range(5):
            queries.append((parent, child, first + rng.randrange(-5 * S, 8 * S)))
    theirs, ours = _answers(rows, queries)
    assert sum(line.startswith("E ") for line in theirs) > 100
    assert ours == theirs


def test_refusal_logs_as_tf2_writes_them() -> None:
    """A NaN, a zero and an infinite rotation: the same codes and lines as tf2's log (an infinite
    rotation fails only the norm check: tf2 looks for NaNs)."""
    rotations = [(math.nan, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 0.0), (math.inf, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.02)]
    lines = [f"set a b {S} 0.5 0 0 {' '.join(map(repr, q))} 0 me" for q in rotations]
    _, log = run_cpp_core(lines)
    theirs = re.findall(r"TF_[A-Z_]+: [^\n]*", log)
    buffer = Buffer()
    for q in rotations:
        assert not buffer.set_transform(Transform((0.5, 0.0, 0.0), q, S, "a", "b"), "me")
    assert [r.message for r in buffer.rejections] == theirs
    assert len(theirs) == 5
