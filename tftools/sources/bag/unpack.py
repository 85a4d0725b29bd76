"""Decompression bounded by what the bag declares: every codec of every bag format, in one place.

A compressed chunk, record or message says how large it is once decompressed; a hostile one
says little and expands to gigabytes (a "bomb"). Each function here decompresses at most the
declared size, never more than ``MAX_UNPACKED``, and within the file's ``Budget``, and returns
what it could decompress with a line saying what was lost.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, BinaryIO, Protocol

from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.lz4_prefix import lz4_prefix

MAX_UNPACKED = 256 << 20  # bytes one chunk, record or message may decompress to, whatever it declares
MAX_RATIO = 1000  # a file's decompressed bytes in all, per byte of the file (real bags: ~3 to 50)
MIN_BUDGET = 64 << 20  # ... but at least this much, so a small bag of very compressible data reads whole
UNDECLARED_SHARE = 16  # a message not stating its size may take this share of its file's budget, at most
FREE_SPACE_MARGIN = 256 << 20  # bytes a file decompressed to disk leaves free there
_PIECE = 1 << 16  # compressed bytes fed at a time, so a damaged stream still yields its start
_OUT_PIECE = 1 << 20  # decompressed bytes asked for at a time from a stream reader
_DAMAGED_PIECE = 1 << 12  # ... and from one of damaged data, read again: what comes before the damage
_ZSTD_MAGIC = b"\x28\xb5\x2f\xfd"
_ZSTD_CHECKSUM_FLAG = 0x04  # of a zstd frame header's descriptor byte


class CompressionUnavailableError(Exception):
    """A compression this machine cannot decompress (the message says what to install)."""


class Unpacked:
    """Decompressed bytes; ``loss`` says why they end before the declared size ("" when whole)."""

    __slots__ = ("data", "loss")

    def __init__(self, data: bytes | memoryview, loss: str = "") -> None:
        self.data = data  # a view of the decompressed bytes: not copied again
        self.loss = loss


class Budget:
    """What one file may decompress in all: ``MAX_RATIO`` times its size (at least ``MIN_BUDGET``).
    Bounds the time a bag of many small bombs takes, each within its own limit."""

    def __init__(self, file_size: int) -> None:
        self.left = max(MIN_BUDGET, MAX_RATIO * file_size)
        self.total = self.left

    def cap(self) -> tuple[int, str]:
        """What is left, and the cap it is, said as the reason should a piece be cut there."""
        return self.left, f"the file's budget of {self.total >> 20} MiB decompressed ({MAX_RATIO}x its size)"

    def spend(self, size: int) -> None:
        self.left = max(0, self.left - size)


def allowed(declared: int, budget: Budget | None = None, most: tuple[int, str] | None = None) -> tuple[int, str]:
    """The bytes a piece declaring ``declared`` (below 0: nothing) may decompress to, and the cap that sets it, said
    as the reason should the piece be cut there; ``most``: the largest cap (default: ``MAX_UNPACKED``)."""
    caps = [most or (MAX_UNPACKED, f"tftools' limit of {MAX_UNPACKED >> 20} MiB a piece")]
    if declared >= 0:  # below 0: not declared
        caps.append((declared, f"its declared size of {declared} bytes"))
    if budget is not None:
        caps.append(budget.cap())
    return min(caps, key=lambda cap: cap[0])


class _Decompressor(Protocol):
    @property
    def needs_input(self) -> bool: ...

    @property
    def eof(self) -> bool: ...

    def decompress(self, data: bytes, max_length: int = -1) -> bytes: ...


def unpack(compression: str, data: bytes | memoryview, declared: int, budget: Budget | None = None) -> Unpacked:
    """``data`` compressed with ``compression`` ("none"/"" for none, "bz2", "lz4" or "zstd"),
    decompressed up to its ``declared`` size. Raises ``CompressionUnavailableError``."""
    if compression in ("", "none"):
        cut = f"cut short at {len(data)} of {declared} bytes" if len(data) < declared else ""
        return Unpacked(data, cut)
    if compression == "bz2":
        import bz2  # imported for the bags that need it, as lz4 and zstd are

        return _fed("bz2", bz2.BZ2Decompressor(), data, declared, budget)
    if compression == "lz4":
        try:
            from lz4.frame import LZ4FrameDecompressor
        except ImportError:
            raise CompressionUnavailableError("the lz4 package is not installed (pip install lz4)") from None
        return _lz4(LZ4FrameDecompressor(), data, declared, budget)
    if compression == "zstd":
        return zstd(data, declared, budget)
    raise CompressionUnavailableError(f"the compression {compression!r} is unknown")


def zstd(
    data: bytes | memoryview, declared: int, budget: Budget | None = None, most: tuple[int, str] | None = None
) -> Unpacked:
    """A zstd frame decompressed up to its declared size (see ``unpack``; ``most``: see ``allowed``)."""
    limit, cap = allowed(declared, budget, most)
    out, loss = _zstd_read(data, limit, _OUT_PIECE)
    if loss:  # again in small pieces, unchecked: a read that fails gives nothing of its piece
        del out[:]  # not held beside the second read (memory)
        out, _ = _zstd_read(_unchecked(data), limit, _DAMAGED_PIECE)
    return _ended("zstd", out, declared, limit, cap, loss, budget)


def _unchecked(data: bytes | memoryview) -> bytes | memoryview:
    """A zstd frame without its content checksum, whose failure would withhold the last piece decompressed
    (the damage is said all the same): its header's flag cleared and the checksum's 4 bytes left off."""
    if bytes(data[:4]) != _ZSTD_MAGIC or len(data) < 9 or not data[4] & _ZSTD_CHECKSUM_FLAG:
        return data
    frame = bytearray(data[:-4])
    frame[4] &= ~_ZSTD_CHECKSUM_FLAG
    return bytes(frame)


def _zstd_read(data: bytes | memoryview, limit: int, piece_size: int) -> tuple[bytearray, str]:
    """What the zstd ``data`` decompresses to, read ``piece_size`` bytes at a time up to just past ``limit``,
    and what damage ended it ("" for none)."""
    zstandard = _zstandard()
    out = bytearray()
    try:
        with zstandard.ZstdDecompressor().stream_reader(data) as reader:
            while len(out) <= limit and (piece := reader.read(min(piece_size, limit + 1 - len(out)))):
                out += piece
    except zstandard.ZstdError as e:
        return out, f"zstd data damaged ({e})"
    return out, ""


def zstd_messages(file_size: int) -> Callable[[bytes], bytes]:
    """Decompresses one zstd-compressed message of a file (rosbag2's compression by message) within
    the file's budget: whole, or ``DamageError``. A message declaring more than it may have is
    lost unread; one that does not state its size (rosbag2 states it) may take no more than
    ``1 / UNDECLARED_SHARE`` of the budget, so that one bomb does not use up the budget of the rest."""
    budget = Budget(file_size)

    def message(data: bytes) -> bytes:
        zstandard = _zstandard()
        try:
            declared = zstandard.frame_content_size(data)
        except zstandard.ZstdError as e:
            raise DamageError(f"not a zstd frame ({e})") from None
        limit, cap = allowed(declared, budget)
        if declared > limit:
            raise DamageError(f"zstd data declares {declared} bytes, past {cap}")
        most = None
        if declared < 0:
            share = budget.total // UNDECLARED_SHARE
            pieces = [(MAX_UNPACKED, f"tftools' limit of {MAX_UNPACKED >> 20} MiB a piece")]
            most = min([*pieces, (share, f"{share >> 20} MiB, its share of the file's budget")], key=lambda c: c[0])
        unpacked = zstd(data, declared, budget, most)  # below 0: not declared
        if unpacked.loss:
            raise DamageError(unpacked.loss)
        return bytes(unpacked.data)

    return message


def zstd_file(source: BinaryIO, target: Path, budget: Budget) -> str:
    """Decompress the zstd file ``source`` into ``target``, at most its declared size, the budget,
    and what leaves ``FREE_SPACE_MARGIN`` free where ``target`` is; returns what was lost ("" for nothing).
    Raises ``OSError`` (a full disk, say)."""
    zstandard = _zstandard()
    head = source.read(18)  # a zstd frame header is at most 18 bytes
    source.seek(0)
    try:
        declared = zstandard.frame_content_size(head)
    except zstandard.ZstdError:
        declared = -1
    import shutil

    free = max(0, shutil.disk_usage(target.parent).free - FREE_SPACE_MARGIN)
    limit, cap = allowed(declared, budget, (free, f"the {free >> 20} MiB free in {target.parent} (less a margin)"))
    written, loss = 0, ""
    with target.open("wb") as out:
        try:
            with zstandard.ZstdDecompressor().stream_reader(source) as reader:
                while written < limit and (piece := reader.read(min(_OUT_PIECE, limit - written))):
                    out.write(piece)
                    written += len(piece)
                if written >= limit and reader.read(1):
                    loss = f"decompressed only up to {cap}; the rest is lost"
        except zstandard.ZstdError as e:
            loss = f"zstd data damaged after {written} bytes ({e}); the rest is lost"
    budget.spend(written)
    if not loss and 0 <= declared != written:
        loss = f"zstd data cut short: {written} of {declared} bytes; the rest is lost"
    return loss


def _fed(
    codec: str, decompressor: _Decompressor, data: bytes | memoryview, declared: int, budget: Budget | None
) -> Unpacked:
    """Feed ``data`` a piece at a time to a streaming decompressor, asking for no more than the limit."""
    limit, cap = allowed(declared, budget)
    out = bytearray()
    loss = ""
    pos = 0
    try:
        while len(out) <= limit and not decompressor.eof:
            if decompressor.needs_input:
                if pos >= len(data):
                    break
                piece, pos = bytes(data[pos : pos + _PIECE]), pos + _PIECE
            else:
                piece = b""
            out += decompressor.decompress(piece, limit + 1 - len(out))
    except (OSError, EOFError, RuntimeError, ValueError) as e:  # what bz2 and lz4 raise on bad data
        loss = f"{codec} data damaged ({e})"
    return _ended(codec, out, declared, limit, cap, loss, budget)


def _lz4(decompressor: _Decompressor, data: bytes | memoryview, declared: int, budget: Budget | None) -> Unpacked:
    """``data`` as lz4 decompresses it; where it ends inside a block (a file cut short) or a block is damaged,
    that block up to the cut or the damage too (``lz4_prefix``): lz4 gives a block only once it is whole
    and sound. The loss is said all the same."""
    fed = _fed("lz4", decompressor, data, declared, budget)
    cut = fed.loss.startswith("lz4 data cut short")
    if decompressor.eof or not (cut or fed.loss.startswith("lz4 data damaged")):
        return fed
    limit, cap = allowed(declared, budget)
    if budget is not None:
        budget.left += len(fed.data)  # spent again below, on what is kept
    prefix = lz4_prefix(data, limit + 1)
    out = prefix if len(prefix) > len(fed.data) else bytearray(fed.data)
    return _ended("lz4", out, declared, limit, cap, "" if cut else fed.loss, budget)


def _ended(
    codec: str, out: bytearray, declared: int, limit: int, cap: str, loss: str, budget: Budget | None
) -> Unpacked:
    """The bytes decompressed, cut at the limit, and the line that says what was lost."""
    if len(out) > limit:
        del out[limit:]
        loss = f"{codec} data decompresses past {cap}; read up to there"
    elif not loss and 0 <= len(out) < declared:
        loss = f"{codec} data cut short: {len(out)} of {declared} bytes"
    if budget is not None:
        budget.spend(len(out))
    return Unpacked(memoryview(out), loss)


def _zstandard() -> Any:
    try:
        import zstandard
    except ImportError:
        raise CompressionUnavailableError("the zstandard package is not installed (pip install zstandard)") from None
    return zstandard
