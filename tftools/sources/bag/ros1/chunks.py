"""A chunk's message records: where they begin, and what their headers say, read in bulk."""

from __future__ import annotations

from array import array

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.ros1.records import (
    OP_CONNECTION,
    OP_MESSAGE,
    ByteSpan,
    Connection,
    read_connection,
    read_record,
    u32,
    value_at,
)
from tftools.sources.bag.spans import Spans, joined, selects_all
from tftools.sources.codecs import _wire
from tftools.sources.codecs.gather import distinct, u32_at

_MIN_HEADER = 4 + len("op=") + 1  # a record header holds at least its op field


def walk(data: ByteSpan, chunk: int) -> Spans:
    """The records in ``data``, chunk ``chunk``'s records, up to their end or one cut short (``in_chunk``)."""
    starts = array("q")  # 8 bytes a record, not a Python int's 36: a chunk may hold millions
    pos, limit = 0, len(data)
    try:
        while pos + 8 <= limit:
            header_length = u32(data, pos)
            if header_length < _MIN_HEADER:
                break
            header_end = pos + 4 + header_length
            record_end = header_end + 4 + u32(data, header_end) if header_end + 4 <= limit else limit + 1
            if record_end > limit:
                break
            starts.append(pos)
            pos = record_end
    except DamageError:
        pass
    return in_chunk(np.frombuffer(starts, np.int64).copy() if starts else np.zeros(0, np.int64), chunk, limit)


def in_chunk(offsets: Int64Array, chunk: int, size: int) -> Spans:
    """The records at ``offsets`` of chunk ``chunk``'s data (``size`` bytes), each of them reaching
    at most to its end (channels and times unknown until ``locate`` reads them)."""
    unknown = np.full(len(offsets), -1, np.int64)
    return Spans(
        np.full(len(offsets), chunk, np.int64), offsets, unknown, unknown, offsets, np.full(len(offsets), size)
    )


def locate(
    data: bytes | memoryview, records: Spans, *, follow: bool, cut: BoolArray | None = None
) -> tuple[Spans, list[Connection], str]:
    """The message records among ``records`` (each at ``start`` in ``data``, within ``end``),
    with their connections, times and payloads; the connection records met; why the first that
    is not a message is not. With ``follow``, connection records before a message are stepped
    over (index entries may point at them). Records ``cut`` were read only so far (for their
    message's header): their payload ends at ``end``, not where their record says.

    Records are recognised in bulk by their header's layout, learnt from the first record of
    each header length; any other record is read one by one.
    """
    raw = np.frombuffer(data, np.uint8)
    limit = np.minimum(records.end, len(raw))
    cut = np.zeros(len(records), bool) if cut is None else cut
    if len(records) and records.start[0] >= 0 and records.start[0] + 8 <= limit[0]:
        # Every record laid out as the first, as recorders write them: one pass, no header's length
        # gathered first (a miss to memory a record, as the match's own).
        template = _Template.learn(data, int(records.start[0]))
        if template is not None:
            start, limits, cuts = (np.ascontiguousarray(a) for a in (records.start, limit, cut))
            hit, values = template.match(raw, start, limits, cuts)
            if hit.all():
                return Spans(records.chunk, records.offset, *values), [], ""
    inside = (records.start >= 0) & (records.start + 8 <= limit)
    if inside.all():
        header_len = u32_at(raw, records.start)
    else:
        header_len = np.full(len(records), -1, np.int64)
        header_len[inside] = u32_at(raw, records.start[inside])
    found = np.zeros(len(records), bool)
    header = np.zeros((4, len(records)), np.int64)  # conn, time, data start and end of each
    for length in distinct(header_len[header_len >= 0]).tolist():
        rows = np.flatnonzero(header_len == length)
        template = _Template.learn(data, int(records.start[rows[0]]))
        if template is None:
            continue
        if selects_all(rows, len(records)):
            hit, values = template.match(raw, np.ascontiguousarray(records.start), limit, np.ascontiguousarray(cut))
            if hit.all():  # every record a message of one layout (as recorders write them): no gathers
                return Spans(records.chunk, records.offset, *values), [], ""
        else:
            hit, values = template.match(raw, records.start[rows], limit[rows], cut[rows])
        hit_rows = rows[hit]
        found[hit_rows] = True
        header[:, hit_rows] = values
    messages = Spans(records.chunk[found], records.offset[found], *header[:, found])
    slow, slow_cut = records.rows(~found), cut[~found].tolist()
    connections: list[Connection] = []
    more: list[tuple[int, ...]] = []
    first_error = ""
    for row, end in enumerate(limit[~found].tolist()):
        try:
            message = _message_at(data, int(slow.start[row]), end, connections, follow, cut=slow_cut[row])
        except DamageError as e:
            first_error = first_error or str(e)
            continue
        if message is not None:
            skipped, *fields = message
            more.append((int(slow.chunk[row]), int(slow.offset[row]) + skipped, *fields))
    if more:
        messages = joined([messages, Spans(*np.array(more, np.int64).T)])
        messages = messages.rows(np.lexsort((messages.offset, messages.chunk)))  # in file order
    return messages, connections, first_error


def _message_at(
    data: ByteSpan, pos: int, end: int, connections: list[Connection], follow: bool, *, cut: bool = False
) -> tuple[int, int, int, int, int] | None:
    """(bytes stepped over, conn, time, data start, data end) of the message record at ``pos``;
    None for a connection record (noted in ``connections``) when not following. A message ``cut``
    (read for its header) ends at ``end``."""
    at = pos
    while True:
        record = read_record(data, at, end)
        if record.op == OP_MESSAGE and cut:
            return at - pos, record.uint("conn"), record.time("time"), record.data_start, min(record.data_end, end)
        if record.data_end > end:
            raise DamageError(f"the record at byte {at} of the chunk is cut short")
        if record.op == OP_MESSAGE:
            return at - pos, record.uint("conn"), record.time("time"), record.data_start, record.data_end
        if record.op != OP_CONNECTION:
            raise DamageError(f"the record at byte {at} of the chunk has op {record.op}, not a message")
        connections.append(read_connection(data, record))
        if not follow:
            return None
        at = record.data_end


class _Template:
    """The bytes of a message record header of one length, and where conn and time sit in them."""

    def __init__(self, header: bytes, conn_at: int, time_at: int) -> None:
        self.header = header
        self.conn_at = conn_at
        self.time_at = time_at

    @classmethod
    def learn(cls, data: ByteSpan, pos: int) -> _Template | None:
        """The template of the message record at ``pos``; None when it is something else."""
        try:
            record = read_record(data, pos)
        except DamageError:
            return None
        fields = record.fields
        if record.op != OP_MESSAGE or len(fields.get("conn", b"")) != 4 or len(fields.get("time", b"")) != 8:
            return None
        header = bytes(data[pos + 4 : record.data_start - 4])
        return cls(header, value_at(header, "conn"), value_at(header, "time"))

    def match(
        self, raw: UInt8Array, offsets: Int64Array, limit: Int64Array, cut: BoolArray
    ) -> tuple[BoolArray, tuple[Int64Array, ...]]:
        """Which records have this layout and end within ``limit`` (or, ``cut``, are read up to it);
        their conn, time, data start and end (compiled: one pass over the records)."""
        hit, *values = _wire.match_records(raw, offsets, limit, cut, self.header, self.conn_at, self.time_at)
        return hit, tuple(values)
