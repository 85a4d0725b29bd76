"""Samples a buffer refused, recorded with tf2's codes instead of printed."""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple, overload

import numpy as np
import numpy.typing as npt

from tftools.core._kernels import through_matrix as kernel_through_matrix
from tftools.core.arrays import Int32Array, Int64Array, UInt8Array
from tftools.core.batch import TransformBatch
from tftools.core.frames import Names
from tftools.core.history import rows_as_sent
from tftools.core.semantics import Semantics, dialect
from tftools.core.time import to_sec


class RejectionCode(str, enum.Enum):
    """Why ``Buffer.set_transform`` refused a sample: tf2's ``setTransform`` log codes
    (ROS 2's tf2 has no ``TF_REPEATED_DATA``: it stores or ignores such samples)."""

    NAN_INPUT = "TF_NAN_INPUT"
    DENORMALIZED_QUATERNION = "TF_DENORMALIZED_QUATERNION"
    SELF_TRANSFORM = "TF_SELF_TRANSFORM"
    NO_FRAME_ID = "TF_NO_FRAME_ID"
    NO_CHILD_FRAME_ID = "TF_NO_CHILD_FRAME_ID"
    REPEATED_DATA = "TF_REPEATED_DATA"
    OLD_DATA = "TF_OLD_DATA"

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True, slots=True)
class Rejection:
    """One refused sample: what was wrong, which frames, when, and from whom."""

    code: RejectionCode
    frame_id: str
    child_frame_id: str
    stamp: int
    authority: str
    record_time: int = 0
    values: tuple[float, ...] = ()
    sequence: int = -1  # the sample's arrival number in its buffer (``EdgeHistory.sequence``)
    semantics: Semantics = "ros1"  # the tf2 whose log line ``message`` is

    @property
    def message(self) -> str:
        """tf2's log line for this rejection (ROS 2's shows the rotation as its matrix gave it back)."""
        c, a = self.child_frame_id, self.authority
        shown = list(self.values)
        if self.semantics == "ros2" and len(shown) >= 4:
            shown[-4:] = through_matrix(shown[-4:])
        values = " ".join(c_float(v) for v in shown)
        vector, quaternion = " ".join(values.split(" ")[:3]), " ".join(values.split(" ")[3:])
        if self.semantics == "ros2":  # ROS 2's lines where they differ from ROS 1's
            ros2 = {
                RejectionCode.SELF_TRANSFORM: f'TF_SELF_TRANSFORM: Ignoring transform from authority "{a}" with '
                f'frame_id and  child_frame_id "{c}" because they are the same',
                RejectionCode.OLD_DATA: f"TF_OLD_DATA ignoring data from the past for frame {c} at time "
                f"{dialect('ros2').seconds(self.stamp)} according to authority {a}\n"
                "Possible reasons are listed at http://wiki.ros.org/tf/Errors%20explained",
            }
            if self.code in ros2:
                return ros2[self.code]
        return {
            RejectionCode.NAN_INPUT: f'TF_NAN_INPUT: Ignoring transform for child_frame_id "{c}" from authority '
            f'"{a}" because of a nan value in the transform ({vector}) ({quaternion})',
            RejectionCode.DENORMALIZED_QUATERNION: "TF_DENORMALIZED_QUATERNION: Ignoring transform "
            f'for child_frame_id "{c}" from authority "{a}" because of an invalid quaternion in '
            f"the transform ({values})",
            RejectionCode.SELF_TRANSFORM: f'TF_SELF_TRANSFORM: Ignoring transform from authority "{a}" '
            f'with frame_id and child_frame_id  "{c}" because they are the same',
            RejectionCode.NO_FRAME_ID: f'TF_NO_FRAME_ID: Ignoring transform with child_frame_id "{c}"  '
            f'from authority "{a}" because frame_id not set',
            RejectionCode.NO_CHILD_FRAME_ID: f'TF_NO_CHILD_FRAME_ID: Ignoring transform from authority "{a}" '
            "because child_frame_id not set ",
            RejectionCode.REPEATED_DATA: "TF_REPEATED_DATA ignoring data with redundant timestamp "
            f"for frame {c} (parent {self.frame_id}) at time {to_sec(self.stamp):f} "
            f"according to authority {a}",
            RejectionCode.OLD_DATA: "TF_OLD_DATA ignoring data from the past for frame "
            f"{c} (parent {self.frame_id}) at time {to_sec(self.stamp):f} according to authority {a}",
        }[self.code]


def c_float(value: float) -> str:
    """``value`` as C's ``printf("%f")`` prints it: a NaN with its sign bit set as ``-nan``."""
    if math.isnan(value):
        return "-nan" if math.copysign(1.0, value) < 0 else "nan"
    return f"{value:f}"


