"""An MCAP file without a usable summary (a killed recording) read record by record, up to any damage."""

from __future__ import annotations

from typing import BinaryIO

from tftools.sources.bag.contents import ProgressCallback
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.mcap.records import (
    CHANNEL,
    CHUNK,
    DATA_END,
    FOOTER,
    HEADER,
    MAGIC,
    MESSAGE,
    MESSAGE_HEAD,
    RECORD,
    SCHEMA,
    Channels,
    Salvaged,
    chunk_records,
    held,
    known,
    scan_records,
)
from tftools.sources.storage.source import ByteSource

_PROGRESS_STEP = 1 << 24


def stream(source: ByteSource, channels: Channels, progress: ProgressCallback) -> None:
    """Read the records up to the end of the data or the damage, noting what is lost; ``DamageError``
    when the damage comes before anything could be read."""
    with source.stream() as f:  # every record is read
        reader, result = _Stream(f, source.size, channels), channels.result
        result.windowed = False
        damage = reader.run(progress)
    if reader.lost_chunks:
        result.note_problem(f"{reader.lost_chunks} chunks are damaged; their messages are lost")
    if reader.salvaged.chunks:
        result.note_problem(reader.salvaged.line())
    if not damage:
        return
    if not result.message_count and not reader.chunks_read:
        raise DamageError(damage)
    read = (
        f"read the {result.message_count} messages before it, up to record time {result.end / 1e9:.3f} s"
        if result.message_count
        else "no message before it could be read"
    )
    result.note_problem(f"{damage}: {read}; the rest is lost")


class _Stream:
    """Top-level records one by one; messages outside chunks are read only when wanted."""

    def __init__(self, f: BinaryIO, size: int, channels: Channels) -> None:
        self.f, self.size, self.channels = f, size, channels
        self.pos = len(MAGIC)
        self.number = 0  # of the record: orders the messages of equal record time
        self.lost_chunks = self.chunks_read = 0
        self.salvaged = Salvaged()  # damaged chunks of which some messages were read

    def run(self, progress: ProgressCallback) -> str:
        """Returns where and what the damage met is, or "" at a clean end."""
        self.f.seek(self.pos)
        reported = 0
        while True:
            head = self.f.read(RECORD.size)
            if len(head) < RECORD.size:
                return f"cut short at byte {self.size}"
            opcode, length = RECORD.unpack_from(head)
            if self.number == 0 and opcode != HEADER:
                raise DamageError("no MCAP header record")
            if not known(opcode):
                return f"damaged at byte {self.pos} (unknown record type {opcode:#04x})"
            if opcode in (FOOTER, DATA_END):
                return ""
            end = self.pos + RECORD.size + length
            if end > self.size:
                if opcode == CHUNK:
                    self._chunk(self.f.read(), partial=True)
                kind = "a chunk" if opcode == CHUNK else "a record"
                return f"cut short at byte {self.size}, inside {kind} that runs from byte {self.pos} to {end}"
            try:
                self._record(opcode, length)
            except DamageError as e:
                return f"damaged at byte {self.pos} ({e})"
            self.pos, self.number = end, self.number + 1
            if self.pos - reported >= _PROGRESS_STEP:
                progress(self.pos, self.size)
                reported = self.pos

    def _record(self, opcode: int, length: int) -> None:
        if opcode == MESSAGE:
            self._message(length)
        elif opcode in (CHUNK, SCHEMA, CHANNEL):
            content = self.f.read(length)
            if opcode == CHUNK:
                self._chunk(content, partial=False)
            else:
                self.channels.register(opcode, content)
        else:
            self.f.seek(length, 1)

    def _message(self, length: int) -> None:
        if length < MESSAGE_HEAD.size:
            raise DamageError("message record too short")
        channel_id, _, log_time, _ = MESSAGE_HEAD.unpack(self.f.read(MESSAGE_HEAD.size))
        log_time = held(log_time)
        self.channels.result.note_times(log_time, log_time, 1)
        rest = length - MESSAGE_HEAD.size
        target = self.channels.wanted.get(channel_id)
        if target is None:
            self.f.seek(rest, 1)
        else:
            self.channels.result.messages.add(target, [log_time], [self.number << 32], [self.f.read(rest)])

    def _chunk(self, content: bytes, *, partial: bool) -> None:
        """A chunk's records (of one ``partial``, cut short by the end of the file, as far as they go); a
        damaged complete chunk's as far as they still parse, noted, or counted lost when none does."""
        try:
            data, damage = chunk_records(content, self.channels.budget)
        except DamageError:
            self.lost_chunks += not partial
            self.channels.result.note_lost()
            return
        walked, read = scan_records(data, self.number, self.channels, counted=True)
        damaged = damage or walked
        if partial or not damaged or read:
            self.chunks_read += 1
        if partial or not damaged:
            return
        self.channels.result.note_lost()
        if read:
            self.salvaged.note(damaged, read, None)
        else:
            self.lost_chunks += 1
