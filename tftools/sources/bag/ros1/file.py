"""One ROS1 bag being read: its bytes, the connections wanted, the messages found, the damage met."""

from __future__ import annotations

import numpy as np

from tftools.core.arrays import BoolArray
from tftools.sources.bag.contents import ProgressCallback, RecordWindow
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.ros1.records import Chunk, Connection, RecordReader
from tftools.sources.bag.scan import FileScan
from tftools.sources.bag.spans import Spans, selects_all
from tftools.sources.bag.unpack import Budget, Unpacked, unpack
from tftools.sources.codecs.select import ClockCodec, HeaderCodec, Wanted, copied, select
from tftools.sources.contents import Recorded
from tftools.sources.storage.source import ByteSource, FileBytes


class Damage:
    """Chunks (or bytes between them) that could not be read: how many, the first, messages lost."""

    __slots__ = ("doubtful", "first", "lost", "lost_known", "places", "spans")

    def __init__(self) -> None:
        self.places = 0
        self.first = ""
        self.lost = 0
        self.lost_known = True  # the index says how many messages each chunk held
        self.doubtful = False  # messages were read of a chunk decompressed past damage
        self.spans: list[tuple[int, int]] = []  # record-time spans of the damaged chunks

    def note(
        self, pos: int, reason: str, lost: int | None, *, doubtful: bool = False, span: tuple[int, int] | None = None
    ) -> None:
        """Damage at byte ``pos``; ``span``: the record times of the chunk it is in, when the index gives them."""
        self.doubtful |= doubtful
        if span is not None:
            self.spans.append(span)
        self.places += 1
        self.first = self.first or f"first at byte {pos}: {reason}"
        if lost is None:
            self.lost_known = False
        else:
            self.lost += lost


class BagFile:
    """A ROS1 bag's bytes (``buf``, ``source``'s buffer), being read for the messages ``wanted``
    recorded in ``window``: into ``scan``, its description and transform, clock and stamped messages."""

    def __init__(
        self,
        name: str,
        buf: FileBytes,
        source: ByteSource,
        wanted: Wanted,
        progress: ProgressCallback,
        window: RecordWindow | None = None,
    ) -> None:
        self.name = name
        self.buf = buf
        self.source = source  # the file ``buf`` maps, to read chunks from without mapping their pages
        self.size = len(buf)
        self.records = RecordReader(buf)
        self.budget = Budget(self.size)  # what its chunks may decompress to in all
        self.wanted = wanted
        self.progress = progress
        self.scan = FileScan(MessageSet(window=window))
        self.damage = Damage()
        self.transform_messages = 0  # wanted, found (clock messages are not counted)
        self.channels: dict[int, int] = {}  # connection id -> message set channel, of those wanted
        self._met: set[int] = set()  # connection ids
        self._clocks: set[int] = set()  # message set channels of clock connections
        self.headed: set[int] = set()  # connection ids read for their messages' headers only

    def connect(self, connection: Connection) -> None:
        """A connection record met: its topic described, and read if it is wanted."""
        if connection.id in self._met:
            return
        self._met.add(connection.id)
        self.scan.topics.setdefault(connection.topic, connection.type)
        codec, unread = (
            select(connection.topic, connection.type, "ros1", self.wanted, connection.definition)
            if self.wanted.copy is None
            else (copied(_recorded(connection), self.wanted.copy), None)
        )
        self.scan.note_skipped(unread)
        if codec is not None:
            channel = self.scan.messages.channel(
                connection.topic, codec, publisher=connection.callerid, tie=connection.id
            )
            self.channels[connection.id] = channel
            if isinstance(codec, ClockCodec):
                self._clocks.add(channel)
            if isinstance(codec, HeaderCodec):
                self.headed.add(connection.id)

    @property
    def transform_connections(self) -> set[int]:
        """The ids of the connections met whose messages are read for their transforms."""
        return {c for c, channel in self.channels.items() if c not in self.headed and channel not in self._clocks}

    def add(self, data: bytes | memoryview, messages: Spans) -> BoolArray:
        """Keep the wanted ones of ``messages`` (their payloads copied out of ``data``); returns which."""
        channel = messages.looked_up(self.channels)
        kept = channel >= 0
        every = selects_all(kept, len(kept))
        self.scan.messages.add_spans((channel if every else channel[kept]).astype(np.int32), messages.rows(kept), data)
        self.transform_messages += int(np.count_nonzero(kept & ~np.isin(channel, list(self._clocks))))
        return kept

    def release(self, start: int, end: int) -> None:
        """A chunk has been read (the messages wanted are copied out by then): what holds its bytes
        may let go (a local file's map its pages, which then count towards the page cache, not this
        process's resident memory)."""
        self.source.release(start, end)

    def unpacked(self, chunk: Chunk, end: int) -> Unpacked:
        """The chunk's data up to ``end``, uncompressed: read from the source, not ``buf`` (faulting in
        the pages of a mapping costs more than the copy a read makes, and they would count as resident)."""
        return unpack(chunk.compression, self.source.read(chunk.data_start, end), chunk.size, self.budget)

    @property
    def counted(self) -> str:
        """What ``transform_messages`` counts, said: sensor data read for its headers is counted with the tf."""
        return "transform messages" if self.wanted.headers is None else "messages of the topics read"

    def note_damage(self) -> None:
        d = self.damage
        if not d.places:
            return
        self.scan.damaged += d.spans
        what = "a damaged part" if d.places == 1 else f"{d.places} damaged parts"
        kind = self.counted
        if d.lost_known:
            lost = f"{d.lost} {kind} lost"
        else:
            lost = f"at least {d.lost} {kind} lost" if d.lost else f"the {kind} there are lost"
        doubt = f"; of a damaged chunk, the {kind} read may hold a wrong value" if d.doubtful else ""
        if d.lost_known and not d.lost:  # a chunk decompressed past damage, every message of it still parsing
            self.scan.note_problem(f"{self.name}: {what} found ({d.first}); no {kind} lost{doubt}")
            return
        self.scan.note_problem(f"{self.name}: {what} could not be read ({d.first}); {lost}{doubt}")


def _recorded(c: Connection) -> Recorded:
    return Recorded(c.topic, c.type, "ros1", c.definition, c.md5sum, c.callerid, c.latching)
