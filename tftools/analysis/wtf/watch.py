"""``tfx wtf --watch``: a live system checked again and again over a sliding window of what it said, the
checks of a bag (``check``) on each window, and its health (``analysis.wtf.health``) told once a second."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Collection
from dataclasses import dataclass

import numpy as np

from tftools.analysis.edges import TimeWindow, edge_stats
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import BagReport, check
from tftools.analysis.wtf.health import Status, statuses
from tftools.analysis.wtf.jumps import NEIGHBOURS
from tftools.analysis.wtf.query import CHECK_DEFAULTS, CheckQuery
from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.time import from_sec
from tftools.sources.live.base import LiveSource
from tftools.sources.live.capture import Heard, heard_recording
from tftools.sources.live.time_jump import TimeJump, watch_jumps
from tftools.sources.ticker import tick_every

#: The window re-checked by default (s): long enough for the gap and stale thresholds' ten periods of a
#: 1 Hz edge, short enough that a problem gone is soon said so.
DEFAULT_WINDOW = 10.0

#: Edges remembered as heard once, to say them STALE when they stop (bounded as a live source's frames).
MAX_EDGES = 20_000


@dataclass(frozen=True)
class Health:
    """One re-check: its report, and the statuses it makes at ``now`` (ns, the source's clock)."""

    now: int
    report: BagReport
    statuses: list[Status]


class Window(Heard):
    """The transforms a live source said over the last ``window`` ns of its clock, the static ones for
    ever (the latest of each child: /tf_static is said once), fed from the source's thread. A jump back
    of the clock forgets the dynamic ones, as a tf2 listener clears its buffer."""

    def __init__(self, window: int) -> None:
        super().__init__(None)
        self.window = window
        self._last_heard: dict[tuple[str, str], int] = {}  # dynamic edges heard, and when last

    def forget_dynamic(self, jump: TimeJump) -> None:
        with self._lock:
            self._last_heard.clear()
        super().forget_dynamic(jump)

    def take(self, now: int) -> tuple[TransformBatch, int, dict[tuple[str, str], int]]:
        """What was heard over ``[now - window, now]`` (and the statics), where that span begins (or
        where the hearing began, if later), and the dynamic edges heard before but not in it."""
        with self._lock:
            merged = concat_batches(self._batches)
            cutoff = now - self.window
            keep = (merged.record_time >= cutoff) | _latest_static(merged)
            kept = take_rows(merged, np.flatnonzero(keep))
            self._batches = [kept] if len(kept) else []
            self._remember(kept)
            heard = _edges(take_rows(kept, np.flatnonzero(~kept.static)))
            gone = {edge: last for edge, last in self._last_heard.items() if edge not in heard}
            return kept, max(self._begin, cutoff), gone

    def _remember(self, batch: TransformBatch) -> None:
        for edge, last in _edges(take_rows(batch, np.flatnonzero(~batch.static))).items():
            if edge in self._last_heard or len(self._last_heard) < MAX_EDGES:
                self._last_heard[edge] = max(last, self._last_heard.get(edge, 0))


def _latest_static(batch: TransformBatch) -> np.ndarray:
    """The rows that are each static child's latest."""
    keep = np.zeros(len(batch), bool)
    rows = np.flatnonzero(batch.static)
    if len(rows):
        children = batch.child[rows][::-1]
        _, first = np.unique(children, return_index=True)
        keep[rows[::-1][first]] = True
    return keep


def _edges(batch: TransformBatch) -> dict[tuple[str, str], int]:
    """Each parent -> child pair of ``batch`` (names as received) and its latest record time."""
    if not len(batch):
        return {}
    pairs = np.stack([batch.parent, batch.child], axis=1)
    unique, inverse = np.unique(pairs, axis=0, return_inverse=True)
    latest = np.zeros(len(unique), np.int64)
    np.maximum.at(latest, inverse.reshape(-1), batch.record_time)
    names = batch.frame_names
    return {(names[p], names[c]): int(t) for (p, c), t in zip(unique.tolist(), latest.tolist(), strict=True)}


def check_window(
    source: LiveSource,
    window: Window,
    query: CheckQuery = CHECK_DEFAULTS,
    hardware_id: str = "tf",
) -> Health:
    """``check`` of what ``window`` holds now, with ``query``, and its statuses."""
    now = source.clock.now()
    transforms, begin, gone = window.take(now)
    recording = heard_recording(source, transforms, begin, now, query.semantics)
    report = check(recording, query)
    report.findings = [f for f in report.findings if _settled(f, transforms)]
    start = max(begin, now - window.window)
    edges = edge_stats(recording.buffer, TimeWindow(start, now, by_record_time=True, timeline=recording.timeline))
    ignore: Collection[str] = query.ignore
    said = statuses(
        report,
        edges,
        now,
        ignore=ignore,
        gone=gone,
        window=window.window,
        hardware_id=hardware_id,
        delays_unavailable=recording.timeline.delays_unavailable,
    )
    return Health(now, report, said)


#: Checks that judge a sample by the samples either side of it (``jumps.NEIGHBOURS`` each way).
_BY_NEIGHBOURS = frozenset({"jump", "map_corrections"})


def _settled(finding: Finding, transforms: TransformBatch) -> bool:
    """Whether ``finding`` stands on what the window holds: a step is judged by its edge's motion either
    side of it, which a window cuts at both ends (the newest step's later samples have not come yet; the
    oldest's earlier ones are gone): one with fewer than ``NEIGHBOURS`` samples on a side is left to the
    next windows, which see it whole (a bag's check sees every step whole)."""
    if finding.code not in _BY_NEIGHBOURS or len(finding.frames) < 2:
        return True
    names = list(transforms.frame_names)
    parent, child = finding.frames[0], finding.frames[1]
    if parent not in names or child not in names:
        return True
    edge = (transforms.parent == names.index(parent)) & (transforms.child == names.index(child)) & ~transforms.static
    stamps = transforms.stamp[edge]
    before = int(np.count_nonzero(stamps < finding.first_time))  # the first step's start and those before it
    after = int(np.count_nonzero(stamps > finding.last_time))
    return before > NEIGHBOURS and after >= NEIGHBOURS


def watch_live(
    source: LiveSource,
    on_health: Callable[[Health], object],
    window: float = DEFAULT_WINDOW,
    query: CheckQuery = CHECK_DEFAULTS,
    *,
    period: float = 1.0,
    duration: float | None = None,
    hardware_id: str = "tf",
) -> None:
    """Listen to ``source`` (not yet started; closed on return) and give ``on_health`` the check of the
    last ``window`` seconds every ``period`` seconds of the source's clock, until ``duration`` wall seconds
    pass (None: for ever), the source ends, or Ctrl-C."""
    held = Window(from_sec(window))
    with source:
        source.start(watch_jumps(source, held.keep, held.forget_dynamic))
        held.since(source.clock.now())

        def tick() -> None:
            on_health(check_window(source, held, query, hardware_id))

        with contextlib.suppress(KeyboardInterrupt):
            count = None if duration is None else max(1, round(duration / period))  # a simulated clock's
            tick_every(period, tick, count=count, duration=duration, stop=lambda: source.finished, clock=source.clock)
