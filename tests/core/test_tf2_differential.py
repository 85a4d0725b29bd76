"""Our Buffer against the real tf2 on random scenarios: same answers, same errors, same text."""

from __future__ import annotations

import itertools
from collections import Counter, defaultdict
from typing import Any

import numpy as np
import pytest

from tests.core import scenarios
from tests.oracle import ERROR_CLASSES, Row, run_tf2
from tftools.core import ExtrapolationError

SEEDS_PER_FEATURE = 3
BASES = (100, 1_700_000_000)  # small times keep nanoseconds exact through tf2's binding


def _cases() -> list[tuple[str, int, frozenset[str], int]]:
    cases = []
    for feature, base in itertools.product(("healthy", *scenarios.FEATURES), BASES):
        features = frozenset() if feature == "healthy" else frozenset({feature})
        for seed in range(SEEDS_PER_FEATURE):
            cases.append((f"{feature}-{base}-{seed}", seed * 7919 + hash(feature) % 1000, features, base))
    for seed in range(6):  # everything at once
        cases.append((f"all-{seed}", 10_000 + seed, frozenset(scenarios.FEATURES) - {"cycle"}, BASES[seed % 2]))
    return cases


CASES = _cases()


@pytest.fixture(scope="module")
def oracle(tf2_available: None) -> dict[str, tuple[scenarios.Built, dict[str, Any]]]:
    built = {name: scenarios.build(seed, features, base) for name, seed, features, base in CASES}
    results = run_tf2([b.scenario for b in built.values()])
    return {name: (b, r) for (name, b), r in zip(built.items(), results, strict=True)}


