"""Freed memory given back to the system as a bag is loaded."""

from __future__ import annotations

import ctypes
import functools
from collections.abc import Callable


class FreedMemory:
    """Counts the bytes let go and, past ``every`` of them, returns the C heap's free pages.

    glibc keeps freed heap memory resident for reuse; a bag's decoded parts, freed one after
    the other as the buffer's histories take them in, could not be reused by those histories
    (they are larger), so without this the rows would count twice in peak memory.
    """

    def __init__(self, every: int = 8 << 20) -> None:
        self.every = every
        self._pending = 0

    def freed(self, nbytes: int) -> None:
        self._pending += nbytes
        if self._pending >= self.every:
            self.release()

    def release(self) -> None:
        self._pending = 0
        trim = _malloc_trim()
        if trim is not None:
            trim(0)


@functools.cache
def _malloc_trim() -> Callable[[int], int] | None:
    """glibc's ``malloc_trim``; None elsewhere (other allocators return memory their own way)."""
    try:
        trim: Callable[[int], int] = ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError):
        return None
    return trim
