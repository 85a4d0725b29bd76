"""The seam between the buffer and its compiled core: the refusal log, the duplicates and the lock are
the core's, seen from Python as views and a bound lock; the codes Python reads are the core's."""

from __future__ import annotations

import pickle
import signal
import threading
import time

import numpy as np
import pytest

from tftools.core import _kernels
from tftools.core.buffer import Buffer
from tftools.core.errors import TransformError
from tftools.core.frames import NO_PARENT
from tftools.core.rejection import LIVE_REJECTIONS_KEPT, RejectionCode
from tftools.core.transform import Transform

S = 1_000_000_000


def _refusing(buffer: Buffer, n: int, first: int = 0) -> None:
    """``n`` samples of a to b at one stamp, each after the first refused (ROS 1) or a duplicate (ROS 2)."""
    for k in range(first, first + n):
        buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"), f"node{k % 3}")


# --- the refusal log and the duplicates: the core's columns ----------------------------------


def test_the_refusal_log_reads_the_cores_columns_as_read_only_views() -> None:
    buffer = Buffer(cache_time=None)
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "/a", "b"), "one")
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "/a", "b"), "two")  # repeated
    buffer.set_transform(Transform((2.0, 0, 0), (0, 0, 0, 2), S, "x", "/y"), "two", static=True)  # denormalized
    code, parent, child, stamp, authority, record_time, sequence, values, flags = buffer._core.refusals()
    for column in (code, parent, child, stamp, authority, record_time, sequence, values, flags):
        assert not column.flags.writeable and not column.flags.owndata
    assert [_kernels.REFUSALS[c] for c in code.tolist()] == ["REPEATED_DATA", "DENORMALIZED_QUATERNION"]
    names = buffer._core.refused_frame_names()
    assert [(names[p], names[c]) for p, c in zip(parent.tolist(), child.tolist(), strict=True)] == [
        ("a", "b"),
        ("x", "y"),
    ]  # as tf2 names them, the slash kept in the flags
    assert sequence.tolist() == [1, 2] and values[1].tolist() == [2.0, 0, 0, 0, 0, 0, 2.0]
    assert [buffer.authorities[a] for a in authority.tolist()] == ["two", "two"]
    assert flags.tolist() == [
        _kernels.PARENT_HAD_SLASH,
        _kernels.FROM_STATIC_TOPIC | _kernels.CHILD_HAD_SLASH,
    ]
    assert not buffer.has_frame("x")  # a refused sample's frames are not the buffer's
    first, second = buffer.rejections
    assert (first.code, first.frame_id, first.authority) == (RejectionCode.REPEATED_DATA, "a", "two")
    assert (second.code, second.child_frame_id, second.values) == (
        RejectionCode.DENORMALIZED_QUATERNION,
        "y",
        (0.0, 0.0, 0.0, 2.0),
    )
    rows, arrivals = buffer.rejections.rows()  # as sent: the slashes and the static topic back
    assert arrivals.tolist() == [1, 2] and rows.frame_names[rows.parent[0]] == "/a"
    assert rows.frame_names[rows.child[1]] == "/y" and rows.static.tolist() == [False, True]


def test_a_view_of_the_log_keeps_its_rows_while_the_log_grows_and_forgets() -> None:
    buffer = Buffer(semantics="ros1")  # live: keeps about the latest LIVE_REJECTIONS_KEPT
    _refusing(buffer, 100)
    before = buffer._core.refusals()[6]
    sequences = before.tolist()
    _refusing(buffer, 3 * LIVE_REJECTIONS_KEPT, first=100)
    assert before.tolist() == sequences == list(range(1, 100))  # the old view still shows its rows
    kept = buffer._core.refusals()[6]
    assert len(kept) <= 2 * LIVE_REJECTIONS_KEPT and kept[-1] == buffer.arrivals - 1
    assert buffer.rejections.total == buffer.arrivals - 1 > len(buffer.rejections) == len(kept)


def test_duplicates_are_the_cores_arrival_numbers_viewed() -> None:
    buffer = Buffer(cache_time=None, semantics="ros2")
    _refusing(buffer, 5)
    duplicates = buffer.duplicates
    assert duplicates.dtype == np.int64 and not duplicates.flags.writeable
    assert duplicates.tolist() == [1, 2, 3, 4] and not buffer.rejections
    _refusing(buffer, 2, first=5)
    assert duplicates.tolist() == [1, 2, 3, 4] and buffer.duplicates.tolist() == [1, 2, 3, 4, 5, 6]


def test_a_copy_has_the_refusal_log_and_the_duplicates() -> None:
    ros1, ros2 = Buffer(cache_time=None), Buffer(cache_time=None, semantics="ros2")
    for buffer in (ros1, ros2):
        _refusing(buffer, 4)
        buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 2), S, "a", "c"), "bad")  # refused
        state = buffer.__getstate__()  # what pickle and copy take (the clock holds a lock: copied apart)
        state["_core"] = pickle.loads(pickle.dumps(state["_core"]))  # plain values
        copy = Buffer.__new__(Buffer)
        copy.__setstate__(state)
        assert list(copy.rejections) == list(buffer.rejections) and copy.rejections.total == buffer.rejections.total
        assert copy.duplicates.tolist() == buffer.duplicates.tolist()
        _refusing(copy, 1, first=10)  # the copy's log is its own
        assert len(copy.rejections) + len(copy.duplicates) == len(buffer.rejections) + len(buffer.duplicates) + 1


