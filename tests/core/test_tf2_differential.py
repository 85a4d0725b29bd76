"""Our Buffer against the real tf2 on random scenarios: same answers, same errors, same text."""

from __future__ import annotations

import itertools
from collections import Counter, defaultdict

import numpy as np
import pytest

from tests.core import scenarios
from tests.oracle import ERROR_CLASSES, run_tf2

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
def oracle(tf2_available: None) -> dict[str, tuple[scenarios.Built, dict]]:
    built = {name: scenarios.build(seed, features, base) for name, seed, features, base in CASES}
    results = run_tf2([b.scenario for b in built.values()])
    return {name: (b, r) for (name, b), r in zip(built.items(), results, strict=True)}


def assert_same(ours: dict, theirs: dict, query: list) -> None:
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
def test_lookups_match_tf2(oracle, name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_into_buffer(built.scenario)
    for query, theirs in zip(built.scenario.queries, result["answers"], strict=True):
        assert_same(scenarios.answer(buffer, query), theirs, query)


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_rejections_match_tf2(oracle, name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_into_buffer(built.scenario)
    assert Counter(str(r.code) for r in buffer.rejections) == Counter(result["rejections"])


@pytest.mark.parametrize("name", [c[0] for c in CASES if "shuffle" in c[0] or "all" in c[0] or "cache" in c[0]])
def test_one_by_one_insertion_matches_tf2(oracle, name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_one_by_one(built.scenario)
    assert Counter(str(r.code) for r in buffer.rejections) == Counter(result["rejections"])
    for query, theirs in zip(built.scenario.queries, result["answers"], strict=True):
        assert_same(scenarios.answer(buffer, query), theirs, query)


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_lookup_many_matches_tf2(oracle, name: str) -> None:
    built, result = oracle[name]
    buffer = scenarios.load_into_buffer(built.scenario)
    by_pair: dict[tuple[str, str], list[tuple[int, dict]]] = defaultdict(list)
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


def test_binding_time_is_what_tf2_stores(tf2_available) -> None:
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
