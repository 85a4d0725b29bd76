"""The compiled core (native/module.cpp): the buffer's state (native/core.hpp), tf2's rules for each sample
(native/insert.hpp) and tf2's walk over the histories (native/walk.hpp)."""

from types import TracebackType
from typing import Any

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, UInt8Array
from tftools.core.batch import TransformBatch
from tftools.core.transform import Transform
from tftools.core.walk import Failure

#: Times per block of ``BufferCore.lookup_many``'s chain path.
BLOCK: int
#: The bytes of one sample in a history's columns.
ROW_BYTES: int
#: The largest bulk load whose histories' block is laid on large pages.
LARGE_PAGES_UP_TO: int
#: Why a walk failed (``walk.Failure``'s first item): it did not, a loop, two trees, an extrapolation.
NO_FAILURE: int
LOOP: int
UNCONNECTED: int
EXTRAPOLATION: int
#: Why a history had no sample at a time (``history.Extrapolation.kind``).
NO_DATA: int
ONLY_ONE: int
FUTURE: int
PAST: int
#: ``EdgeHistory.flags`` bits.
FROM_STATIC_TOPIC: int
PARENT_HAD_SLASH: int
CHILD_HAD_SLASH: int
#: tf2's id of no frame (a root's parent).
NO_PARENT: int
#: A live buffer keeps its latest this many refusals and duplicates (up to twice as many).
LIVE_REJECTIONS_KEPT: int
#: The refusal codes by number (``BufferCore.refusals``' code column), as ``rejection.RejectionCode``'s names.
REFUSALS: tuple[str, ...]

def through_matrix(rotations: FloatArray) -> None:
    """Rotations (N, 4, x y z w), in place, as ROS 2's tf2 holds and returns them: through a
    ``tf2::Transform``'s basis (``Matrix3x3::setRotation``, then ``getRotation``)."""

def buffer_lookup(self: Any, target_frame: str, source_frame: str, time: int = 0) -> Transform:
    """``Buffer.lookup``, a method in C: its core's (``self._core``) ``lookup_frames`` where the walk
    answers, else ``self._lookup_by_ids(target_frame, source_frame, time)``."""

def buffer_can_transform(self: Any, target_frame: str, source_frame: str, time: int = 0) -> bool:
    """``Buffer.can_transform``, a method in C: its core's ``can_transform_frames``."""

def buffer_set_transform(
    self: Any, transform: Transform, authority: str = "", static: bool = False, record_time: int = 0
) -> bool:
    """``Buffer.set_transform``, a method in C: its core's ``set_transform`` (the common case), else
    ``self._set_transform_by_batch(transform, authority, static, record_time)``."""

class EdgeHistory:
    """The samples of one child frame, read-only: views of the columns the buffer's core owns (each keeps
    them alive; a history that grows or is pruned moves to new columns, the views keep the old).

    A dynamic history is sorted by stamp, like tf2's ``TimeCache``: no stamp twice under ROS 1's tf2,
    several samples of one stamp in arrival order under ROS 2's. A static history keeps every sample in
    arrival order and answers with the last one at every time, like tf2's ``StaticCache`` (which keeps
    only that one). Each row stores its parent, so a frame can change parent over time."""

    #: Whether the frame is static (tf2's StaticCache).
    static: bool
    #: The history this one replaced when ROS 2's tf2 turned the frame static or dynamic (kept only where
    #: every sample is kept).
    replaced: EdgeHistory | None
    stamps: Int64Array
    #: (N, 7): tx ty tz qx qy qz qw, as sent.
    values: FloatArray
    translations: FloatArray
    rotations: FloatArray
    parents: Int32Array
    authorities: Int32Array
    record_times: Int64Array
    #: Arrival order across the whole buffer, to tell when stamps went backwards.
    sequence: Int64Array
    #: ``history.FROM_STATIC_TOPIC``, ``PARENT_HAD_SLASH``, ``CHILD_HAD_SLASH``.
    flags: UInt8Array
    #: tf2's ``getLatestTimestamp``: 0 for a static edge or an empty history.
    latest_stamp: int
    oldest_stamp: int
    #: The parent of the newest sample (the current one, for a static edge); 0 if empty.
    latest_parent: int

    def __len__(self) -> int: ...
    def __getstate__(self) -> list[tuple[object, ...]]:
        """Its columns and those of the histories it replaced, copied (pickle's)."""

    def __setstate__(self, state: list[tuple[object, ...]]) -> None: ...
    def parent_at(self, time: int) -> int | None:
        """tf2's ``TimeCache::getParent``: the parent at ``time`` (of the older of the two samples around
        it), or None where the history has no sample then (the walk says why). Where samples share a stamp
        (ROS 2), tf2's newest-first list makes the last to arrive count, except at the oldest stamp, which is
        the list's back: there the first one."""

