"""The compiled walk's calls against each other: one verdict for a lookup, can_transform, chain
and latest common time; batches with the single lookup's bits. (tf2 itself judges the walk in
test_tf2_differential.py.)"""

from __future__ import annotations

import sys
from collections.abc import Iterator

import numpy as np
import pytest

from tests.core import scenarios
from tftools import Buffer, Transform, TransformError
from tftools.core import kernels, walk
from tftools.core.buffer import LookupBatch
from tftools.core.history import FUTURE, NO_DATA, ONLY_ONE, PAST

S = scenarios.S
CASES = [(seed, frozenset({f}) if f else frozenset()) for seed in range(2) for f in (None, *scenarios.FEATURES)]


def kernel_walk(buffer: Buffer, target: str, source: str, time: int) -> tuple[list[float], int] | None:
    found, _ = buffer._core.lookup(buffer._core.frame_id(target), buffer._core.frame_id(source), time)
    return None if found is None else ([*found[0], *found[1]], found[2])


def lookups(built: scenarios.Built, buffer: Buffer) -> Iterator[tuple[str, str, int]]:
    for kind, *args in built.scenario.queries:
        if kind not in ("lookup", "can"):
            continue
        target, source = args[0], args[1]
        if target != source and buffer.has_frame(target) and buffer.has_frame(source):
            yield target, source, args[2] * S + args[3]


def _case_id(value: object) -> str:
    return "-".join(sorted(value)) or "healthy" if isinstance(value, frozenset) else str(value)


@pytest.mark.parametrize(("seed", "features"), CASES, ids=_case_id)
def test_one_walk_gives_one_verdict(seed: int, features: frozenset[str]) -> None:
    """Where the lookup fails, the walk reports a failure (an extrapolation with a gap of the kind its
    time and stamp tell), and succeeds with the frames from source to target where it succeeds."""
    built = scenarios.build(seed, features, 1_700_000_000)
    buffer = scenarios.load_into_buffer(built.scenario)
    asked, failures = 0, set()
    for target, source, time in lookups(built, buffer):
        ids = buffer._core.frame_id(target), buffer._core.frame_id(source)
        for t in (time, 0):
            found = kernel_walk(buffer, target, source, t)
            frames, failure = buffer._core.chain(*ids, t)
            assert buffer._core.can_transform(*ids, t) == (found is not None), (target, source, t)
            assert (failure[0] == walk.NO_FAILURE) == (found is not None), (target, source, t)
            assert buffer._core.lookup(*ids, t)[1] == failure, "the lookup's own walk says why it fails"
            answered = buffer._core.lookup_frames(target, source, t)
            assert (answered is None) == (found is None)
            # A failed lookup_frames keeps its walk's failure, for the Python path that words it.
            assert buffer._core.last_failure(*ids, t) == (None if found is not None else failure)
            assert buffer._core.last_failure(*ids, t + 1) is None
            if found is not None:
                assert (frames[0], frames[-1]) == (ids[1], ids[0])
            else:
                assert frames == []
                failures.add(failure[0])
                _assert_a_gap_of_its_kind(failure)
            common, common_failure = buffer._core.latest_common_time(*ids)
            if common_failure[0] == walk.NO_FAILURE:
                assert kernel_walk(buffer, target, source, common) == kernel_walk(buffer, target, source, 0)
            else:
                assert found is None or t != 0
                assert common_failure[0] in (walk.LOOP, walk.UNCONNECTED)
            asked += 1
    assert asked > 50
    assert walk.EXTRAPOLATION in failures, "every scenario asks at times outside some history"
    assert (walk.LOOP in failures) == ("cycle" in features)


def _assert_a_gap_of_its_kind(failure: walk.Failure) -> None:
    what, kind, time, stamp = failure
    if what != walk.EXTRAPOLATION:
        assert (kind, time, stamp) == (0, 0, 0)
    elif kind == NO_DATA:
        assert stamp == 0
    elif kind == ONLY_ONE:
        assert stamp != time
    else:
        assert kind in (FUTURE, PAST) and (time > stamp if kind == FUTURE else time < stamp)


