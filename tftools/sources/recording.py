"""``Recording``: bags read into a buffer (or a live system heard, or a buffer as it is), with what they held."""

from __future__ import annotations

import ctypes
import functools
import os
import threading
from collections.abc import Callable, Sequence
from dataclasses import field

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.core.batch import TransformBatch, concat_batches, named_by_use, take_rows
from tftools.core.buffer import Buffer
from tftools.core.semantics import Semantics
from tftools.core.stored import stored_rows
from tftools.core.time import SimClock
from tftools.sources.bag import ProgressCallback
from tftools.sources.bag.messages import a_core_aside
from tftools.sources.bag.reader import BagReader
from tftools.sources.bag.robot import RobotMessages, robot_messages
from tftools.sources.codecs.gather import distinct
from tftools.sources.codecs.select import carries_transforms
from tftools.sources.contents import (
    BUFFER_FORMAT,
    DEFAULT_TOPICS,
    ClockSamples,
    OfferedQos,
    RecordingContents,
    SourceInfo,
    StampedRead,
)
from tftools.sources.errors import NoTransformsError
from tftools.sources.timeline import Timeline, timeline_of
from tftools.values import record


@record
class Recording:
    """One recording (one bag or a split bag, a live capture, a buffer): its buffer, whose clock stands
    at the recording's end in ROS time (``timeline.end``) and whose histories are the only copy of the
    transforms, its clocks, and its description."""

    buffer: Buffer
    contents: RecordingContents
    timeline: Timeline
    refused: TransformBatch = field(default_factory=TransformBatch.empty)
    refused_sequence: Int64Array = field(default_factory=lambda: np.zeros(0, np.int64))

    @property
    def start(self) -> int:
        """Record time of the first message, every topic counted, whose record time is known (ns)."""
        return self.timeline.record_start

    @property
    def end(self) -> int:
        return self.timeline.record_end

    @property
    def paths(self) -> list[str]:
        return [f.path for f in self.contents.files]

    @property
    def problems(self) -> list[str]:
        """What could not be read, one line each; the rest was read."""
        return self.contents.problems

    @property
    def clock(self) -> ClockSamples:
        """The recorded /clock (a split recording's files merged); none live or for a buffer."""
        return self.contents.clock

    @property
    def stamped(self) -> StampedRead:
        """The headers of the sensor data read with the transforms (``read_recording``'s ``headers``, or
        heard live beside them), each topic's, and one line per topic whose headers could not be read."""
        return self.contents.stamped

    @property
    def qos(self) -> dict[str, OfferedQos]:
        """Each ROS 2 bag's offered QoS (the profiles its publishers offered, and per topic its messages and
        publishers, as metadata.yaml says), by the bag's path; none for other sources."""
        return self.contents.qos

    @functools.cached_property
    def robot(self) -> RobotMessages:
        """The recorded robot description (the latest) and joint states, of a recording read with
        ``whole=ROBOT_TOPICS``; empty otherwise."""
        return robot_messages(self.contents)

    @property
    def transform_count(self) -> int:
        """Transforms read, stored or refused."""
        return sum(f.transform_count for f in self.contents.files)

    @property
    def transforms(self) -> TransformBatch:
        """Every transform read, in record order, as rows (rebuilt from the buffer: a copy)."""
        stored, sequence = stored_rows(self.buffer)
        if not len(self.refused):
            return stored
        merged = concat_batches([stored, self.refused])
        return take_rows(merged, np.argsort(np.concatenate([sequence, self.refused_sequence]), kind="stable"))


def read_recording(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    progress: ProgressCallback | None = None,
    *,
    allow_empty: bool = False,
    semantics: Semantics | None = None,
    headers: Sequence[str] | None = None,
    whole: Sequence[str] = (),
    header_limit: int | None = None,
) -> Recording:
    """Read bags into a whole-recording buffer (no cache limit) answering as ``semantics`` (by default
    the recording's own); ``NoTransformsError`` when no transform was found, unless ``allow_empty``.
    With ``headers``, the sensor data's headers on those topics (none named: every topic whose
    messages start with a header) are read in the same pass (``Recording.stamped``), and so are the
    messages of the ``whole`` topics, whole (``ROBOT_TOPICS``: ``Recording.robot``). ``header_limit``: the
    headers read of each topic at most (``BagReader``'s)."""
    with BagReader(paths, topics, headers=headers, whole=whole, header_limit=header_limit) as reader:
        contents = reader.read(progress=progress)
    if not contents.parts and not allow_empty:
        raise no_transforms(paths, contents)
    return recording_of(contents, semantics)


def no_transforms(paths: Sequence[str | os.PathLike[str]], contents: RecordingContents) -> NoTransformsError:
    """The error for bags at ``paths`` in which no transform was found: why, as far as ``contents`` tells."""
    found = sorted({t for f in contents.files for t in f.topics})
    damage = [p for f in contents.files for p in f.problems]
    carriers = sorted({t for f in contents.files for t, kind in f.topics.items() if carries_transforms(kind)})
    ros2 = semantics_of(contents) == "ros2"
    return NoTransformsError(
        [str(p) for p in paths], contents.topics, found, contents.unread, damage, carriers, ros2=ros2
    )


