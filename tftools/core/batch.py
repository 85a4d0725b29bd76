"""``TransformBatch``: transforms in columns, the bulk input of a buffer."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, IntpArray
from tftools.core.frames import Names


@dataclass
class TransformBatch:
    """Transforms in arrival order, one row each, as sources decode them.

    Frame ids and authorities are indices into the batch's own string tables, which keep the
    names exactly as received (a leading ``/`` or an empty id included): validating them is the
    buffer's job. Several batches of one source may share the same tables.
    """

    frame_names: Sequence[str]
    authorities: Sequence[str]
    parent: Int32Array
    child: Int32Array
    stamp: Int64Array
    translation: FloatArray  # (N, 3)
    rotation: FloatArray  # (N, 4), x y z w
    static: BoolArray  # received on /tf_static
    record_time: Int64Array  # when it was received or recorded; 0 where unknown
    authority: Int32Array = field(default_factory=lambda: np.zeros(0, np.int32))

    def __post_init__(self) -> None:
        n = len(self.stamp)
        if len(self.authority) != n:
            self.authority = np.zeros(n, np.int32)
        for name in ("parent", "child", "record_time", "static"):
            if len(getattr(self, name)) != n:
                raise ValueError(f"TransformBatch.{name} has {len(getattr(self, name))} rows, not {n}")
        if self.translation.shape != (n, 3) or self.rotation.shape != (n, 4):
            raise ValueError("TransformBatch needs translation (N, 3) and rotation (N, 4)")

    def __len__(self) -> int:
        return len(self.stamp)

    @property
    def nbytes(self) -> int:
        """The bytes of its columns (not of its string tables)."""
        return sum(getattr(self, name).nbytes for name in ROW_COLUMNS)

    @classmethod
    def empty(cls) -> TransformBatch:
        return BatchBuilder().take()


#: A batch's columns of one value per row (``frame_names`` and ``authorities`` are its string tables).
ROW_COLUMNS = ("parent", "child", "stamp", "translation", "rotation", "static", "record_time", "authority")


class BatchBuilder:
    """Collects transforms one by one (or message by message) into ``TransformBatch`` es.

    For transforms made in Python (a buffer's ``set_transform``, tests); decoders fill columns directly.
    """

    def __init__(self) -> None:
        self._frames = Names()
        self._authorities = Names()
        self.frame_names = self._frames.names
        self.authorities = self._authorities.names
        self._clear()

    def _clear(self) -> None:
        self._ids: list[int] = []  # parent, child pairs
        self._stamps: list[int] = []
        self._values: list[float] = []  # 7 per row
        self._static: list[bool] = []
        self._record: list[int] = []
        self._authority: list[int] = []

    def __len__(self) -> int:
        return len(self._stamps)

    def add(
        self,
        parent: str,
        child: str,
        stamp: int,
        translation: Sequence[float],
        rotation: Sequence[float],
        *,
        static: bool = False,
        record_time: int = 0,
        authority: str = "",
    ) -> None:
        self._ids += (self._frames.intern(parent), self._frames.intern(child))
        self._stamps.append(stamp)
        self._values += (*translation, *rotation)
        self._static.append(static)
        self._record.append(record_time)
        self._authority.append(self._authorities.intern(authority))

    def take(self) -> TransformBatch:
        """The rows added since the last ``take``, as a batch."""
        ids = np.array(self._ids, np.int32).reshape(-1, 2)
        values = np.array(self._values, np.float64).reshape(-1, 7)
        batch = TransformBatch(
            frame_names=self.frame_names,
            authorities=self.authorities,
            parent=ids[:, 0].copy(),
            child=ids[:, 1].copy(),
            stamp=np.array(self._stamps, np.int64),
            translation=values[:, :3].copy(),
            rotation=values[:, 3:].copy(),
            static=np.array(self._static, bool),
            record_time=np.array(self._record, np.int64),
            authority=np.array(self._authority, np.int32),
        )
        self._clear()
        return batch


def concat_batches(batches: Sequence[TransformBatch]) -> TransformBatch:
    """One batch of all rows, in the given order, over merged string tables."""
    batches = [b for b in batches if len(b)]
    if not batches:
        return TransformBatch.empty()
    if len(batches) == 1:
        return batches[0]
    frames, authorities = Names(), Names()
    parents, children, auths = [], [], []
    for b in batches:
        fmap = np.array([frames.intern(n) for n in b.frame_names] or [0], np.int32)
        amap = np.array([authorities.intern(n) for n in b.authorities] or [0], np.int32)
        parents.append(fmap[b.parent])
        children.append(fmap[b.child])
        auths.append(amap[b.authority])
    remapped = {"parent": parents, "child": children, "authority": auths}  # ids into the merged tables
    columns = {
        name: np.concatenate(remapped[name] if name in remapped else [getattr(b, name) for b in batches])
        for name in ROW_COLUMNS
    }
    return TransformBatch(frame_names=frames.names, authorities=authorities.names, **columns)


def named_by_use(batch: TransformBatch) -> TransformBatch:
    """``batch`` over only the frame names its rows use, numbered as they first come (a row's parent, then its
    child): the same rows give the same table, whatever order a reader interned its names in."""
    if not len(batch):
        return batch
    ids = np.stack([batch.parent, batch.child], axis=1).ravel()
    used, first = np.unique(ids, return_index=True)
    used = used[np.argsort(first)]
    number = np.zeros(len(batch.frame_names), np.int32)
    number[used] = np.arange(len(used), dtype=np.int32)
    names = [batch.frame_names[i] for i in used.tolist()]
    return replace(batch, frame_names=names, parent=number[batch.parent], child=number[batch.child])


def take_rows(batch: TransformBatch, rows: IntpArray | slice) -> TransformBatch:
    """The given rows of ``batch``, in that order, sharing its string tables (a slice: views, not copies)."""
    return replace(batch, **{name: getattr(batch, name)[rows] for name in ROW_COLUMNS})