def assert_same(ours: dict[str, Any], theirs: dict[str, Any], query: Row) -> None:
    where = f"query {query}"
    assert ours["ok"] == theirs["ok"], f"{where}: ours {ours}, tf2 {theirs}"
    if not theirs["ok"]:
        expected = ERROR_CLASSES.get(theirs["error"])
        if expected is not None:  # get_latest_common_time raises tf2's base class
            assert ours["error"] == expected, where
        assert ours["message"] == theirs["message"], where
        return
    for key in ("stamp", "frame_id", "child_frame_id", "can", "text"):
        assert ours.get(key) == theirs.get(key), f"{where}: {key} ours {ours.get(key)!r}, tf2 {theirs.get(key)!r}"
    if "t" in theirs:
        np.testing.assert_allclose(ours["t"], theirs["t"], rtol=0, atol=1e-9, err_msg=where)
        np.testing.assert_allclose(ours["q"], theirs["q"], rtol=0, atol=1e-9, err_msg=where)


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_lookups_match_tf2(oracle: dict[str, tuple[scenarios.Built, dict[str, Any]]], name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_into_buffer(built.scenario)
    for query, theirs in zip(built.scenario.queries, result["answers"], strict=True):
        assert_same(scenarios.answer(buffer, query), theirs, query)


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_rejections_match_tf2(oracle: dict[str, tuple[scenarios.Built, dict[str, Any]]], name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_into_buffer(built.scenario)
    assert Counter(str(r.code) for r in buffer.rejections) == Counter(result["rejections"])


@pytest.mark.parametrize("name", [c[0] for c in CASES if "shuffle" in c[0] or "all" in c[0] or "cache" in c[0]])
def test_one_by_one_insertion_matches_tf2(oracle: dict[str, tuple[scenarios.Built, dict[str, Any]]], name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_one_by_one(built.scenario)
    assert Counter(str(r.code) for r in buffer.rejections) == Counter(result["rejections"])
    for query, theirs in zip(built.scenario.queries, result["answers"], strict=True):
        assert_same(scenarios.answer(buffer, query), theirs, query)


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_lookup_many_matches_tf2(oracle: dict[str, tuple[scenarios.Built, dict[str, Any]]], name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_into_buffer(built.scenario)
    by_pair: dict[tuple[str, str], list[tuple[int, dict[str, Any]]]] = defaultdict(list)
    for query, theirs in zip(built.scenario.queries, result["answers"], strict=True):
        kind, *args = query
        if kind == "lookup" and buffer.has_frame(args[0]) and buffer.has_frame(args[1]):
            by_pair[(args[0], args[1])].append((args[2] * scenarios.S + args[3], theirs))
    assert by_pair, "the scenario asked no lookup between known frames"
    for (target, source), asked in by_pair.items():
        times = np.array([t for t, _ in asked], np.int64)
        got = buffer.lookup_many(target, source, times)
        for i, (_, theirs) in enumerate(asked):
            where = f"lookup_many({target}, {source}) at {times[i]}"
            assert got.valid[i] == theirs["ok"], where
            if theirs["ok"]:
                assert list(divmod(int(got.stamps[i]), scenarios.S)) == theirs["stamp"], where
                np.testing.assert_allclose(got.translations[i], theirs["t"], atol=1e-9, err_msg=where)
                np.testing.assert_allclose(got.rotations[i], theirs["q"], atol=1e-9, err_msg=where)


def test_binding_time_is_what_tf2_stores(tf2_available: None) -> None:
    """Our model of the binding's float rounding, checked on stamps that do get rounded."""
    from tests.oracle import Scenario

    rng = np.random.default_rng(5)
    stamps = [int(s) for s in rng.integers(1_600_000_000 * scenarios.S, 1_800_000_000 * scenarios.S, 200)]
    scenario = Scenario(
        inserts=[
            ["a", f"b{i}", *divmod(s, scenarios.S), 0, 0, 0, 0, 0, 0, 1, "x", False] for i, s in enumerate(stamps)
        ],
        queries=[["lookup", "a", f"b{i}", 0, 0] for i in range(len(stamps))],
    )
    answers = run_tf2([scenario])[0]["answers"]
    from tests.oracle import binding_time

    assert [a["stamp"] for a in answers] == [list(divmod(binding_time(s), scenarios.S)) for s in stamps]
    assert any(binding_time(s) != s for s in stamps), "these stamps should exercise the rounding"


def test_ros1_deviations_match_tf2(tf2_available: None) -> None:
    """A frame's chain to itself is empty; a fixed-frame ``can_transform`` of an unknown, empty or
    '/'-led frame to itself is False; an empty buffer's YAML is ``{}`` (all three once differed)."""
    from tests.oracle import Scenario

    t0 = ["a", "b", 100, 0, 1, 2, 3, 0, 0, 0, 1, "x", False]
    t1 = ["b", "c", 100, 0, 1, 2, 3, 0, 0, 0, 1, "x", False]
    frames = ["a", "b", "c", "ghost", "", "/b"]
    queries = [["can_full", f, 0, 0, f, 0, 0, f] for f in frames]
    queries += [["can_full", "a", 0, 0, "c", 100, 0, f] for f in frames]
    queries += [["chain", f, 0, 0, f, 0, 0, f] for f in ("a", "b", "c")]
    queries += [["chain", "a", 100, 0, "c", 100, 0, "a"], ["chain", "c", 0, 0, "a", 0, 0, "c"], ["yaml"]]
    scenarios_ = [Scenario(inserts=[t0, t1], queries=queries), Scenario(queries=[["yaml"], ["frames"]])]
    results = run_tf2(scenarios_)
    for scenario, result in zip(scenarios_, results, strict=True):
        buffer = scenarios.load_into_buffer(scenario)
        for query, theirs in zip(scenario.queries, result["answers"], strict=True):
            ours = scenarios.answer(buffer, query)
            assert ours == {k: v for k, v in theirs.items() if k in ours}, query
            assert ours.keys() == theirs.keys(), query
    assert results[1]["answers"][0]["text"] == "{}"


def test_messages_print_times_as_tf2_does_through_a_double(tf2_available: None) -> None:
    """tf2 (ROS 1) prints ``%.09f`` of ``toSec()``. Through its binding a stamp is on the double's
    grid, where that is exact, and we match; off the grid (C++ tf2 stores every nanosecond) the
    double shows, as ``cache.cpp`` says: there our message prints it, ``format_sec`` does not."""
    from tests.oracle import Scenario, binding_time
    from tftools.core import Buffer, Transform
    from tftools.core.time import format_sec

    stamp = binding_time(1_700_000_007_990_000_001)
    row = ["a", "b", *divmod(stamp, scenarios.S), 0, 0, 0, 0, 0, 0, 1, "x", False]
    queries = [["lookup", "a", "b", 1_700_000_009, 1], ["lookup", "a", "b", 1_700_000_006, 0]]
    scenario = Scenario(inserts=[row], queries=queries)
    result = run_tf2([scenario])[0]
    buffer = scenarios.load_into_buffer(scenario)
    for query, theirs in zip(queries, result["answers"], strict=True):
        assert_same(scenarios.answer(buffer, query), theirs, query)

    for off_grid in (1_700_000_007_990_000_001, 1_700_000_007_990_000_123):
        buffer = Buffer()
        buffer.set_transform(Transform((0, 0, 0), (0, 0, 0, 1), off_grid, "a", "b"))
        with pytest.raises(ExtrapolationError, match=r"only time 1700000007\.990000010 is in"):
            buffer.lookup("a", "b", 1_700_000_009 * scenarios.S)
        assert format_sec(off_grid) == f"1700000007.990000{off_grid % 1000:03d}"
