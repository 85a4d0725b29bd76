"""What an LZ4 frame cut short still holds: the bytes of its last block up to the cut.

The lz4 package gives a block's bytes only once the whole block is there, and a ROS 1 bag or MCAP
chunk is often one block (roslz4 writes blocks of up to 4 MiB; a default 768 KiB chunk is one). An
LZ4 block is a run of sequences, each literal bytes then a copy of earlier output, so every sequence
before the cut decodes exactly as it would whole (https://github.com/lz4/lz4/blob/dev/doc/): read
here, in Python, only for data that ended early or failed to decompress. Past damage it may decode
garbage until an offset points before the output: what is made of it is checked where it is parsed
(records at the offsets an index gives, their lengths and types), and the damage is said.
"""

from __future__ import annotations

#: The largest output read so (each sequence gives at least 4 bytes: the time is bounded by it).
MAX_PREFIX = 16 << 20
_MAGIC = b"\x04\x22\x4d\x18"
_UNCOMPRESSED = 0x80000000


def lz4_prefix(data: bytes | memoryview, limit: int) -> bytearray:
    """The bytes that the LZ4 frame ``data`` (cut short) decodes to, up to where it was cut and at most
    ``limit`` (and ``MAX_PREFIX``); empty when ``data`` does not begin as an LZ4 frame."""
    src = bytes(data)
    limit = min(limit, MAX_PREFIX)
    out = bytearray()
    if len(src) < 7 or src[:4] != _MAGIC or src[4] >> 6 != 1:
        return out
    flags = src[4]
    block_checksum, content_size, dictionary = flags & 0x10, flags & 0x08, flags & 0x01
    pos = 7 + 8 * bool(content_size) + 4 * bool(dictionary)  # magic, FLG, BD, the optional fields, HC
    while pos + 4 <= len(src) and len(out) < limit:
        size = int.from_bytes(src[pos : pos + 4], "little")
        pos += 4
        if size == 0:  # the end mark
            break
        stored, size = size & _UNCOMPRESSED, size & ~_UNCOMPRESSED
        block = src[pos : pos + size]
        if stored:
            out += block
        else:
            _block(block, out, limit)
        if len(block) < size:
            break
        pos += size + 4 * bool(block_checksum)
    del out[limit:]
    return out


def _block(src: bytes, out: bytearray, limit: int) -> None:
    """Append to ``out`` the sequences of the LZ4 block ``src`` (maybe cut short) that are whole, stopping at
    ``limit`` bytes of output or at an offset that points before the output (damage)."""
    pos, end = 0, len(src)
    while pos < end and len(out) < limit:
        token = src[pos]
        pos += 1
        literals, pos = _length(src, pos, token >> 4)
        if pos + literals > end:  # cut inside the literals: those there are exact
            out += src[pos:end]
            return
        out += src[pos : pos + literals]
        pos += literals
        if pos + 2 > end:  # the block's last sequence has literals only, or the cut is here
            return
        offset = src[pos] | src[pos + 1] << 8
        pos += 2
        match, pos = _length(src, pos, token & 15)
        if pos > end or not 0 < offset <= len(out):
            return
        match += 4
        start = len(out) - offset
        if offset >= match:
            out += out[start : start + match]
        else:  # the copy overlaps what it writes: a repeated pattern
            pattern = out[start:]
            out += (pattern * (match // offset + 1))[:match]


def _length(src: bytes, pos: int, nibble: int) -> tuple[int, int]:
    """A length of ``nibble`` continued by bytes of 255 while it is 15; past the end of ``src``, a position
    past the end (the caller stops)."""
    length = nibble
    if nibble == 15:
        while True:
            if pos >= len(src):
                return length, len(src) + 1
            byte = src[pos]
            pos += 1
            length += byte
            if byte != 255:
                break
    return length, pos
