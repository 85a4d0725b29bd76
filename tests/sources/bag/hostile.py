"""Hostile bag files written from code: decompression bombs, looping links, lying lengths (issue 14)."""

from __future__ import annotations

import bz2
import sqlite3
import struct
from pathlib import Path

import lz4.frame
import zstandard

ZEROS = 1 << 20  # zeros compressed at a time


def compressed_zeros(codec: str, size: int) -> bytes:
    """``size`` zero bytes compressed with ``codec`` (bz2, lz4 or zstd): a small bomb."""
    piece = b"\0" * min(size, ZEROS)
    count, rest = divmod(size, len(piece))
    if codec == "bz2":
        c = bz2.BZ2Compressor(9)
        return b"".join([*(c.compress(piece) for _ in range(count)), c.compress(piece[:rest]), c.flush()])
    if codec == "lz4":
        f = lz4.frame.LZ4FrameCompressor()
        return b"".join([f.begin(), *(f.compress(piece) for _ in range(count)), f.compress(piece[:rest]), f.flush()])
    z = zstandard.ZstdCompressor(level=19).compressobj()
    return b"".join([*(z.compress(piece) for _ in range(count)), z.compress(piece[:rest]), z.flush()])


def _ros1_field(name: str, value: bytes) -> bytes:
    data = name.encode() + b"=" + value
    return struct.pack("<I", len(data)) + data


def ros1_record(fields: list[tuple[str, bytes]], data: bytes) -> bytes:
    header = b"".join(_ros1_field(k, v) for k, v in fields)
    return struct.pack("<I", len(header)) + header + struct.pack("<I", len(data)) + data


def ros1_bag(chunks: list[tuple[str, bytes, int]]) -> bytes:
    """A ROS1 bag without index: chunks of (compression, data, declared size)."""
    head = ros1_record(
        [("op", b"\x03"), ("index_pos", bytes(8)), ("conn_count", bytes(4)), ("chunk_count", bytes(4))], b""
    )
    pad = 4096 - len(head)
    head = head[:-4] + struct.pack("<I", pad) + b" " * pad
    body = b"".join(
        ros1_record([("op", b"\x05"), ("compression", c.encode()), ("size", struct.pack("<I", n))], d)
        for c, d, n in chunks
    )
    return b"#ROSBAG V2.0\n" + head + body


def _mcap_record(op: int, content: bytes) -> bytes:
    return struct.pack("<BQ", op, len(content)) + content


def _string(text: str) -> bytes:
    data = text.encode()
    return struct.pack("<I", len(data)) + data


MCAP_MAGIC = b"\x89MCAP0\r\n"


def mcap_bomb(compression: str, payload: bytes, declared: int, *, summary: bool = True) -> bytes:
    """An MCAP file of one /tf channel and one chunk of ``payload`` declaring ``declared`` bytes."""
    out = bytearray(MCAP_MAGIC)
    out += _mcap_record(1, _string("ros2") + _string("hostile"))
    schema = struct.pack("<H", 1) + _string("tf2_msgs/msg/TFMessage") + _string("ros2msg") + _string("")
    channel = struct.pack("<HH", 1, 1) + _string("/tf") + _string("cdr") + struct.pack("<I", 0)
    out += _mcap_record(3, schema) + _mcap_record(4, channel)
    chunk_at = len(out)
    head = struct.pack("<QQQI", 0, 1, declared, 0) + _string(compression)
    out += _mcap_record(6, head + struct.pack("<Q", len(payload)) + payload)
    chunk_length = len(out) - chunk_at
    index_at = len(out)
    out += _mcap_record(7, struct.pack("<HI", 1, 16) + struct.pack("<QQ", 0, 0))
    index_length = len(out) - index_at
    out += _mcap_record(0x0F, bytes(4))
    summary_at = 0
    if summary:
        summary_at = len(out)
        out += _mcap_record(3, schema) + _mcap_record(4, channel)
        offsets = struct.pack("<I", 10) + struct.pack("<HQ", 1, index_at)
        chunk_index = struct.pack("<QQQQ", 0, 1, chunk_at, chunk_length) + offsets + struct.pack("<Q", index_length)
        out += _mcap_record(8, chunk_index + _string(compression) + struct.pack("<QQ", len(payload), declared))
        out += _mcap_record(0x0B, struct.pack("<QHIIIIQQI", 1, 1, 1, 0, 0, 1, 0, 1, 0))
    out += _mcap_record(2, struct.pack("<QQI", summary_at, 0, 0)) + MCAP_MAGIC
    return bytes(out)


def db3(path: Path, payloads: list[bytes], *, page_size: int = 4096) -> Path:
    """A rosbag2 .db3 of /tf messages with these payloads."""
    db = sqlite3.connect(path)
    db.execute(f"PRAGMA page_size={page_size}")
    db.executescript(
        # rosbag2's tables, without its NOT NULL constraints: a hostile file need not have them
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT,"
        " offered_qos_profiles TEXT);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);"
    )
    db.execute("INSERT INTO topics VALUES (1, '/tf', 'tf2_msgs/msg/TFMessage', 'cdr', '')")
    db.executemany("INSERT INTO messages VALUES (?, 1, ?, ?)", [(i + 1, 5 + i, p) for i, p in enumerate(payloads)])
    db.commit()
    db.close()
    return path


