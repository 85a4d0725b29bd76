"""``Buffer``: tf2's BufferCore, its state owned by the compiled core (``native/core.hpp``), read through
numpy views (``EdgeHistory``)."""

from __future__ import annotations

import time as _time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from functools import wraps
from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt

from tftools.core import history as _history
from tftools.core import walk
from tftools.core._kernels import (
    BufferCore,
    BufferLock,
    Spare,
    buffer_can_transform,
    buffer_lookup,
    buffer_set_transform,
)
from tftools.core.arrays import BoolArray, FloatArray, Int64Array
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.errors import InvalidArgumentError, TransformError, UnknownFrameError
from tftools.core.frames import NO_PARENT, frame_name
from tftools.core.history import EdgeHistory
from tftools.core.kernels import BatchOutputs, lookup_in_parallel
from tftools.core.rejection import RejectionLog
from tftools.core.rotation import quat_multiply_many, quat_rotate_many
from tftools.core.semantics import Semantics, check_semantics, dialect
from tftools.core.time import NS_PER_S, Clock, SimClock
from tftools.core.transform import Transform

#: tf2's default cache length (``BufferCore::DEFAULT_CACHE_TIME``), for live buffers.
DEFAULT_CACHE_TIME = 10 * NS_PER_S

#: tf2 accepts a quaternion whose squared norm is within this of 1.
QUATERNION_TOLERANCE = 10e-3

_Method = TypeVar("_Method", bound=Callable[..., Any])


def _locked(method: _Method) -> _Method:
    """Run ``method`` holding the buffer's lock, so a live source may insert from its thread."""

    @wraps(method)
    def run(self: Buffer, *args: Any, **kwargs: Any) -> Any:
        with self._lock:
            return method(self, *args, **kwargs)

    return run  # type: ignore[return-value]


