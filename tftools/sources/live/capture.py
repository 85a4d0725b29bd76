"""Listening to a live system: for a while into a ``Recording``, or for ever into a ``Buffer``."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence

from tftools.core.batch import TransformBatch, concat_batches
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.kernels_table import compiled
from tftools.sources.bag.contents import BagContents, BagFileInfo
from tftools.sources.live import open_live
from tftools.sources.live.base import LiveSource
from tftools.sources.recording import Recording, recording_of

TF_TYPE = "tf2_msgs/msg/TFMessage"


def capture(
    source: LiveSource | None = None,
    duration: float = 5.0,
    topics: Sequence[str] | None = None,
    *,
    until: Callable[[], bool] | None = None,
) -> Recording:
    """Listen ``duration`` wall seconds (as view_frames does) and return what was heard as a recording.

    ``source``: a live source not yet started (closed on return); ``None`` opens one as
    ``open_live(topics=topics)`` does. ``until`` may end the capture early (checked ten times a
    second). Its one file entry describes the source (path e.g. ``ROS1 master
    http://127.0.0.1:11311``, format ``ros1-live``); record times are receive times, and the
    recording spans from the start of listening to its end on the source's clock.
    """
    if source is None:
        source = open_live(topics=topics)
    batches: list[TransformBatch] = []
    lock = threading.Lock()

    def keep(batch: TransformBatch) -> None:
        with lock:
            batches.append(batch)

    with source:
        source.start(keep)
        begin = source.clock.now()
        deadline = time.monotonic() + duration
        while time.monotonic() < deadline and not source.finished and not (until is not None and until()):
            time.sleep(min(0.1, max(0.0, deadline - time.monotonic())))
        end = source.clock.now()
    with lock:
        transforms = concat_batches(batches)
    return _recording(source, transforms, begin, end)


def _recording(source: LiveSource, transforms: TransformBatch, begin: int, end: int) -> Recording:
    if len(transforms):  # a sim clock may start at 0 and jump: span what was heard too
        begin = min(begin, int(transforms.record_time.min()))
        end = max(end, int(transforms.record_time.max()))
    info = BagFileInfo(
        path=source.describe(),
        format=source.format,
        start=begin,
        end=end,
        message_count=source.message_count,
        topics=dict.fromkeys(source.topics, TF_TYPE),
        transform_count=len(transforms),
    )
    return recording_of(BagContents([transforms] if len(transforms) else [], [info], tuple(source.topics)))


def listen(source: LiveSource, cache_time: int | None = DEFAULT_CACHE_TIME) -> Buffer:
    """Start ``source`` into a new buffer (tf2's cache length by default) on the source's clock,
    filled from then on in the background, as a ``tf2_ros::TransformListener`` fills its buffer.
    Close the source to stop."""
    compiled()  # load the compiled lookups now: loading them later would stall the receiving threads
    buffer = Buffer(cache_time=cache_time, clock=source.clock)

    def insert(batch: TransformBatch) -> None:
        buffer.insert(batch)

    source.start(insert)
    return buffer