def _varint5(value: int) -> bytes:
    """SQLite's varint of ``value`` (below 2**35) in five bytes, seven bits each."""
    return bytes([*(0x80 | ((value >> (7 * (4 - i))) & 0x7F) for i in range(4)), value & 0x7F])


def db3_looping_overflow(path: Path, declared: int) -> Path:
    """A .db3 whose one message declares ``declared`` bytes of data, spilling into an overflow
    page that links to itself (64 KiB pages): read naively, the chain never ends."""
    page = 65536
    db3(path, [b"\x01" * 3 * page], page_size=page)
    data = bytearray(path.read_bytes())
    db = sqlite3.connect(path)
    root = db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'messages'").fetchone()[0]
    db.close()
    base = (root - 1) * page
    assert data[base] == 0x0D  # a table leaf holding the one row
    (cell,) = struct.unpack_from(">H", data, base + 8)
    at = base + cell
    # Find the overflow pointer: the cell's local bytes end with it; the old size gives its place.
    size, size_len = _varint_at(data, at)
    rowid, rowid_len = _varint_at(data, at + size_len)
    usable = page
    local = _local(size, usable)
    pointer_at = at + size_len + rowid_len + local
    (overflow,) = struct.unpack_from(">I", data, pointer_at)
    # New cell: 5-byte varints for the sizes, header of 9 bytes, a 1-byte topic id and time.
    blob = declared
    header = bytes([9, 0, 1, 1]) + _varint5(2 * blob + 12)
    record_size = len(header) + 2 + blob
    new_local = _local(record_size, usable)
    body = (header + bytes([1, 5]) + b"\x01" * new_local)[:new_local]
    new_cell = _varint5(record_size) + bytes([rowid]) + body + struct.pack(">I", overflow)
    start = base + page - len(new_cell)
    data[base + 8 : base + 10] = struct.pack(">H", page - len(new_cell))
    data[base + 5 : base + 7] = struct.pack(">H", page - len(new_cell))
    data[start : base + page] = new_cell
    struct.pack_into(">I", data, (overflow - 1) * page, overflow)  # the overflow page links to itself
    assert rowid_len == 1
    path.write_bytes(data)
    return path


def _varint_at(data: bytes | bytearray, pos: int) -> tuple[int, int]:
    value = 0
    for i in range(9):
        byte = data[pos + i]
        if i == 8:
            return (value << 8) | byte, 9
        value = (value << 7) | (byte & 0x7F)
        if byte < 0x80:
            return value, i + 1
    raise AssertionError


def _local(size: int, usable: int) -> int:
    max_local, min_local = usable - 35, (usable - 12) * 32 // 255 - 23
    if size <= max_local:
        return size
    local = min_local + (size - min_local) % (usable - 4)
    return local if local <= max_local else min_local


def db3_shared_overflow(records: int, chain: int) -> bytes:
    """A database image of 512-byte pages whose ``records`` /tf message records (topic id 1) all
    claim the one overflow chain of ``chain`` pages: read naively, ``records * chain`` pages."""
    page, min_local = 512, (512 - 12) * 32 // 255 - 23
    size = min_local + (page - 4) * chain  # the cell keeps ``min_local`` bytes, the chain the rest
    header = bytes([9, 0, 1, 1]) + _varint5(12 + 2 * (size - 11))  # id as rowid, topic id, time, blob
    leaf_pages = -(-records // 9)
    first_overflow = 2 + leaf_pages
    cells = [
        _varint5(size) + _varint5(i + 1) + (header + bytes([1, i % 100]) + bytes(min_local))[:min_local]
        + struct.pack(">I", first_overflow)
        for i in range(records)
    ]  # fmt: skip
    image = bytearray(page * (1 + leaf_pages + chain))
    image[:16] = b"SQLite format 3\x00"
    struct.pack_into(">HBBBBBB", image, 16, page, 1, 1, 0, 64, 32, 32)
    for number in range(2, 2 + leaf_pages):
        base, mine = (number - 1) * page, cells[(number - 2) * 9 : (number - 1) * 9]
        image[base] = 0x0D
        struct.pack_into(">H", image, base + 3, len(mine))
        end = base + page
        for k, cell in enumerate(mine):
            end -= len(cell)
            image[end : end + len(cell)] = cell
            struct.pack_into(">H", image, base + 8 + 2 * k, end - base)
    for k in range(chain):  # each overflow page links to the next, the last to none
        struct.pack_into(">I", image, (first_overflow + k - 1) * page, first_overflow + k + 1 if k + 1 < chain else 0)
    return bytes(image)
