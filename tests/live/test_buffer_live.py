"""A buffer fed from another thread: wait_for_transform, and lookups while insertions go on."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from tftools.core.batch import BatchBuilder
from tftools.core.buffer import Buffer
from tftools.core.errors import ExtrapolationError, UnknownFrameError
from tftools.core.transform import Transform


def test_wait_returns_once_another_thread_inserts() -> None:
    buffer = Buffer()
    answers: list[Transform] = []
    waiter = threading.Thread(target=lambda: answers.append(buffer.wait_for_transform("map", "base", 0, 30.0)))
    waiter.start()
    buffer.set_transform(Transform((1, 2, 3), (0, 0, 0, 1), 10, "map", "base"), "/pub")
    waiter.join(30)
    assert [a.translation for a in answers] == [(1.0, 2.0, 3.0)]


def test_wait_raises_the_lookups_error_when_time_runs_out() -> None:
    buffer = Buffer()
    buffer.set_transform(Transform((1, 0, 0), (0, 0, 0, 1), 10, "map", "base"), "/pub")
    with pytest.raises(UnknownFrameError, match='"laser" passed to lookupTransform argument source_frame'):
        buffer.wait_for_transform("map", "laser", 0, 0.05)
    with pytest.raises(ExtrapolationError, match=r"Lookup would require extrapolation at time 0\.000000020"):
        buffer.wait_for_transform("map", "base", 20, 0.05)


def test_lookups_while_another_thread_inserts() -> None:
    buffer = Buffer(cache_time=2 * 10**9)
    done, looking = threading.Event(), threading.Event()
    errors: list[BaseException] = []

    def publish() -> None:
        try:
            looking.wait(5)  # an insert is quicker than the switch interval: 400 would pass before one lookup
            for i in range(1, 401):
                builder = BatchBuilder()
                stamp = i * 10_000_000
                builder.add("map", "odom", stamp, (i, 0, 0), (0, 0, 0, 1), authority="/a")
                builder.add("odom", "base", stamp, (0, i, 0), (0, 0, 0, 1), authority="/b")
                buffer.insert(builder.take())
                time.sleep(0)  # the lookups' turn
        except BaseException as error:  # reported by the main thread
            errors.append(error)
        finally:
            done.set()

    thread = threading.Thread(target=publish)
    buffer.set_transform(Transform((0, 0, 0), (0, 0, 0, 1), 0, "map", "odom"), "/a")
    buffer.set_transform(Transform((0, 0, 0), (0, 0, 0, 1), 0, "odom", "base"), "/b")
    thread.start()
    seen = 0
    while not done.is_set():
        t = buffer.lookup("map", "base")
        assert t.translation[0] == t.translation[1] == t.stamp / 10_000_000  # both edges at one common time
        many = buffer.lookup_many("map", "base", [0, t.stamp])
        assert many.valid.all()
        seen += 1
        looking.set()
    thread.join()
    assert not errors and seen > 0
    assert buffer.lookup("map", "base").translation == (400.0, 400.0, 0.0)
    history = buffer.history("base")
    assert history is not None and np.all(np.diff(history.stamps) > 0)
