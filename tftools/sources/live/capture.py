"""Listening to a live system: for a while into a ``Recording``, or for ever into a ``Buffer`` (and waiting
for a transform in it)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.errors import TransformError
from tftools.core.semantics import Semantics
from tftools.sources.codecs.types import TF_MESSAGE
from tftools.sources.contents import RecordingContents, SourceInfo
from tftools.sources.live.base import LiveSource
from tftools.sources.live.errors import TransformNotHeardError
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
    heard = Heard(on_jump)
    with source:
        source.start(watch_jumps(source, heard.keep, heard.forget_dynamic))
        heard.since(source.clock.now())
        deadline = time.monotonic() + duration
        while time.monotonic() < deadline and not source.finished and not (until is not None and until()):
            time.sleep(min(0.1, max(0.0, deadline - time.monotonic())))
        end = source.clock.now()
    transforms, begin = heard.transforms()
    return heard_recording(source, transforms, begin, end, semantics)


class Heard:
    """The batches a capture (or a watch's window) heard, from the source's thread: a jump back of the
    clock forgets the dynamic transforms heard before it (static ones kept), as ``Buffer.clear`` does a
    buffer."""

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


def heard_recording(
    source: LiveSource, transforms: TransformBatch, begin: int, end: int, semantics: Semantics | None = None
) -> Recording:
    """``transforms`` heard from ``source`` between ``begin`` and ``end`` (its clock, ns) as a recording."""
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


#: Wall seconds between two reminders of ``wait_for_transform``.
REMIND_EVERY = 5.0


@dataclass(frozen=True)
class Waiting:
    """What ``wait_for_transform`` tells its ``on_reminder`` every few seconds: why the transform is not
    there yet (tf2's reason, its first line), after how long, and the frames heard so far."""

    waited: float  # wall seconds
    reason: str
    frames: list[str]


def wait_for_transform(
    buffer: Buffer,
    target: str,
    source: str,
    timeout: float | None = None,
    on_reminder: Callable[[Waiting], object] | None = None,
    remind_every: float = REMIND_EVERY,
) -> None:
    """Block until the latest ``target`` <- ``source`` can be looked up in ``buffer`` (one ``listen`` fills),
    telling ``on_reminder`` every ``remind_every`` wall seconds why it is not there yet; after ``timeout``
    seconds (None: never), ``TransformNotHeardError``."""
    started = time.monotonic()
    while True:
        patience = remind_every if timeout is None else min(remind_every, started + timeout - time.monotonic())
        try:
            buffer.wait_for_transform(target, source, 0, max(patience, 0.0))
            return
        except TransformError as error:
            reason = str(error).strip().split("\n")[0]
            waited = time.monotonic() - started
            if timeout is not None and waited >= timeout:
                raise TransformNotHeardError(target, source, waited, reason) from None
            if on_reminder is not None:
                on_reminder(Waiting(waited, reason, list(buffer.frames)))
