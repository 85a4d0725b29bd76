"""Samples a buffer refused, recorded with tf2's codes instead of printed."""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple, overload

import numpy as np
import numpy.typing as npt

from tftools.core._kernels import LIVE_REJECTIONS_KEPT as LIVE_REJECTIONS_KEPT
from tftools.core._kernels import REFUSALS, BufferCore
from tftools.core._kernels import through_matrix as kernel_through_matrix
from tftools.core.arrays import Int64Array, UInt8Array
from tftools.core.batch import TransformBatch
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


# LIVE_REJECTIONS_KEPT (the core's): a live buffer (finite cache time) keeps its latest this many
# rejections (up to twice as many); every one is counted.

#: The codes by the core's number for them.
_CODES = tuple(RejectionCode[name] for name in REFUSALS)
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
    """A buffer's refused samples, in the order refused: the log its compiled core keeps, as columns
    (numpy views of them); a ``Rejection`` is made only when one is read, so a million refusals cost
    tens of megabytes, not a gigabyte. Each keeps the whole sample, so that ``rows`` gives back what
    was sent.

    A live buffer's keeps only about the latest ``LIVE_REJECTIONS_KEPT``; ``total`` counts every one.
    """

    def __init__(self, core: BufferCore, semantics: Semantics = "ros1") -> None:
        self.semantics: Semantics = semantics
        self._core = core
        self._seen = -1  # the ``total`` the views below were taken at
        self._columns: dict[str, npt.NDArray[Any]] = {}
        self._frames: list[str] = []
        self._publishers: list[str] = []

    @property
    def total(self) -> int:
        return self._core.refusal_total

    def _join(self) -> dict[str, npt.NDArray[Any]]:
        """The core's columns, viewed as they are now (taken again only after a refusal)."""
        if self._seen != self._core.refusal_total:
            self._columns = dict(zip(_COLUMNS, self._core.refusals(), strict=True))
            self._frames = self._core.refused_frame_names()
            self._publishers = self._core.publisher_names()
            self._seen = self._core.refusal_total
        return self._columns

    # --- reading -----------------------------------------------------------------------------

    def __len__(self) -> int:
        return self._core.refusals_kept

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
            self._frames[int(c["parent"][i])],
            self._frames[int(c["child"][i])],
            int(c["stamp"][i]),
            self._publishers[int(c["authority"][i])],
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
        batch = rows_as_sent(self._frames, self._publishers, {k: v[first] for k, v in c.items()})
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
        key = (c["parent"].astype(np.int64) * len(self._frames) + c["child"]) * len(label_ids) + group_of
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
            parent, child = self._frames[int(c["parent"][first])], self._frames[int(c["child"][first])]
            result[(parent, child, labels[int(c["code"][first])])] = EdgeRejections(
                len(rows),
                int(samples.shape[1]),
                int(stamps.min()),
                int(stamps.max()),
                tuple(sorted({self._publishers[a] for a in np.unique(c["authority"][rows]).tolist()})),
                tuple(_CODES[int(i)] for i in codes[np.argsort(code_first)]),
            )
        return result


def code_bits(*codes: RejectionCode) -> int:
    """``codes`` as bits of ``RejectionLog.verdicts``."""
    return sum(1 << _CODE_INDEX[code] for code in set(codes))


#: The log's columns, in ``BufferCore.refusals``' order: code (the core's number), parent and child (ids
#: into ``BufferCore.refused_frame_names``), stamp, authority (the buffer's publisher id), record time,
#: sequence (arrival number), values (N, 7) and flags (as ``EdgeHistory.flags``).
_COLUMNS = ("code", "parent", "child", "stamp", "authority", "record_time", "sequence", "values", "flags")