def through_matrix(rotation: Sequence[float]) -> list[float]:
    """``rotation`` (x y z w) as ROS 2's tf2 holds it: back from a ``tf2::Transform``'s basis (the
    compiled kernel, whose NaNs keep tf2's signs)."""
    turned = np.array([rotation], np.float64)
    kernel_through_matrix(turned)
    return [float(v) for v in turned[0]]


#: A live buffer (finite cache time) keeps its latest this many rejections; every one is counted.
LIVE_REJECTIONS_KEPT = 10_000

_CODES = list(RejectionCode)
_CODE_INDEX = {code: i for i, code in enumerate(_CODES)}
#: How many of a refused sample's 7 values its ``Rejection`` shows (the last ones), as tf2's log
#: line does: all for NaN, the rotation for the other checks of ``setTransform``, none for a stamp.
_SHOWN_VALUES = {
    RejectionCode.NAN_INPUT: 7,
    RejectionCode.DENORMALIZED_QUATERNION: 4,
    RejectionCode.SELF_TRANSFORM: 4,
    RejectionCode.NO_FRAME_ID: 4,
    RejectionCode.NO_CHILD_FRAME_ID: 4,
}


class EdgeRejections(NamedTuple):
    """One edge's rejections of one code (or group of codes): how many, the distinct samples
    among them (stamp, record time, publisher), their first and last stamps, the publishers
    (sorted) and the codes."""

    rows: int
    samples: int
    first_stamp: int
    last_stamp: int
    authorities: tuple[str, ...]
    codes: tuple[RejectionCode, ...]  # in order of first refusal


