"""The compiled lookups (native/module.cpp): tftools.core.walk's tf2 walk over the buffer's edge histories."""

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array

#: Times per block of ``EdgeTable.lookup_many``'s chain path.
BLOCK: int

class EdgeTable:
    """Per frame id, where its history's samples lie (see ``tftools.core.kernels``)."""

    def update(
        self,
        frame: int,
        static: bool,
        stamps: Int64Array,
        values: FloatArray,
        parents: Int32Array,
        start: int,
        end: int,
    ) -> None:
        """Describe ``frame``'s history: rows ``start:end`` of the arrays (which the table keeps alive)."""

    def lookup(
        self, target: int, source: int, time: int
    ) -> tuple[tuple[float, float, float], tuple[float, float, float, float], int] | None:
        """walk.lookup: (tx, ty, tz), (qx, qy, qz, qw) and the time used (0: the latest common time);
        None where tf2 fails."""

    def can_transform(self, target: int, source: int, time: int) -> bool:
        """walk.can_transform."""

    def latest_common_time(self, target: int, source: int) -> int | None:
        """walk.latest_common_time of two different frames; None where tf2 fails."""

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