class BufferLock:
    """A buffer's lock (``Buffer.lock``), the core's: reentrant as ``threading.RLock``, with the condition
    its waiters wait on (``threading.Condition``'s ``wait`` and ``notify_all``). Every change of the core
    holds it and wakes the waiters; whoever blocks on it lets go of the GIL, and a signal's handler that
    raises interrupts the wait."""

    def acquire(self) -> bool: ...
    def release(self) -> None:
        """RuntimeError where this thread does not hold it."""

    def __enter__(self) -> bool: ...
    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, traceback: TracebackType | None
    ) -> None: ...
    def wait(self, timeout: float) -> bool:
        """Let go of the lock (however many times held) until ``notify_all`` or ``timeout`` seconds, then
        hold it again as before; whether it was notified. RuntimeError where this thread does not hold it."""

    def notify_all(self) -> None: ...
    def owned(self) -> bool:
        """Whether this thread holds it."""

class Spare:
    """The memory of a bulk load's block of histories, brought in on a thread of its own while the rows are
    read (a fresh large page's first write is paid there, not in the insert); at most the largest block
    laid on large pages. ``BufferCore.reserve`` takes it; what the block does not use is given back."""

    #: Bytes brought in so far and still held (0 once taken or given back).
    brought: int

    def ahead(self, rows: int) -> None:
        """A block for ``rows`` rows or more to come: its memory brought in, and a read's part ahead."""