class RejectionLog(Sequence[Rejection]):
    """A buffer's refused samples, in the order refused, held as columns: a ``Rejection`` is
    made only when one is read, so a million refusals cost tens of megabytes, not a gigabyte.
    Each keeps the whole sample, so that ``rows`` gives back what was sent.

    ``limit`` keeps only the latest that many (a live buffer's); ``total`` counts every one.
    """

    def __init__(self, semantics: Semantics = "ros1", limit: int | None = None) -> None:
        self.semantics: Semantics = semantics
        self.limit = limit
        self.total = 0
        self._frames = Names()
        self._publishers = Names()
        self._parts: list[dict[str, npt.NDArray[Any]]] = []
        self._joined = {name: np.zeros((0, 7) if name == "values" else 0, dtype) for name, dtype in _COLUMNS.items()}

    # --- recording ---------------------------------------------------------------------------

    def add(
        self, code: RejectionCode, names: Sequence[str], authorities: Sequence[str], rows: Mapping[str, Any]
    ) -> None:
        """Refusals of one ``code``, a row each, in the columns of ``_COLUMNS`` but ``code``: frames (as
        tf2 names them) and publishers as indices into ``names`` and ``authorities`` (interned here, once
        per distinct one), ``values`` (N, 7), ``flags`` as ``EdgeHistory.flags``."""
        n = len(rows["stamp"])
        if n == 0:
            return
        interned = {
            "parent": _interned(rows["parent"], names, self._frames),
            "child": _interned(rows["child"], names, self._frames),
            "authority": _interned(rows["authority"], authorities, self._publishers),
        }
        given = {**rows, **interned, "code": np.full(n, _CODE_INDEX[code])}
        self._parts.append({name: np.array(given[name], dtype) for name, dtype in _COLUMNS.items()})
        self.total += n
        if self.limit is not None and len(self) > 2 * self.limit:
            self._join()
            self._joined = {k: v[-self.limit :].copy() for k, v in self._joined.items()}

    def _join(self) -> dict[str, npt.NDArray[Any]]:
        if self._parts:
            parts = [self._joined, *self._parts]
            self._joined = {k: np.concatenate([p[k] for p in parts]) for k in self._joined}
            self._parts = []
        return self._joined

    # --- reading -----------------------------------------------------------------------------

    def __len__(self) -> int:
        return len(self._joined["stamp"]) + sum(len(p["stamp"]) for p in self._parts)

    @overload
    def __getitem__(self, index: int) -> Rejection: ...

    @overload
    def __getitem__(self, index: slice) -> list[Rejection]: ...

    def __getitem__(self, index: int | slice) -> Rejection | list[Rejection]:
        c = self._join()
        if isinstance(index, slice):
            return [self._make(c, i) for i in range(*index.indices(len(c["stamp"])))]
        n = len(c["stamp"])
        if not -n <= index < n:
            raise IndexError("rejection index out of range")
        return self._make(c, index % n)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, RejectionLog | list | tuple):
            return list(self) == list(other)
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"RejectionLog({len(self)} kept of {self.total})"

    def _make(self, c: dict[str, npt.NDArray[Any]], i: int) -> Rejection:
        code = _CODES[int(c["code"][i])]
        shown = _SHOWN_VALUES.get(code, 0)
        return Rejection(
            code,
            self._frames.names[int(c["parent"][i])],
            self._frames.names[int(c["child"][i])],
            int(c["stamp"][i]),
            self._publishers.names[int(c["authority"][i])],
            int(c["record_time"][i]),
            tuple(c["values"][i, 7 - shown :].tolist()) if shown else (),
            int(c["sequence"][i]),
            self.semantics,
        )

    def rows(self) -> tuple[TransformBatch, Int64Array]:
        """The kept refused samples as they were sent, in arrival order, one row per sample (tf2 may
        refuse one for several reasons), and each one's arrival number."""
        c = self._join()
        sequence, first = np.unique(c["sequence"], return_index=True)
        batch = rows_as_sent(self._frames.names, self._publishers.names, {k: v[first] for k, v in c.items()})
        return batch, sequence

    def verdicts(self, sequences: Int64Array) -> UInt8Array:
        """What the samples of arrival numbers ``sequences`` were refused for, each as the bits
        (``code_bits``) of its kept rejections' codes (several where tf2 logs several): 0 for one not
        refused, or whose rejections are no longer kept."""
        c = self._join()
        bits = np.zeros(len(sequences), np.uint8)
        order = np.argsort(sequences, kind="stable")
        at = np.minimum(np.searchsorted(sequences, c["sequence"], sorter=order), max(len(sequences) - 1, 0))
        if len(sequences):
            found = sequences[order[at]] == c["sequence"]
            np.bitwise_or.at(bits, order[at[found]], (1 << c["code"][found]).astype(np.uint8))
        return bits

    def sequences(self, start: int = 0) -> Int64Array:
        """The arrival numbers of the rejections from the ``start``-th kept one on, in order."""
        sequence: Int64Array = self._join()["sequence"][start:].copy()
        return sequence

    def by_edge(self, groups: Mapping[RejectionCode, str] | None = None) -> dict[tuple[str, str, str], EdgeRejections]:
        """The kept rejections per (parent, child, group), in order of first refusal: a group is
        ``groups[code]`` (several codes may share one), or the code itself. Counted with numpy,
        not row by row."""
        c = self._join()
        n = len(c["stamp"])
        if not n:
            return {}
        labels = [groups[code] if groups else code.value for code in _CODES]
        label_ids = {label: i for i, label in enumerate(dict.fromkeys(labels))}
        group_of = np.array([label_ids[label] for label in labels], np.int64)[c["code"]]
        key = (c["parent"].astype(np.int64) * len(self._frames.names) + c["child"]) * len(label_ids) + group_of
        order = np.argsort(key, kind="stable")
        bounds = np.flatnonzero(np.diff(key[order])) + 1
        result: dict[tuple[str, str, str], EdgeRejections] = {}
        for rows in sorted(np.split(order, bounds), key=lambda g: int(g[0])):
            first = int(rows[0])
            stamps = c["stamp"][rows]
            samples = np.unique(
                np.stack([stamps, c["record_time"][rows], c["authority"][rows].astype(np.int64)]), axis=1
            )
            codes, code_first = np.unique(c["code"][rows], return_index=True)
            parent, child = self._frames.names[int(c["parent"][first])], self._frames.names[int(c["child"][first])]
            result[(parent, child, labels[int(c["code"][first])])] = EdgeRejections(
                len(rows),
                int(samples.shape[1]),
                int(stamps.min()),
                int(stamps.max()),
                tuple(sorted({self._publishers.names[a] for a in np.unique(c["authority"][rows]).tolist()})),
                tuple(_CODES[int(i)] for i in codes[np.argsort(code_first)]),
            )
        return result


def code_bits(*codes: RejectionCode) -> int:
    """``codes`` as bits of ``RejectionLog.verdicts``."""
    return sum(1 << _CODE_INDEX[code] for code in set(codes))


def _interned(ids: npt.NDArray[np.integer[Any]], names: Sequence[str], table: Names) -> Int32Array:
    """``ids`` (into ``names``) as ids of ``table``, interning each distinct name once."""
    distinct, where = np.unique(np.asarray(ids), return_inverse=True)
    mapped = np.array([table.intern(names[name_id]) for name_id in distinct.tolist()], np.int32)
    return mapped[where.reshape(-1)]


#: The columns a ``RejectionLog`` holds, and their types (values: (N, 7)).
_COLUMNS: dict[str, type[np.generic]] = {
    "code": np.uint8,
    "parent": np.int32,
    "child": np.int32,
    "stamp": np.int64,
    "authority": np.int32,
    "record_time": np.int64,
    "sequence": np.int64,
    "values": np.float64,
    "flags": np.uint8,
}
