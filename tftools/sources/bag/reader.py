"""``BagReader``: one recording (a bag, or a split one's files) opened once, its indexes read once,
read whole or window after window."""

from __future__ import annotations

import importlib
import os
from collections.abc import Sequence
from contextlib import ExitStack
from typing import Protocol

from tftools.sources.bag.contents import (
    BagContents,
    ProgressCallback,
    RecordWindow,
    in_record_order,
    in_turn,
    merged_clock,
)
from tftools.sources.bag.formats import sniff
from tftools.sources.bag.scan import FileRead, placed_among, record_times
from tftools.sources.bag.strays import TimeRuns, leave_out_of_window, leave_out_strays
from tftools.sources.codecs.select import Wanted
from tftools.sources.contents import DEFAULT_TOPICS, MessageSink, StampedRead, concat_sent
from tftools.sources.errors import BagError
from tftools.sources.headers import merged
from tftools.sources.storage import open_files
from tftools.sources.storage.source import Files


class FormatFile(Protocol):
    """A file (or ROS 2 bag directory) of one format, open: its index read once, read as often as asked."""

    def read(self, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None = None) -> FileRead: ...

    def close(self) -> None: ...


class BagReader:
    """The recording at ``paths`` (several: a split one's files, merged by record time), a context
    manager: each file is opened, recognised and its index or summary read once, on entering; ``read``
    then reads the transforms on ``topics`` (default ``/tf`` and ``/tf_static``), the recorded clock
    (a rosgraph_msgs/Clock topic, whatever ``topics`` are) and, with ``headers``, the headers of the
    sensor data on those topics (none named: of every topic whose messages start with a header), of the
    whole recording or of one window of record time, as often as asked (``header_limit``: of each topic's first
    messages at most, per publisher where the recording says it). With ``copy``, nothing is
    decoded: every message is handed to it as recorded, with its channel (``Recorded``), in the
    files' order (a copy of the recording).

    A path may be a URL (``s3://``, ``gs://``, ``az://``, ``http(s)://``; ``tftools[fleet]``): only
    the ranges the readers need are fetched, once while the reader is open, and each
    ``BagFileInfo.fetched`` says how much. Raises ``BagError`` for a path that cannot be read at all;
    a damaged file is read as far as it goes, and what was lost is listed in its ``BagFileInfo.problems``.
    """

    def __init__(
        self,
        paths: Sequence[str | os.PathLike[str]],
        topics: Sequence[str] | None = None,
        *,
        headers: Sequence[str] | None = None,
        whole: Sequence[str] = (),
        copy: MessageSink | None = None,
        header_limit: int | None = None,
    ) -> None:
        self.paths = [os.fspath(p) for p in paths]
        headed = None if headers is None else tuple(headers)
        self.wanted = Wanted(tuple(topics) if topics else DEFAULT_TOPICS, headed, tuple(whole), copy, header_limit)
        self._stack = ExitStack()
        self._files: list[_Opened] = []
        self._runs: list[TimeRuns] = []  # per file, its windows' record times, to learn its strays
        self._kept: list[tuple[tuple[int, int], int, str] | None] | None = None  # once learnt (``strays_learnt``)

    def __enter__(self) -> BagReader:
        try:
            self._files = [self._open(location) for location in self.paths]
        except BaseException:
            self._stack.close()
            raise
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def close(self) -> None:
        self._files = []
        self._stack.close()

    @property
    def topics(self) -> tuple[str, ...]:
        return self.wanted.topics

    def read(self, window: RecordWindow | None = None, progress: ProgressCallback | None = None) -> BagContents:
        """What the recording holds (see the class), and each file described; with a ``window``, only the
        transforms, clock and headers recorded in it (the files' indexes skip the rest; a file without
        one is read whole, and its ``windowed`` is False), each ``BagFileInfo`` still describing its
        whole file. An empty window reads only the descriptions. The headers asked for by name that
        were not read are each said in ``stamped.problems``."""
        if len(self._files) != len(self.paths):
            raise ValueError("BagReader.read outside its with block: the recording is not open")
        shares = in_turn(progress or _unreported, [opened.size for opened in self._files])
        reads = [opened.read(self.wanted, share, window) for share, opened in zip(shares, self._files, strict=True)]
        self._strays(reads, window)
        if len(reads) > 1:
            _placed_among_files(reads)
        streams = merged([stream for read in reads for stream in read.stamped])
        problems = [line for read in reads for line in read.stamped_problems]
        missing = sorted(set(self.wanted.headers or ()) - {stream.topic for stream in streams})
        kinds = {topic: kind for read in reads for topic, kind in read.info.topics.items()}
        problems += [
            f"{topic}: {kinds[topic]} messages have no header" if topic in kinds else f"{topic}: not in the recording"
            for topic in missing
        ]
        return BagContents(
            in_record_order([batch for read in reads for batch in read.batches]),
            [read.info for read in reads],
            self.topics,
            merged_clock([read.clock for read in reads]),
            StampedRead(streams, problems),
            [whole for read in reads for whole in read.whole],
            {read.info.path: read.qos for read in reads if read.qos is not None},
            concat_sent([read.sent for read in reads]),
            reads[0].room if len(reads) == 1 else None,
        )

    def strays_learnt(self) -> bool:
        """Whether, its windows each read once since it was opened, some of a file's messages lay decades from
        the rest of its own (``strays``): from then on each window's read leaves them out and says so once, as a
        whole read does (a window's read alone holds too few of a file's times to judge)."""
        self._kept = [runs.strays() for runs in self._runs] if self._runs else None
        self._runs = []
        return any(self._kept or ())

    def _strays(self, reads: Sequence[FileRead], window: RecordWindow | None) -> None:
        """The strays of ``reads`` left out (a whole read's, or a window's once learnt), or the windows' times
        gathered to learn them (``strays_learnt``)."""
        if window is None:
            for read in reads:
                leave_out_strays(read)
        elif self._kept is not None:
            for read, kept in zip(reads, self._kept, strict=True):
                if kept is not None:
                    leave_out_of_window(read, *kept, described=window.first >= window.last)
        else:
            self._runs = self._runs or [TimeRuns() for _ in reads]
            for runs, read in zip(self._runs, reads, strict=True):
                runs.add(read)

    def _open(self, location: str) -> _Opened:
        files = self._stack.enter_context(open_files(location))
        try:
            opened = _open_format(files)
        except BagError as e:
            raise e.said_of(location) if files.fetched() else e from None
        return _Opened(self._stack, files, opened)