def test_the_table_follows_growth_pruning_and_new_frames() -> None:
    buffer = Buffer(cache_time=3 * S)
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"))
    buffer.set_transform(Transform((2.0, 0, 0), (0, 0, 0, 1), 2 * S, "a", "b"))
    assert buffer.lookup("a", "b", S + S // 2).translation[0] == 1.5
    for k in range(3, 200):  # grows, then prunes (moving the arrays) many times
        buffer.set_transform(Transform((float(k), 0, 0), (0, 0, 0, 1), k * S, "a", "b"))
        buffer.set_transform(Transform((0, float(k), 0), (0, 0, 0, 1), k * S, "b", f"c{k}"))
        assert buffer.lookup("a", f"c{k}", k * S).translation == (float(k), float(k), 0.0)
        assert buffer.lookup("a", "b", 0).stamp == k * S
    with pytest.raises(TransformError, match="into the past"):
        buffer.lookup("a", "b", 100 * S)
    assert not buffer.can_transform("a", "b", 100 * S)


def test_a_copied_buffer_gets_its_own_state() -> None:
    """A copied buffer (``__getstate__``, ``__setstate__``) is the same buffer where it is rebuilt:
    its frames, publishers, histories (the ones ROS 2 replaced too), arrivals and rejections; and its own."""
    import pickle

    buffer = Buffer(cache_time=None, semantics="ros2")
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"), "one")
    buffer.set_transform(Transform((1.5, 0, 0), (0, 0, 0, 1), 2 * S, "a", "b"), "two")
    buffer.set_transform(Transform((9.0, 0, 0), (0, 0, 0, 1), S, "a", "b"), "two", static=True)  # replaces
    buffer.set_transform(Transform((float("nan"), 0, 0), (0, 0, 0, 1), S, "a", "d"), "two")  # refused
    state = buffer.__getstate__()  # what pickle and copy take (a buffer's clock holds a lock: copied apart)
    state["_core"] = pickle.loads(pickle.dumps(state["_core"]))  # plain values, no memory addresses
    copy = Buffer.__new__(Buffer)
    copy.__setstate__(state)
    assert copy.frames == buffer.frames and copy.authorities == buffer.authorities
    assert copy.arrivals == buffer.arrivals == 4 and len(copy.rejections) == 1
    assert copy.all_frames_as_yaml() == buffer.all_frames_as_yaml()
    hist, kept = copy.history("b"), buffer.history("b")
    assert hist is not None and kept is not None and kept.replaced is not None
    assert hist.static and hist.replaced is not None and not hist.replaced.static
    for a, b in ((hist, kept), (hist.replaced, kept.replaced)):
        for column in ("stamps", "values", "parents", "authorities", "record_times", "sequence", "flags"):
            assert np.array_equal(getattr(a, column), getattr(b, column)), column
    copy.set_transform(Transform((2.0, 0, 0), (0, 0, 0, 1), S, "a", "c"))
    assert copy.lookup("a", "c").translation == (2.0, 0.0, 0.0)
    assert not buffer.has_frame("c")
    pickled = pickle.loads(pickle.dumps(kept))  # a history alone, the one it replaced with it
    assert pickled.replaced is not None and pickled.values.tolist() == kept.values.tolist()
    assert pickled.replaced.stamps.tolist() == kept.replaced.stamps.tolist() == [S, 2 * S]


def test_a_frame_asked_for_before_it_exists_is_found_once_it_does() -> None:
    """The table remembers the frames it last looked up by name, but not a name it did not know."""
    buffer = Buffer(cache_time=None)
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"))
    late = "c"
    assert not buffer.can_transform("a", late)
    buffer.set_transform(Transform((2.0, 0, 0), (0, 0, 0, 1), S, "a", late))
    assert buffer.can_transform("a", late)
    assert buffer.lookup("a", late).translation == (2.0, 0.0, 0.0)


@pytest.mark.parametrize(("seed", "features"), CASES[::3], ids=_case_id)
def test_lookup_many_answers_as_single_lookups(
    seed: int, features: frozenset[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(kernels, "_TIMES_PER_THREAD", 7)  # several threads even here
    built = scenarios.build(seed, features, 1_700_000_000)
    buffer = scenarios.load_into_buffer(built.scenario)
    pairs = {(target, source) for target, source, _ in lookups(built, buffer)}
    times = [t for *_, t in lookups(built, buffer)] + [0, 0]
    for target, source in sorted(pairs):
        for asked in (np.array(times), np.sort(times)):  # unordered (sorted inside), ordered
            got = buffer.lookup_many(target, source, asked)
            for i, time in enumerate(asked.tolist()):
                expected = kernel_walk(buffer, target, source, time)
                assert got.valid[i] == (expected is not None), (target, source, time)
                if expected is not None:
                    assert got.stamps[i] == expected[1]
                    np.testing.assert_allclose(got.translations[i], expected[0][:3], rtol=0, atol=1e-12)
                    np.testing.assert_allclose(got.rotations[i], expected[0][3:], rtol=0, atol=1e-12)


def test_lookup_many_over_times_spanning_all_int64(monkeypatch: pytest.MonkeyPatch) -> None:
    """Times too far apart for a bucket's sorting key to hold each whole (the buckets are then only
    nearly sorted, each time read back from its row): the same answers as one by one, in their rows."""
    monkeypatch.setattr(kernels, "_TIMES_PER_THREAD", 7)
    buffer = Buffer(cache_time=None)
    for k in range(1, 11):
        angle = 0.3 * k
        rotation = (0.0, 0.0, float(np.sin(angle / 2)), float(np.cos(angle / 2)))
        buffer.set_transform(Transform((float(k), k * k / 7, 0), rotation, k * S, "a", "b"))
    rng = np.random.default_rng(3)
    extremes = [np.iinfo(np.int64).min, np.iinfo(np.int64).max, -S, 0, S, 10 * S]
    times = rng.permutation(np.concatenate([rng.integers(S, 10 * S, 500), extremes]))
    got = buffer.lookup_many("a", "b", times)
    assert got.valid.sum() == 500 + 3  # inside the history, its ends and 0
    for i, time in enumerate(times.tolist()):
        expected = kernel_walk(buffer, "a", "b", time)
        assert got.valid[i] == (expected is not None), time
        assert got.stamps[i] == (time or 10 * S)
        if expected is not None:
            assert [*got.translations[i], *got.rotations[i]] == expected[0]  # the very same bits


def test_a_batch_writes_into_a_kept_answers_memory_only_once_it_is_let_go(monkeypatch: pytest.MonkeyPatch) -> None:
    """Batches of a like size take turns with two kept blocks of memory, never one that an earlier answer (or
    any view of it) still holds, and answer the same bits in them; a copied buffer keeps none of it."""
    monkeypatch.setattr(kernels, "_KEPT_BYTES", (1, 1 << 20))  # small batches kept too
    buffer = Buffer(cache_time=None)
    for k in range(1, 11):
        rotation = (0.0, 0.0, float(np.sin(0.15 * k)), float(np.cos(0.15 * k)))
        buffer.set_transform(Transform((float(k), k * k / 7, 0), rotation, k * S, "a", "b"))
    times = np.random.default_rng(4).integers(0, 12 * S, 1000)
    first = buffer.lookup_many("a", "b", times)
    expected = [first.stamps.copy(), first.translations.copy(), first.rotations.copy(), first.valid.copy()]
    assert 0 < first.valid.sum() < len(times)
    held = buffer.lookup_many("a", "b", times[::-1])  # while `first` is alive: memory of its own
    assert not any(np.shares_memory(a, b) for a in vars(first).values() for b in vars(held).values())
    del held
    translations, one = first.translations, _address(first.translations)
    del first
    second = buffer.lookup_many("a", "b", times)  # `first`'s translations still held: not its memory
    assert not np.shares_memory(translations, second.translations)
    assert _columns_equal(second, expected)
    kept = {one, _address(second.translations)}
    del second, translations
    again = buffer.lookup_many("a", "b", times)
    assert _address(again.translations) in kept  # let go of: written into again, with the same bits
    assert _columns_equal(again, expected)
    del again
    # A loop that rebinds its answer (the last one alive during each call) takes turns with the two blocks.
    addresses = []
    for _ in range(4):
        answer = buffer.lookup_many("a", "b", times)
        addresses.append(_address(answer.translations))
        assert _columns_equal(answer, expected)
    assert set(addresses) == kept and addresses[0] != addresses[1] and addresses[2:] == addresses[:2]
    del answer
    assert _address(buffer.lookup_many("a", "b", times[:100]).translations) not in kept  # a tenth the size
    assert "_batch_outputs" not in buffer.__getstate__()


def _columns_equal(batch: LookupBatch, expected: list[np.ndarray]) -> bool:
    got = (batch.stamps, batch.translations, batch.rotations, batch.valid)
    return all(np.array_equal(a, b) for a, b in zip(got, expected, strict=True))


def _address(array: np.ndarray) -> int:
    return int(array.__array_interface__["data"][0])


def test_an_answer_let_go_is_written_over_and_one_held_never_is() -> None:
    """The last answer, where nothing but the core holds it, is the next lookup's (the same object, its
    tuples and floats written over); an answer, or a tuple or float of one, that anything holds keeps its values."""
    buffer = Buffer(cache_time=None)
    for k in range(1, 11):
        rotation = (0.0, 0.0, float(np.sin(0.15 * k)), float(np.cos(0.15 * k)))
        buffer.set_transform(Transform((float(k), k * k / 7, 0), rotation, k * S, "a", "b"))
        buffer.set_transform(Transform((0.5, 0, float(k)), (0, 0, 0, 1), k * S, "b", "c"))
    times = [S + k * S // 3 for k in range(25)]

    def fields(t: Transform) -> tuple[object, ...]:
        return (t.translation, t.rotation, t.stamp, t.frame_id, t.child_frame_id)

    def fresh(target: str, source: str, time: int) -> tuple[object, ...]:
        copy = Buffer.__new__(Buffer)  # another core: nothing kept
        copy.__setstate__(buffer.__getstate__())
        return fields(copy.lookup(target, source, time))

    expected = {(t, s, time): fresh(t, s, time) for t, s in (("a", "b"), ("a", "c"), ("b", "c")) for time in times}
    first = id(buffer.lookup("a", "c", times[0]))
    filler = [Transform() for _ in range(100)]  # what would take a freed answer's memory
    assert id(buffer.lookup("a", "b", times[1])) == first  # let go of, yet not freed: written over
    del filler
    held = [buffer.lookup("a", "c", time) for time in times]  # each held: new ones
    assert len({id(t) for t in held}) == len(times)
    translation = buffer.lookup("a", "b", times[3]).translation  # its tuple held, not the answer
    x = buffer.lookup("b", "c", times[4]).rotation[2]  # a float of it held
    for (target, source, time), want in expected.items():
        got = buffer.lookup(target, source, time)
        assert fields(got) == want and got == Transform(*want)  # type: ignore[arg-type]
    assert [fields(t) for t in held] == [expected["a", "c", time] for time in times]
    assert translation == expected["a", "b", times[3]][0]
    assert x == expected["b", "c", times[4]][1][2]  # type: ignore[index]


def test_an_answer_takes_the_int_it_was_asked_at_as_its_stamp() -> None:
    """A lookup's stamp is the very int its time was given as (no int made for it, none freed), new or
    written over; a plain int of the same value where the time was another kind of int; for time 0, the
    latest common time."""
    buffer = Buffer(cache_time=None)
    for stamp in (10 * S, 20 * S):
        buffer.set_transform(Transform((stamp / S, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "a", "b"))
    asked = [15 * S + k for k in range(3)]
    held = buffer.lookup("a", "b", asked[0])  # held: the next answer is a new one
    assert held.stamp is asked[0]
    assert buffer.lookup("a", "b", asked[1]).stamp is asked[1]  # let go of: written over
    assert buffer.lookup("a", "b", asked[2]).stamp is asked[2]
    assert held.stamp is asked[0]

    class Time(int):
        pass

    for time in (Time(asked[1]), np.int64(asked[1])):
        stamp = buffer.lookup("a", "b", time).stamp
        assert type(stamp) is int and stamp == asked[1]
    assert buffer.lookup("a", "b", 0).stamp == 20 * S


def test_lookup_and_can_transform_in_c_take_their_arguments_as_python_methods_do() -> None:
    """``Buffer.lookup`` and ``can_transform`` (methods in C, no binding's dispatch) take (target_frame,
    source_frame, time=0), by position or keyword, a time as the binding takes it (an int, or what converts
    to one without loss), and refuse anything else with Python's TypeErrors."""
    buffer = Buffer(cache_time=None)
    for stamp in (10, 20):
        buffer.set_transform(Transform((float(stamp), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "a", "b"))
    assert buffer.lookup("a", "b", np.int64(15)).stamp == 15
    assert buffer.lookup("a", "b", 15) == buffer._core.lookup_frames("a", "b", 15)
    assert buffer.lookup(source_frame="b", target_frame="a", time=15).translation == (15.0, 0.0, 0.0)
    assert buffer.lookup("a", "b").stamp == 20 == buffer.lookup("a", "b", time=0).stamp  # time 0: the latest
    assert buffer.can_transform("a", "b", time=15) and not buffer.can_transform(
        target_frame="a", source_frame="b", time=25
    )
    assert buffer.lookup("b", "b", time=15) == Transform.identity(15, "b", "b")  # answered in Python
    for method in (buffer.lookup, buffer.can_transform):
        for time in (1.5, "15", None):
            with pytest.raises(TypeError, match="time must be an int"):
                method("a", "b", time)  # type: ignore[arg-type]  # the wrong call is the test
        with pytest.raises(TypeError, match="missing required argument 'source_frame'"):
            method("a")  # type: ignore[call-arg]  # the wrong call is the test
        with pytest.raises(TypeError, match="from 2 to 3 positional arguments"):
            method("a", "b", 15, 0)  # type: ignore[call-arg]  # the wrong call is the test
        with pytest.raises(TypeError, match="unexpected keyword argument 'at'"):
            method("a", "b", at=15)  # type: ignore[call-arg]  # the wrong call is the test
        with pytest.raises(TypeError, match="multiple values for argument 'time'"):
            method("a", "b", 15, time=15)  # type: ignore[misc]  # the wrong call is the test
    assert "target_frame, source_frame, time=0" in (Buffer.lookup.__doc__ or "") + str(
        __import__("inspect").signature(Buffer.lookup)
    )


def test_set_transform_in_c_takes_its_arguments_as_a_python_method_does() -> None:
    """``Buffer.set_transform`` (a method in C) takes (transform, authority="", static=False,
    record_time=0), by position or keyword, stores its common case itself and hands every other sample
    to the batch path (which refuses what tf2 refuses), and refuses bad calls with Python's TypeErrors."""
    buffer = Buffer(cache_time=None)

    def sample(stamp: int, child: str = "b") -> Transform:
        return Transform((float(stamp), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "a", child)

    assert buffer.set_transform(sample(10))  # frames unknown: the batch path
    assert buffer.set_transform(sample(20), "pub", record_time=7)  # a new publisher: the batch path
    assert buffer.set_transform(authority="pub", transform=sample(30), static=False, record_time=8)  # in C
    assert buffer.set_transform(sample(40), "pub", False, 9)
    assert buffer.set_transform(sample(50))  # authority "", record time 0 by default
    assert buffer.set_transform(sample(60, "c"), "pub", True)  # static: the batch path
    assert not buffer.set_transform(Transform((float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), 70, "a", "b"))
    history = buffer.history("b")
    assert history is not None and not history.static
    assert history.stamps.tolist() == [10, 20, 30, 40, 50]
    assert history.record_times.tolist() == [0, 7, 8, 9, 0]
    assert [buffer.authorities[k] for k in history.authorities.tolist()] == ["", "pub", "pub", "pub", ""]
    assert buffer.lookup("a", "b", 45).translation == (45.0, 0.0, 0.0)
    static = buffer.history("c")
    assert static is not None and static.static
    with pytest.raises(TypeError, match="missing required argument 'transform'"):
        buffer.set_transform()  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="from 1 to 4 positional arguments"):
        buffer.set_transform(sample(80), "pub", False, 0, 1)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="unexpected keyword argument 'stamp'"):
        buffer.set_transform(sample(80), stamp=80)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match="multiple values for argument 'authority'"):
        buffer.set_transform(sample(80), "pub", authority="pub")  # type: ignore[misc]
    assert "transform, authority='', static=False, record_time=0" in str(
        __import__("inspect").signature(Buffer.set_transform)
    )


def test_methods_in_c_find_the_core_in_buffers_slot_or_as_an_attribute() -> None:
    """The methods in C read a Buffer's core from its slot, and any other object's ``_core`` as an
    attribute, whichever class came last; an object without a core raises AttributeError."""
    buffer = Buffer(cache_time=None)
    for stamp in (10, 20):
        buffer.set_transform(Transform((float(stamp), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "a", "b"))

    class Borrowing:
        lookup = Buffer.lookup
        can_transform = Buffer.can_transform

        def __init__(self, core: object) -> None:
            self._core = core

    other = Borrowing(buffer._core)
    held = sys.getrefcount(Borrowing)
    for _ in range(100):  # the class last seen is held while remembered, and let go when another comes
        assert other.lookup("a", "b", 12).translation == (12.0, 0.0, 0.0)
        assert buffer.lookup("a", "b", 15).translation == (15.0, 0.0, 0.0)
        assert other.can_transform("a", "b", 12) and buffer.can_transform("a", "b", 12)
    assert sys.getrefcount(Borrowing) == held
    Borrowing._core = None  # the class changed: its instances' attribute still wins
    assert other.lookup("a", "b", 12).stamp == 12
    del other._core
    with pytest.raises(TypeError, match="_core must be a BufferCore"):
        other.lookup("a", "b", 12)
    unset = Buffer.__new__(Buffer)
    with pytest.raises(AttributeError, match="_core"):
        unset.lookup("a", "b", 12)
    with pytest.raises(AttributeError, match="_core"):
        unset.set_transform(Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), 30, "a", "b"))
    assert buffer.lookup("a", "b", 15).translation == (15.0, 0.0, 0.0)