# --- the codes: the core's, exported ---------------------------------------------------------


def test_every_code_python_reads_is_the_cores() -> None:
    assert {RejectionCode[name] for name in _kernels.REFUSALS} == set(RejectionCode)
    assert Buffer()._core.frame_names()[NO_PARENT] == "NO_PARENT"  # the core's reserved id
    flags = (_kernels.FROM_STATIC_TOPIC, _kernels.PARENT_HAD_SLASH, _kernels.CHILD_HAD_SLASH)
    assert sorted(flags) == [1, 2, 4]  # distinct bits, as a history's flags combine them


# --- the lock and its waiters: the core's -----------------------------------------------------


def test_the_lock_is_the_cores_and_reentrant() -> None:
    buffer = Buffer()
    lock = buffer.lock
    assert isinstance(lock, _kernels.BufferLock) and lock is buffer._core.lock
    with pytest.raises(RuntimeError, match="un-acquired"):
        lock.release()
    with pytest.raises(RuntimeError, match="un-acquired"):
        lock.wait(0.0)
    with lock, lock:  # reentrant: a locked method called with the lock held
        assert lock.owned()
        buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"))
        assert buffer.parent("b") == "a"
    assert not lock.owned()


def test_an_insertion_from_another_thread_waits_for_the_lock_and_wakes_the_waiters() -> None:
    buffer = Buffer()
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"))
    inserted = threading.Event()

    def insert() -> None:
        buffer.set_transform(Transform((2.0, 0, 0), (0, 0, 0, 1), 2 * S, "a", "b"))
        inserted.set()

    with buffer.lock:
        thread = threading.Thread(target=insert)
        thread.start()
        assert not inserted.wait(0.2)  # held here: the other thread's insertion waits (the GIL let go)
        assert buffer.history("b") is not None and len(buffer.history("b") or ()) == 1
        notified = buffer.lock.wait(30.0)  # let go: the insertion comes and wakes this wait
        assert notified and inserted.is_set()
    thread.join()
    assert buffer.lookup("a", "b", 2 * S).translation == (2.0, 0.0, 0.0)


def test_threads_that_let_go_of_the_gil_inside_the_lock_hold_it_one_at_a_time() -> None:
    # Each thread sleeps holding the lock (the GIL let go): the others block in the core, not in the GIL,
    # and are woken as it is let go; inserting between holds takes its fast path.
    buffer = Buffer(cache_time=None)
    inside: list[int] = []
    overlaps: list[list[int]] = []

    def hold(who: int) -> None:
        for k in range(40):
            with buffer.lock:
                inside.append(who)
                time.sleep(0.0002)
                if inside != [who]:
                    overlaps.append(list(inside))
                inside.remove(who)
            buffer.set_transform(Transform((float(k), 0, 0), (0, 0, 0, 1), (who * 100 + k + 1) * S, "a", f"b{who}"))

    threads = [threading.Thread(target=hold, args=(who,)) for who in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert overlaps == [] and inside == []
    assert [len(buffer.history(f"b{who}") or ()) for who in range(4)] == [40] * 4
    assert not buffer.lock.owned()
    with buffer.lock:  # free again, and this thread's
        assert buffer.lock.owned()


def test_wait_for_transform_is_answered_by_an_insertion_from_another_thread() -> None:
    buffer = Buffer()
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"))
    timer = threading.Timer(0.05, lambda: buffer.set_transform(Transform((3.0, 0, 0), (0, 0, 0, 1), 3 * S, "a", "b")))
    timer.start()
    found = buffer.wait_for_transform("a", "b", 3 * S, timeout_s=30.0)
    timer.join()
    assert found.translation == (3.0, 0.0, 0.0)
    with pytest.raises(TransformError):
        buffer.wait_for_transform("a", "b", 4 * S, timeout_s=0.01)


def test_a_signal_interrupts_a_wait_which_leaves_the_lock_held() -> None:
    buffer = Buffer()

    def interrupt(signum: int, frame: object) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    try:
        with buffer.lock:
            signal.setitimer(signal.ITIMER_REAL, 0.05)
            with pytest.raises(KeyboardInterrupt):
                buffer.lock.wait(60.0)
            assert buffer.lock.owned()  # held again, as threading.Condition.wait leaves it
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert not buffer.lock.owned()


# --- the lookup's answer: built by the binding through the type's own fields ------------------


def test_a_lookups_answer_is_the_transform_its_init_would_build() -> None:
    buffer = Buffer()
    buffer.set_transform(Transform((1.0, 2.0, 3.0), (0, 0, 0.6, 0.8), S, "a", "b"))
    found = buffer.lookup("a", "b", S)
    built = Transform((1.0, 2.0, 3.0), (0.0, 0.0, 0.6, 0.8), S, "a", "b")
    assert type(found) is Transform and found == built and hash(found) == hash(built) and repr(found) == repr(built)
    with pytest.raises(AttributeError):
        found.stamp = 0  # type: ignore[misc]  # the refused write is the test
    assert pickle.loads(pickle.dumps(found)) == built


def test_the_core_refuses_an_answer_type_without_field_descriptors() -> None:
    class Plain:
        translation = rotation = stamp = frame_id = child_frame_id = None

    with pytest.raises(TypeError, match="descriptors"):
        _kernels.BufferCore(Plain, None, False, 1e-2, 0)  # type: ignore[arg-type]  # the wrong call is the test