class BufferCore:
    """A buffer's state, one owner as tf2's BufferCore: frames (tf2's ids from 1), publishers, each child
    frame's history, its last publisher, the rows reserved for a bulk load; and the calls on it."""

    #: Samples offered to the buffer so far, stored or refused: the next one's sequence number.
    arrivals: int
    #: The buffer's lock, which every change (``set_transform``, ``insert``, ``reserve``, ``clear``) holds,
    #: waking its waiters; lookups take it only on a free-threaded Python.
    lock: BufferLock
    #: Every refusal so far, kept or not; those kept.
    refusal_total: int
    refusals_kept: int

    def __init__(
        self, answer: type[Transform], cache_time: int | None, ros2: bool, tolerance: float, large_pages_up_to: int
    ) -> None:
        """``answer``: the type lookups return, built through its fields' descriptors; its cache's length,
        whether it answers as ROS 2's tf2, the squared quaternion norm's tolerance, and the largest bulk
        load's block laid on large pages."""

    def set_transform(self, transform: Transform, authority: str, static: bool, record_time: int) -> bool:
        """``Buffer.set_transform``'s common case, through ``insert``'s rules for one row: both frames known
        and named without a leading slash, a valid sample of the child's kind, newer than its newest
        (unless static), a known publisher, nothing reserved. False, having stored nothing, otherwise."""

    def insert(self, batch: TransformBatch) -> int:
        """``Buffer.insert``'s work, in one call: ``batch``'s rows as that many tf2 ``setTransform`` calls,
        ``arrivals`` counted, its publishers interned.

        Rows failing tf2's checks are refused; the others' frames are interned (in order of first
        appearance, each row's child before its parent) and, frame by frame, offered to the frame's
        history: made where there is none (or, under ROS 2, for a change between static and dynamic),
        grown, merged by stamp, pruned; each frame's last publisher noted, its reserved rows used. The refused
        rows go to the refusal log (``refusals``) in the order tf2 refused them (by code: ``Refusal`` in
        native/insert.hpp), the arrival numbers of rows ROS 2's tf2 accepted without storing them (identical
        to a sample held) to ``duplicates``. Returns how many rows tf2 accepted."""

    def refusals(
        self,
    ) -> tuple[
        UInt8Array, Int32Array, Int32Array, Int64Array, Int32Array, Int64Array, Int64Array, FloatArray, UInt8Array
    ]:
        """The refusal log's kept rows, columns viewed (read-only): code (``REFUSALS``' index), parent and
        child (``refused_frame_names``' ids), stamp, authority (a publisher's id), record time, arrival
        number, values (N, 7, as sent) and flags (as ``EdgeHistory.flags``)."""

    def refused_frame_names(self) -> list[str]:
        """The refusal log's frames by id, as tf2 names them (a leading ``/`` dropped)."""

    def duplicates(self) -> Int64Array:
        """The kept arrival numbers of samples ROS 2's tf2 took without storing them, viewed."""

    def reserve(self, rows: list[tuple[str, int]], spare: Spare | None = None) -> None:
        """More rows of these child frames (named without a leading slash) about to come: their
        histories are made, or sized, for them once, in one block (``spare``'s memory, where the block
        is laid on large pages and fits it)."""

    def clear(self) -> None:
        """tf2's ``BufferCore::clear``: each dynamic history emptied, static ones kept, names and ids kept."""

    def frame_id(self, name: str) -> int:
        """The frame's id; 0 (``NO_PARENT``) for an unknown frame."""

    def frame_name(self, frame_id: int) -> str: ...
    def frame_names(self) -> list[str]:
        """Every frame's name by id, from 0 (``NO_PARENT``)."""

    def publisher_names(self) -> list[str]:
        """Every publisher's name by id."""

    @property
    def publisher_count(self) -> int: ...
    def history(self, frame_id: int) -> EdgeHistory | None:
        """The frame's history; None for a root or unknown frame."""

    def broadcasters(self) -> list[int]:
        """Per frame id, the publisher of its last accepted sample; -1 where none."""

    def state(self) -> tuple[object, ...]:
        """The state as plain values (names, counts, each history's columns), for ``restore``."""

    def restore(self, state: tuple[object, ...]) -> None:
        """This new core made into the one ``state`` came from."""

    def lookup_frames(self, target_frame: str, source_frame: str, time: int) -> Transform | None:
        """``Buffer.lookup`` of two different known plain frames where tf2 succeeds; None otherwise
        (``last_failure`` then says why the walk failed, where it walked)."""

    def last_failure(self, target: int, source: int, time: int) -> Failure | None:
        """Why this thread's last ``lookup_frames`` failed, if it walked from ``source`` to ``target``
        at ``time``; else None."""

    def can_transform_frames(self, target_frame: str, source_frame: str, time: int) -> bool:
        """``Buffer.can_transform``."""

    def lookup(
        self, target: int, source: int, time: int, raw: bool = False
    ) -> tuple[tuple[tuple[float, float, float], tuple[float, float, float, float], int] | None, Failure]:
        """tf2's lookup, from one walk: (tx, ty, tz), (qx, qy, qz, qw) and the time used (0: the latest
        common time), or None where tf2 fails; and why it failed (``walk.Failure``). ROS 2's rotation comes
        back through a matrix, unless ``raw`` (the composed one, which ROS 2's lookup with a fixed frame
        multiplies)."""

    def can_transform(self, target: int, source: int, time: int) -> bool:
        """Whether ``lookup`` succeeds, walking parents only."""

    def latest_common_time(self, target: int, source: int) -> tuple[int, Failure]:
        """tf2's ``getLatestCommonTime``: the newest time every dynamic edge between the frames
        has (0: all static), and why it fails (``walk.Failure``; its time then 0)."""

    def chain(self, target: int, source: int, time: int) -> tuple[list[int], Failure]:
        """The walk at ``time`` (0: the latest common time): the frame ids it passes through from
        source to target (tf2's ``_chainAsVector`` order), and why it fails (``walk.Failure``;
        its frames then none)."""

    def lookup_many(
        self,
        target: int,
        source: int,
        times: Int64Array,
        rows: Int64Array,
        stamps: Int64Array,
        values: FloatArray,
        valid: BoolArray,
        chained: bool = True,
    ) -> None:
        """``lookup`` at each of ``times`` (fastest ascending), the k-th answer into row ``rows[k]``
        of ``stamps`` (the time used), ``values`` (N, 7; identity where it failed) and ``valid``.
        Along the chain walked once where the times allow, else the walk at each time (always,
        if not ``chained``): the very same bits. Lets go of the GIL."""

    def lookup_in_parallel(
        self,
        target: int,
        source: int,
        times: Int64Array,
        stamps: Int64Array,
        values: FloatArray,
        valid: BoolArray,
        threads: int,
    ) -> None:
        """``lookup_many`` at ``times`` in any order (put in order inside), the k-th answer into
        row k, on ``threads`` threads. Lets go of the GIL."""

    def chain_takes(self, target: int, source: int, times: Int64Array) -> int:
        """Whether ``lookup_many`` takes ``times`` (1 to ``BLOCK``) as one block along the chain
        walked at the first: 1 or 0, -1 where that walk does not end at a root."""
