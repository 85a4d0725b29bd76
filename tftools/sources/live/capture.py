"""Listening to a live system: for a while into a ``Recording``, or for ever into a ``Buffer``."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

import numpy as np

from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.semantics import Semantics
from tftools.sources.codecs.types import TF_MESSAGE
from tftools.sources.contents import RecordingContents, SourceInfo
from tftools.sources.live.base import LiveSource
from tftools.sources.live.time_jump import OnJump, TimeJump, watch_jumps
from tftools.sources.recording import Recording, recording_of


def capture(
    source: LiveSource,
    duration: float = 5.0,
    *,
    until: Callable[[], bool] | None = None,
    semantics: Semantics | None = None,
    on_jump: OnJump | None = None,
) -> Recording:
    """Listen ``duration`` wall seconds to ``source`` (not yet started; closed on return) as view_frames
    does, or until ``until()`` (asked ten times a second), and return what was heard as a recording
    whose record times are receive times on the source's clock. When that clock jumps back (a replay
    that loops), what was heard is forgotten but for static transforms, as a tf2 listener clears its
    buffer, and the recording spans from the jump; ``on_jump`` is told of each."""
    heard = _Heard(on_jump)
    with source:
        source.start(watch_jumps(source, heard.keep, heard.forget_dynamic))
        heard.since(source.clock.now())
        deadline = time.monotonic() + duration
        while time.monotonic() < deadline and not source.finished and not (until is not None and until()):
            time.sleep(min(0.1, max(0.0, deadline - time.monotonic())))
        end = source.clock.now()
    transforms, begin = heard.transforms()
    return _recording(source, transforms, begin, end, semantics)


class _Heard:
    """The batches a capture heard, from the source's thread: a jump back of the clock forgets the
    dynamic transforms heard before it (static ones kept), as ``Buffer.clear`` does a buffer."""

    def __init__(self, on_jump: OnJump | None) -> None:
        self._on_jump = on_jump
        self._lock = threading.Lock()
        self._batches: list[TransformBatch] = []
        self._begin = 0

    def since(self, begin: int) -> None:
        with self._lock:
            self._begin = begin

    def keep(self, batch: TransformBatch) -> None:
        with self._lock:
            self._batches.append(batch)

    def forget_dynamic(self, jump: TimeJump) -> None:
        with self._lock:
            statics = [take_rows(b, np.flatnonzero(b.static)) for b in self._batches]
            self._batches = [b for b in statics if len(b)]
            self._begin = jump.after
        if self._on_jump is not None:
            self._on_jump(jump)

    def transforms(self) -> tuple[TransformBatch, int]:
        """All heard (still remembered), and when the hearing began (or the last jump back)."""
        with self._lock:
            return concat_batches(self._batches), self._begin


def _recording(
    source: LiveSource, transforms: TransformBatch, begin: int, end: int, semantics: Semantics | None
) -> Recording:
    if len(transforms):  # a sim clock reads 0 until its first /clock: span what was heard too
        first = int(transforms.record_time.min())
        begin = min(begin, first) if begin > 0 else first
        end = max(end, int(transforms.record_time.max()))
    info = SourceInfo(
        path=source.describe(),
        format=source.format,
        start=begin,
        end=end,
        message_count=source.message_count,
        topics=dict.fromkeys(source.topics, TF_MESSAGE),
        transform_count=len(transforms),
    )
    contents = RecordingContents([transforms] if len(transforms) else [], [info], tuple(source.topics))
    return recording_of(contents, semantics, record_step=source.clock_step)


def live_semantics(source: LiveSource) -> Semantics:
    """The tf2 a listener of ``source`` has: ROS 1's on a ROS 1 system, ROS 2's on a ROS 2 one."""
    return "ros1" if source.format.startswith("ros1") else "ros2"


def listen(
    source: LiveSource, cache_time: int | None = DEFAULT_CACHE_TIME, semantics: Semantics | None = None
) -> Buffer:
    """Start ``source`` into a new buffer (tf2's cache length by default) on the source's clock, filled
    in the background and cleared when the clock jumps back, as a ``tf2_ros::TransformListener``
    does its buffer. Close the source to stop."""
    buffer = Buffer(cache_time, source.clock, semantics or live_semantics(source))
    deliver = watch_jumps(source, buffer.insert, lambda _jump: buffer.clear())

    def insert(batch: TransformBatch) -> None:
        with buffer.lock:  # a lookup sees the buffer before a jump's clearing or after the batch that follows it
            deliver(batch)

    source.start(insert)
    return buffer
