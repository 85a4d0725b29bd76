"""The compiled lookups (native/module.cpp): tf2's walk over the buffer's edge histories (native/walk.hpp)."""

import threading
from collections.abc import Callable

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, UInt8Array
from tftools.core.batch import TransformBatch
from tftools.core.history import EdgeHistory
from tftools.core.transform import Transform
from tftools.core.walk import Failure

#: Times per block of ``EdgeTable.lookup_many``'s chain path.
BLOCK: int

def through_matrix(rotations: FloatArray) -> None:
    """Rotations (N, 4, x y z w), in place, as ROS 2's tf2 holds and returns them: through a
    ``tf2::Transform``'s basis (``Matrix3x3::setRotation``, then ``getRotation``)."""

class EdgeTable:
    """Per frame id, where its history's samples lie (see ``tftools.core.kernels``), and what
    ``Buffer``'s single calls need of their buffer, read as it changes."""

    #: Samples offered to the buffer so far, stored or refused: the next one's sequence number.
    arrivals: int

    def __init__(
        self,
        lock: threading.RLock,
        frames: dict[str, int],
        answer: type[Transform],
        authorities: dict[str, int],
        broadcasters: dict[int, int],
        reserved: dict[str, int],
        cache_time: int | None,
        ros2: bool,
        tolerance: float,
    ) -> None:
        """``lock``: the buffer's, which ``set_transform``, ``lookup_frames`` and
        ``can_transform_frames`` hold (the GIL let go while they wait for it); ``frames``: name to id
        (``FrameTable.ids``); ``answer``: the type lookups return, built through its fields' slots;
        the rest: the buffer's publishers' ids, each child frame's last publisher, the rows it
        reserved, its cache's length, whether it answers as ROS 2's tf2, and the squared quaternion
        norm's tolerance."""

    def update(self, frame: int, history: EdgeHistory | None) -> None:
        """Describe ``history`` (``frame``'s) as it is now, by its ``storage()`` (arrays the table keeps alive)."""

    def set_transform(self, transform: Transform, authority: str, static: bool, record_time: int) -> bool:
        """``Buffer.set_transform``'s common case stored in place (the arrays, grown if full, the
        history's bounds, its pruning, the publisher, ``arrivals``): both frames known and plain, a
        valid sample of the child's kind, newer than its newest (unless static), a known publisher,
        nothing reserved. False, having stored nothing, in every other case."""

    def lookup_frames(self, target_frame: str, source_frame: str, time: int) -> Transform | None:
        """``Buffer.lookup`` of two different known plain frames where tf2 succeeds; None otherwise."""

    def can_transform_frames(self, target_frame: str, source_frame: str, time: int) -> bool:
        """``Buffer.can_transform``."""

    def lookup(
        self, target: int, source: int, time: int, raw: bool = False
    ) -> tuple[tuple[float, float, float], tuple[float, float, float, float], int] | None:
        """tf2's lookup: (tx, ty, tz), (qx, qy, qz, qw) and the time used (0: the latest common time);
        None where tf2 fails (``chain`` says why). ROS 2's rotation comes back through a matrix,
        unless ``raw`` (the composed one, which ROS 2's lookup with a fixed frame multiplies)."""

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

    def insert(
        self,
        batch: TransformBatch,
        authority_ids: Int32Array,
        histories: list[EdgeHistory | None],
        intern: Callable[[str], int],
        new_history: Callable[[bool, int, EdgeHistory | None], EdgeHistory],
    ) -> tuple[int, Int64Array, UInt8Array, Int64Array, Int64Array]:
        """``Buffer.insert``'s work, in one call: ``batch``'s rows (``authority_ids``: each of its
        publishers' id in the buffer) as that many tf2 ``setTransform`` calls, ``arrivals`` counted.

        Rows failing tf2's checks are refused; the others' frames are interned by ``intern`` (in order
        of first appearance, each row's child before its parent) and, frame by frame, offered to the
        frame's history: ``histories[frame]``, made by ``new_history(static, capacity, replaced)``
        where there is none (or, under ROS 2, for a change between static and dynamic), grown, merged
        by stamp, pruned; each frame's last publisher noted, its reserved rows used. Returns how many
        rows tf2 accepted, the refused rows (indices into ``batch``) in the order tf2 refused them,
        in groups of one code each (``Refusal`` in native/insert.hpp: the codes, and the groups'
        bounds into the rows), and the rows ROS 2's tf2 accepted without storing them (identical to
        a sample held)."""