def _placed_among_files(reads: Sequence[FileRead]) -> None:
    """Each file's stamped messages placed among every file's transforms (``scan.placed_among``)."""
    placed = placed_among([record_times(r.batches) for r in reads], [r.stamped for r in reads])
    for read, streams in zip(reads, placed, strict=True):
        read.stamped = streams


def _unreported(_done: int, _total: int) -> None:
    pass


class _Opened:
    """One path of a recording, open: its files, and its format's reader of them."""

    def __init__(self, stack: ExitStack, files: Files, opened: FormatFile) -> None:
        stack.callback(opened.close)
        self.files, self.opened = files, opened
        root = files.root
        self.size = sum(files.size(p) for p in files.listing(root)) if files.is_dir(root) else files.size(root)

    def read(self, wanted: Wanted, progress: ProgressCallback, window: RecordWindow | None) -> FileRead:
        """The format's result, said of the URL (with what was fetched) for a remote bag."""
        fetched = self.files.fetched()
        if fetched is None:
            return self.opened.read(wanted, progress, window)
        try:
            read = self.opened.read(wanted, progress, window)
        except BagError as e:
            raise e.said_of(self.files.said(e.path)) from None
        info = read.info
        info.path = self.files.said(info.path)
        info.problems = [self.files.said(line) for line in info.problems]
        info.fetched = self.files.fetched()
        return read


def _open_format(files: Files) -> FormatFile:
    """The recording opened by its format's module, imported only when a file needs it: a ROS1 user
    pays for no sqlite or MCAP code. A file's format is told by its first bytes (``sniff``)."""
    root = files.root
    fmt, source = sniff(files)
    if source is None:  # a ROS 2 bag directory, or one of its files compressed whole
        module = importlib.import_module("tftools.sources.bag.rosbag2")
        opened: FormatFile = module.Rosbag2Bag(root, files)
        return opened
    try:
        module = importlib.import_module(f"tftools.sources.bag.{fmt.module}")
        if fmt.module == "rosbag2":
            opened = module.Rosbag2Bag(root, files, source)
        else:
            opened = module.McapFile(root, source) if fmt.module == "mcap" else module.Ros1File(root, source)
    except BaseException:
        source.close()
        raise
    return opened
