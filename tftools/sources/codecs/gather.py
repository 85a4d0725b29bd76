"""Bytes and numbers gathered from a byte array at many positions at once; distinct values and members found
without ``np.unique``, whose first call imports numpy.ma (a tenth of reading a small bag)."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array


def bytes_at(raw: UInt8Array, at: Int64Array, width: int) -> UInt8Array:
    """The ``width`` bytes at each position of ``at`` (all within ``raw``), one row each."""
    if len(raw) < width or width == 0:
        return np.zeros((len(at) if width == 0 else 0, width), np.uint8)
    # A view with one ``width``-byte item at every position: gathering items copies whole rows.
    windows = np.ndarray((len(raw) - width + 1,), f"V{width}", raw, strides=(1,))
    rows: UInt8Array = windows[at].view(np.uint8).reshape(-1, width)
    return rows


def u32_at(raw: UInt8Array, at: Int64Array) -> Int64Array:
    """The little-endian uint32 at each position of ``at``."""
    return bytes_at(raw, at, 4).view("<u4").reshape(-1).astype(np.int64)


def distinct(values: Int64Array) -> Int64Array:
    """``np.unique(values)``, without its cost where they are in order already."""
    if len(values) < 2 or bool(np.all(values[1:] > values[:-1])):
        return values
    ordered = np.sort(values)
    return ordered[np.concatenate(([True], ordered[1:] != ordered[:-1]))]


def among(values: Int64Array, members: Int64Array) -> BoolArray:
    """``np.isin(values, members)`` of integers, by a search among them sorted: ``np.isin`` of many calls
    ``np.unique``, whose first call imports numpy.ma (~9 ms of CPU, in every fresh process that reads a bag)."""
    if not len(members):
        return np.zeros(len(values), bool)
    ordered = members if bool(np.all(members[1:] >= members[:-1])) else np.sort(members)
    at = np.minimum(np.searchsorted(ordered, values), len(ordered) - 1)
    found: BoolArray = ordered[at] == values
    return found


def first_and_inverse(values: npt.NDArray[Any]) -> tuple[Int64Array, Int64Array]:
    """The first index of each distinct value, and each value's index among them (``np.unique``'s)."""
    order = np.argsort(values, kind="stable")
    ordered = values[order]
    new = np.ones(len(values), bool)
    new[1:] = ordered[1:] != ordered[:-1]
    inverse = np.empty(len(values), np.int64)
    inverse[order] = np.cumsum(new) - 1
    return order[new], inverse


def grouped(values: Int64Array) -> list[Int64Array]:
    """The indices of each distinct value, together."""
    firsts, inverse = first_and_inverse(values)
    order = np.argsort(inverse, kind="stable")
    return np.split(order, np.cumsum(np.bincount(inverse, minlength=len(firsts)))[:-1])