@dataclass(frozen=True)
class LookupBatch:
    """``Buffer.lookup_many``'s answer: one row per requested time."""

    stamps: Int64Array  # the time each lookup was made at (time 0 resolved)
    translations: FloatArray  # (N, 3)
    rotations: FloatArray  # (N, 4), x y z w
    valid: BoolArray  # where tf2 would have succeeded

    def __len__(self) -> int:
        return len(self.stamps)

    def apply_to_points(self, points: npt.ArrayLike) -> FloatArray:
        """Each (x, y, z) expressed in the target frame, as tf2_geometry_msgs transforms a PointStamped:
        rotated, then translated. NaN rows where the lookup failed."""
        return self._failed_as_nan(quat_rotate_many(self.rotations, _rows(points, 3, len(self))) + self.translations)

    def apply_to_vectors(self, vectors: npt.ArrayLike) -> FloatArray:
        """Each (x, y, z) direction in the target frame, as tf2_geometry_msgs transforms a Vector3Stamped:
        rotated only. NaN rows where the lookup failed."""
        return self._failed_as_nan(quat_rotate_many(self.rotations, _rows(vectors, 3, len(self))))

    def apply_to_poses(self, positions: npt.ArrayLike, orientations: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Poses (positions, x y z w orientations) in the target frame, as tf2_geometry_msgs transforms a
        PoseStamped: the position as a point, the orientation composed after the transform's rotation."""
        rotated = quat_multiply_many(self.rotations, _rows(orientations, 4, len(self)))
        return self.apply_to_points(positions), self._failed_as_nan(rotated)

    def _failed_as_nan(self, values: FloatArray) -> FloatArray:
        values[~self.valid] = np.nan
        return values


def _rows(values: npt.ArrayLike, width: int, count: int) -> FloatArray:
    """``values`` as ``count`` rows of ``width`` (one row is repeated)."""
    array = np.asarray(values, np.float64)
    if array.shape == (width,):
        array = np.broadcast_to(array, (count, width))
    if array.shape != (count, width):
        raise InvalidArgumentError(f"expected {count} rows of {width} values, got an array of shape {array.shape}")
    return array


class Buffer:
    """A tf buffer with tf2's semantics: frames, edge histories, lookups.

    ``cache_time`` (nanoseconds) bounds each edge's history as tf2's cache does; ``None`` keeps
    everything, which is what whole-bag analysis wants. ``clock`` answers "what time is it":
    a ``SimClock`` (bag time) unless a live source gives a wall clock. ``semantics`` chooses
    the tf2 to answer as: ``"ros1"`` (ROS 1 bags and systems) or ``"ros2"`` (``.db3``/``.mcap``
    and ROS 2 systems); ``tftools.core.semantics`` lists how they differ.
    """

    # The core in a slot: the methods in C (lookup, can_transform, set_transform) read it there, at
    # its offset, instead of looking the attribute up on every call.
    __slots__ = ("__dict__", "__weakref__", "_core")

    def __init__(
        self,
        cache_time: int | None = DEFAULT_CACHE_TIME,
        clock: Clock | None = None,
        semantics: Semantics = "ros1",
    ) -> None:
        self._cache_time = cache_time
        self.clock: Clock = clock if clock is not None else SimClock()
        self._semantics: Semantics = check_semantics(semantics)
        self._authorities: list[str] = []
        self._attach(self._new_core())

    @property
    def cache_time(self) -> int | None:
        return self._cache_time

    @property
    def semantics(self) -> Semantics:
        return self._semantics

    @property
    def arrivals(self) -> int:
        """Samples offered so far, stored or refused: the next one's ``sequence`` number."""
        return self._core.arrivals

    @property
    def duplicates(self) -> Int64Array:
        """Arrival numbers of samples ROS 2's tf2 accepted without storing them, because it held an
        identical one: neither stored nor refused (with ``rejections``, every arrival); a live buffer
        keeps about the latest ``LIVE_REJECTIONS_KEPT``. A read-only view of the core's log."""
        return self._core.duplicates()

    @property
    def authorities(self) -> list[str]:
        """The publishers heard, by id (``EdgeHistory.authorities``): the core's, copied once per new one."""
        if len(self._authorities) != self._core.publisher_count:
            self._authorities = self._core.publisher_names()
        return self._authorities

    @property
    def lock(self) -> BufferLock:
        """Held by every insertion and lookup (reentrant, the core's); hold it to make several reads
        see one state."""
        return self._lock

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        for derived in ("_lock", "rejections", "_batch_outputs"):
            del state[derived]
        with self._lock:
            # The core's state as plain values (its histories' columns as arrays), rebuilt where the copy is used.
            state["_core"] = self._core.state()
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        state = state.copy()
        core_state = state.pop("_core")
        self.__dict__.update(state)
        core = self._new_core()
        core.restore(core_state)
        self._attach(core)

    def _attach(self, core: BufferCore) -> None:
        """``core`` made this buffer's state, and what is read of it."""
        self._core = core
        self._lock = core.lock
        #: What tf2 refused (``RejectionLog``: a sequence of ``Rejection`` s, the core's columns; a
        #: live buffer keeps about the latest ``LIVE_REJECTIONS_KEPT``, and counts every one in ``total``).
        self.rejections = RejectionLog(core, self.semantics)
        self._batch_outputs = BatchOutputs()

    # --- frames ------------------------------------------------------------------------------

    @property
    def frames(self) -> list[str]:
        """Every frame, in the order tf2 would have interned them."""
        return self._core.frame_names()[1:]

    def has_frame(self, frame: str) -> bool:
        return self._core.frame_id(frame) != NO_PARENT

    def history(self, child_frame: str) -> EdgeHistory | None:
        """The samples stored for ``child_frame`` (None for a root or unknown frame)."""
        return self._core.history(self._core.frame_id(child_frame))

    def in_static_cache(self, frame: str) -> bool:
        """Whether tf2 holds every sample of ``frame`` in a ``StaticCache``: each replaces its value for every
        time, whatever its stamp, refused neither as ``TF_OLD_DATA`` nor as ``TF_REPEATED_DATA``, so the order of
        its stamps matters to no lookup. A frame first sent static, where tf2 keeps a frame's first kind of cache
        (``Dialect.keeps_first_cache``: ROS 1's); ROS 2's turns it dynamic at its first /tf sample."""
        hist = self.history(frame)
        return hist is not None and hist.static and dialect(self.semantics).keeps_first_cache

    def histories(self) -> Iterator[tuple[str, EdgeHistory]]:
        """Each child frame with its history, in frame order."""
        for frame_id, name in enumerate(self._core.frame_names()):
            hist = self._core.history(frame_id)
            if hist is not None:
                yield name, hist

    def frame_name(self, frame_id: int) -> str:
        return self._core.frame_name(frame_id)

    @_locked
    def parent(self, frame: str, time: int = 0) -> str | None:
        """``frame``'s parent at ``time`` (latest if 0), or None (root, unknown, no data then)."""
        hist = self.history(frame)
        if hist is None:
            return None
        parent = hist.parent_at(time)
        return None if parent is None else self._core.frame_name(parent)

    def now(self) -> int:
        return self.clock.now()

    # --- insertion ---------------------------------------------------------------------------

    #: ``set_transform(transform, authority="", static=False, record_time=0)``: add one transform as
    #: tf2's ``setTransform`` does; False if it was refused (ROS 2's tf2 accepts a sample identical to
    #: one it holds, and stores it once). A method in C: its common case (both frames known, named
    #: without a slash, and different; a valid sample, newer than the child's newest unless static, and
    #: of its kind; a known publisher; no rows reserved) is stored in place under the lock by the core's
    #: ``set_transform``; every other sample (nothing stored yet) takes ``_set_transform_by_batch``.
    set_transform = buffer_set_transform

    def _set_transform_by_batch(self, transform: Transform, authority: str, static: bool, record_time: int) -> bool:
        """``set_transform`` where its common case does not store the sample: the batch path."""
        builder = BatchBuilder()
        builder.add(
            transform.frame_id,
            transform.child_frame_id,
            transform.stamp,
            transform.translation,
            transform.rotation,
            static=static,
            record_time=record_time,
            authority=authority,
        )
        return self.insert(builder.take()) == 1

    def insert(self, batch: TransformBatch) -> int:
        """Add a batch in its row order, exactly as that many ``set_transform`` calls would.

        Returns how many rows tf2 accepted: stored, or (ROS 2) identical to one already held
        (their arrival numbers go to ``duplicates``). Refused rows go to ``rejections``.
        Safe to call from another thread than the lookups; wakes ``wait_for_transform``.
        """
        return self._core.insert(batch) if len(batch) else 0

    def clear(self) -> None:
        """tf2's ``BufferCore::clear`` (ROS 1 and ROS 2 alike): each dynamic edge's samples dropped,
        static edges kept, every frame name and id kept (a listener's answer to a jump back in time)."""
        self._core.clear()

    def reserve(self, batches: Iterable[TransformBatch], spare: Spare | None = None) -> None:
        """Size each history once for the rows of ``batches``, about to be inserted: a bulk load
        in parts then grows no history by doubling (what is never stored stays reserved). ``spare``: the
        memory brought in for them while they were read (``RecordingContents.room``), taken if it fits."""
        expected: dict[str, int] = {}
        for batch in batches:
            rows = np.bincount(batch.child, minlength=len(batch.frame_names))
            for child in np.flatnonzero(rows).tolist():
                name = frame_name(batch.frame_names[child])
                expected[name] = expected.get(name, 0) + int(rows[child])
        self._core.reserve(list(expected.items()), spare)

    # --- lookups -----------------------------------------------------------------------------

    #: ``lookup(target_frame, source_frame, time=0)``: the transform taking ``source_frame`` data into
    #: ``target_frame`` at ``time`` (ns); time 0 means the latest time all edges of the chain share. Raises
    #: tf2's errors with tf2's messages: ``UnknownFrameError``, ``ConnectivityError``,
    #: ``ExtrapolationError``, ``InvalidArgumentError``. A method in C (the core's ``lookup_frames``
    #: without a Python frame); where the walk does not answer, ``_lookup_by_ids``.
    lookup = buffer_lookup

    @_locked
    def _lookup_by_ids(self, target_frame: str, source_frame: str, time: int, raw: bool = False) -> Transform:
        """``lookup`` where ``lookup_frames`` does not answer: a frame to itself, names to check
        (tf2's errors for them), and every failure, worded by ``walk.error`` from the failed walk
        (``lookup_frames``', else this one's). ``raw``: ROS 2's rotation as composed, before its
        ``tf2::Transform`` gives it back (``BufferCore.lookup``)."""
        if target_frame == source_frame:
            return Transform.identity(self._identity_stamp(target_frame, time), target_frame, source_frame)
        target_id, source_id = self._frame_ids("lookupTransform", target_frame, source_frame)
        failure = None if raw else self._core.last_failure(target_id, source_id, time)
        if failure is None:
            found, failure = self._core.lookup(target_id, source_id, time, raw)
            if found is not None:
                return Transform(*found, target_frame, source_frame)
        raise self._walk_error(target_frame, source_frame, failure)

    @_locked
    def lookup_full(
        self, target_frame: str, target_time: int, source_frame: str, source_time: int, fixed_frame: str
    ) -> Transform:
        """tf2's "time travel": ``source_frame`` at ``source_time`` into ``target_frame`` at
        ``target_time``, assuming ``fixed_frame`` does not move between the two times. Both tf2s
        multiply the two lookups as ``tf2::Transform``s (ROS 1's as returned; ROS 2's as composed)."""
        self._frame_id("lookupTransform argument target_frame", target_frame)
        self._frame_id("lookupTransform argument source_frame", source_frame)
        self._frame_id("lookupTransform argument fixed_frame", fixed_frame)
        source_in_fixed = self._lookup_by_ids(fixed_frame, source_frame, source_time, raw=True)
        fixed_in_target = self._lookup_by_ids(target_frame, fixed_frame, target_time, raw=True)
        composed = fixed_in_target * source_in_fixed
        return Transform(composed.translation, composed.rotation, fixed_in_target.stamp, target_frame, source_frame)

    #: ``can_transform(target_frame, source_frame, time=0)``: whether ``lookup`` would succeed (tf2's
    #: ``canTransform``). A method in C, as ``lookup``.
    can_transform = buffer_can_transform

    def can_transform_full(
        self, target_frame: str, target_time: int, source_frame: str, source_time: int, fixed_frame: str
    ) -> bool:
        """Whether ``lookup_full`` would succeed (tf2's ``canTransform`` with a fixed frame): False
        for an invalid or unknown frame, even where all three are that one frame."""
        try:
            self.lookup_full(target_frame, target_time, source_frame, source_time, fixed_frame)
        except TransformError:
            return False
        return True

    @_locked
    def latest_common_time(self, target_frame: str, source_frame: str) -> int:
        """The newest time at which every edge between the two frames has data (0: all static)."""
        target_id = self._frame_id("get_latest_common_time", target_frame)
        source_id = self._frame_id("get_latest_common_time", source_frame)
        common, failure = self._core.latest_common_time(target_id, source_id)
        if failure[0] != walk.NO_FAILURE:
            raise self._walk_error(target_frame, source_frame, failure)
        return common

    @_locked
    def lookup_many(self, target_frame: str, source_frame: str, times: npt.ArrayLike) -> LookupBatch:
        """``lookup`` at many times (int64 ns), vectorized; ``valid`` marks where tf2 succeeds.

        Unknown or invalid frame names raise as ``lookup`` does; every other failure is a
        ``False`` in ``valid`` (call ``lookup`` at such a time for tf2's reason). A large batch's arrays
        share one block of memory, which the buffer keeps for its next batches once they are let go.
        """
        stamps = np.asarray(times, dtype=np.int64).reshape(-1)
        if target_frame == source_frame:
            resolved = np.where(stamps == 0, self._identity_stamp(target_frame, 0), stamps)
            n = len(stamps)
            return LookupBatch(resolved, np.zeros((n, 3)), np.tile([0.0, 0, 0, 1], (n, 1)), np.ones(n, bool))
        target_id, source_id = self._frame_ids("lookupTransform", target_frame, source_frame)
        resolved, values, valid = lookup_in_parallel(self._core, target_id, source_id, stamps, self._batch_outputs)
        return LookupBatch(resolved, values[:, :3], values[:, 3:], valid)

    def transform_points(
        self, target_frame: str, source_frame: str, times: npt.ArrayLike, points: npt.ArrayLike
    ) -> FloatArray:
        """Points (N, 3) of ``source_frame`` at ``times`` (N, or one for all) in ``target_frame``;
        NaN rows where tf2 could not look the transform up (``lookup`` at that time says why)."""
        return self.lookup_many(target_frame, source_frame, _times_for(times, points)).apply_to_points(points)

    def transform_vectors(
        self, target_frame: str, source_frame: str, times: npt.ArrayLike, vectors: npt.ArrayLike
    ) -> FloatArray:
        """Vectors (N, 3) rotated into ``target_frame`` (no translation), as ``transform_points``."""
        return self.lookup_many(target_frame, source_frame, _times_for(times, vectors)).apply_to_vectors(vectors)

    def transform_poses(
        self,
        target_frame: str,
        source_frame: str,
        times: npt.ArrayLike,
        positions: npt.ArrayLike,
        orientations: npt.ArrayLike,
    ) -> tuple[FloatArray, FloatArray]:
        """Poses (positions (N, 3), orientations (N, 4) x y z w) in ``target_frame``, as ``transform_points``."""
        batch = self.lookup_many(target_frame, source_frame, _times_for(times, positions))
        return batch.apply_to_poses(positions, orientations)

    @_locked
    def chain(self, target_frame: str, source_frame: str, time: int = 0) -> list[str]:
        """The frames a lookup passes through, from ``source_frame`` to ``target_frame`` (none
        from a frame to itself, as tf2's ``_chainAsVector``)."""
        if target_frame == source_frame:
            return []
        target_id, source_id = self._frame_ids("chain", target_frame, source_frame)
        frames, failure = self._core.chain(target_id, source_id, time)
        if failure[0] != walk.NO_FAILURE:
            raise self._walk_error(target_frame, source_frame, failure)
        names = self._core.frame_names()
        return [names[f] for f in frames]

    def wait_for_transform(
        self, target_frame: str, source_frame: str, time: int = 0, timeout_s: float = 0.0
    ) -> Transform:
        """``lookup``, waiting up to ``timeout_s`` wall seconds for the data it needs to arrive
        (tf2's ``lookupTransform`` with a timeout); then raises the lookup's error."""
        deadline = _time.monotonic() + timeout_s
        with self._lock:
            while True:
                try:
                    return self.lookup(target_frame, source_frame, time)
                except TransformError:
                    remaining = deadline - _time.monotonic()
                    if remaining <= 0:
                        raise
                    self._lock.wait(remaining)

    # --- tf2's introspection -----------------------------------------------------------------

    @_locked
    def all_frames_as_string(self) -> str:
        """tf2's ``allFramesAsString``: "Frame X exists with parent Y." per child frame."""
        return walk.frames_as_string(self._tree())

    @_locked
    def all_frames_as_yaml(self) -> str:
        """tf2's ``allFramesAsYAML``: per child frame its parent, broadcaster, rate and span."""
        publishers = self.authorities
        names = {frame_id: publishers[a] for frame_id, a in enumerate(self._core.broadcasters()) if a >= 0}
        return walk.frames_as_yaml(self._tree(), names)

    def _tree(self) -> walk.Tree:
        names = self._core.frame_names()
        return walk.Tree([self._core.history(i) for i in range(len(names))], names, dialect(self.semantics))

    def _walk_error(self, target_frame: str, source_frame: str, failure: walk.Failure) -> TransformError:
        return walk.error(failure, target_frame, source_frame, dialect(self.semantics), self._tree)

    def _new_core(self) -> BufferCore:
        """The buffer's state: its frames, publishers and histories, compiled."""
        ros2 = self.semantics == "ros2"
        return BufferCore(Transform, self._cache_time, ros2, QUATERNION_TOLERANCE, _history.LARGE_PAGES_UP_TO)

    def _identity_stamp(self, frame: str, time: int) -> int:
        if time != 0:
            return time
        hist = self.history(frame)
        return hist.latest_stamp if hist is not None else 0

    def _frame_ids(self, call: str, target_frame: str, source_frame: str) -> tuple[int, int]:
        """The ids of a lookup's two frames, checked as tf2's ``validateFrameId`` checks them."""
        target_id, source_id = self._core.frame_id(target_frame), self._core.frame_id(source_frame)
        if not target_id or not source_id or target_frame[0] == "/" or source_frame[0] == "/":
            target_id = self._frame_id(f"{call} argument target_frame", target_frame)
            source_id = self._frame_id(f"{call} argument source_frame", source_frame)
        return target_id, source_id

    def _frame_id(self, argument: str, frame: str) -> int:
        """tf2's ``validateFrameId``."""
        if not frame:
            raise dialect(self.semantics).empty_frame(argument)
        if frame.startswith("/"):
            raise dialect(self.semantics).leading_slash(frame, argument)
        frame_id = self._core.frame_id(frame)
        if frame_id == NO_PARENT:
            raise UnknownFrameError.missing(frame, argument)
        return frame_id


def _times_for(times: npt.ArrayLike, rows: npt.ArrayLike) -> Int64Array:
    """One time per row: ``times`` as given, or one time repeated for every row."""
    stamps = np.asarray(times, np.int64).reshape(-1)
    shape = np.shape(rows)
    count = shape[0] if len(shape) == 2 else 1
    return np.repeat(stamps, count) if len(stamps) == 1 else stamps