def semantics_of(contents: RecordingContents) -> Semantics:
    """ROS 1's tf2 for ROS 1 bags, MCAP files of the ros1 profile and live ROS 1, ROS 2's for rosbag2
    and other MCAP files and live ROS 2 (a split recording: its first file's)."""
    formats = [f.format for f in contents.files]
    return "ros1" if not formats or formats[0].startswith("ros1") else "ros2"


def recording_of(contents: RecordingContents, semantics: Semantics | None = None, record_step: int = 0) -> Recording:
    """The buffer of ``contents``, which it takes: each part is inserted, then let go and its memory
    given back (``_malloc_trim``), so that the transforms are held once, in the buffer's
    histories. Rows the buffer refused, or took for identical ones it holds (ROS 2), are kept aside
    for ``transforms``. ``record_step``: how coarse the record times are (``Timeline.record_step``)."""
    clock = SimClock(contents.end)
    buffer = Buffer(cache_time=None, clock=clock, semantics=semantics or semantics_of(contents))
    refused: list[TransformBatch] = []
    refused_sequence = [np.zeros(0, np.int64)]
    parts, contents.parts = contents.parts, []
    room, contents.room = contents.room, None
    # pages given back on another core where one is free (``_give_back``), asked only where some will be before the end
    aside = sum(part.nbytes for part in parts) >= FREED_BYTES_TO_GIVE_BACK and a_core_aside()
    buffer.reserve(parts, room)
    del room  # what the histories did not take given back
    parts.reverse()
    freed = 0
    giving_back: threading.Thread | None = None
    while parts:
        part = parts.pop()
        first, seen, seen_again = buffer.arrivals, len(buffer.rejections), len(buffer.duplicates)
        buffer.insert(part)
        if len(buffer.rejections) > seen or len(buffer.duplicates) > seen_again:
            again = np.array(buffer.duplicates[seen_again:], np.int64)
            # unique: a sample refused for two reasons (NaN and denormalized) is one row
            sequence = distinct(np.concatenate([buffer.rejections.sequences(seen), again]))
            refused.append(take_rows(part, sequence - first))
            refused_sequence.append(sequence)
        freed += part.nbytes
        del part
        if freed >= FREED_BYTES_TO_GIVE_BACK:
            giving_back = _give_back(giving_back, aside)
            freed = 0
    _give_back(giving_back, aside=False)
    timeline = timeline_of(buffer, contents.clock, contents.start, contents.end, record_step)
    clock.reset(timeline.end)
    # its names as its rows first use them: the reader's table (every name of the file, its headers' too) is
    # interned in the order its parts were decoded, which depends on how the read grouped them
    unstored = named_by_use(concat_batches(refused))
    return Recording(buffer, contents, timeline, unstored, np.concatenate(refused_sequence))


#: Bytes of decoded parts freed before their pages are given back to the system.
FREED_BYTES_TO_GIVE_BACK = 8 << 20


def _give_back(under_way: threading.Thread | None, aside: bool) -> threading.Thread | None:
    """The C heap's free pages given back (``_malloc_trim``), once those ``under_way`` are: on a thread of its own
    where ``aside`` (its caller inserts the next part meanwhile; ctypes lets go of the GIL), else at once. The
    first of a 300 s robot's ingest takes 1.3 to 2 ms of CPU (the read's freed memory with the parts'), the
    next ~1 ms: a tenth of its insert's."""
    if under_way is not None:
        under_way.join()
    if not aside:
        _malloc_trim()(0)
        return None
    thread = threading.Thread(target=_malloc_trim(), args=(0,), name="tfx-give-back", daemon=True)
    thread.start()
    return thread


@functools.cache
def _malloc_trim() -> Callable[[int], int]:
    """glibc's ``malloc_trim``, which returns the C heap's free pages to the system (elsewhere a no-op:
    other allocators return memory their own way). glibc keeps freed memory for reuse, but the
    histories, being larger, cannot reuse a freed part's: the rows would count twice in peak memory."""
    try:
        trim: Callable[[int], int] = ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError):
        return lambda _pad: 0
    return trim


def recording_of_buffer(buffer: Buffer) -> Recording:
    """``buffer`` as it is (filled by hand, or by a live source) as a recording, for the checks: the
    samples it stored and those its rejection log keeps, spanning from the first arrival to the
    buffer's time. Where a sample's arrival is unknown (no record time), its stamp stands for it."""
    stored, _ = stored_rows(buffer)
    refused, refused_sequence = buffer.rejections.rows()
    arrivals = np.concatenate([np.where(b.record_time > 0, b.record_time, b.stamp) for b in (stored, refused)])
    start = int(arrivals.min()) if len(arrivals) else buffer.now()
    end = max(buffer.now(), int(arrivals.max()) if len(arrivals) else 0)
    info = SourceInfo("the buffer", BUFFER_FORMAT, start, end, len(arrivals), transform_count=len(arrivals))
    contents = RecordingContents([], [info], DEFAULT_TOPICS)
    timeline = timeline_of(buffer, ClockSamples.empty(), start, end)
    return Recording(buffer, contents, timeline, refused, refused_sequence)
