"""Recordings with known publishing rates, jitter, a dropped stretch and a lagging publisher."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tests.bags import BagFormat, TfMessage, write_bag
from tftools.core.batch import BatchBuilder
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S, SimClock
from tftools.core.transform import Transform

START = 1_600_000_000 * NS_PER_S
DURATION = 30 * NS_PER_S
MS = 1_000_000


@dataclass
class Truth:
    """What one publisher of one edge really did: the stamps it sent and when each arrived."""

    parent: str
    child: str
    publisher: str
    hz: float
    stamps: list[int] = field(default_factory=list)
    records: list[int] = field(default_factory=list)

    @property
    def delays(self) -> list[int]:
        return [r - s for r, s in zip(self.records, self.stamps, strict=True)]


@dataclass
class Scene:
    messages: list[TfMessage]
    truth: dict[str, Truth]  # child frame -> truth (dynamic edges)
    static: list[tuple[str, str]]

    @property
    def start(self) -> int:
        return self.messages[0].record_time

    @property
    def end(self) -> int:
        return self.messages[-1].record_time


JITTER_SIGMA = 1 * MS  # scheduling noise of /odometry's stamps
DROP = (10 * NS_PER_S, 12_500 * MS)  # /localizer sends nothing in this stretch (after START)
LAG = (250 * MS, 40 * MS)  # /camera_driver's transforms arrive 250-290 ms late


def scene(seed: int = 3) -> Scene:
    """odom->base_link 40 Hz with stamp jitter, map->odom 20 Hz with a 2.5 s hole,
    base_link->camera 15 Hz arriving late, base_link->wheel 10 Hz, base_link->laser static."""
    rng = np.random.default_rng(seed)
    truth = {
        "base_link": Truth("odom", "base_link", "/odometry", 40),
        "odom": Truth("map", "odom", "/localizer", 20),
        "camera": Truth("base_link", "camera", "/camera_driver", 15),
        "wheel": Truth("base_link", "wheel", "/state_publisher", 10),
    }
    messages = [TfMessage("/tf_static", START, [_transform("base_link", "laser", START)], "/state_publisher")]
    for t in truth.values():
        period = round(NS_PER_S / t.hz)
        for k in range(int(DURATION // period)):
            stamp = START + 7 * MS + k * period
            if t.child == "base_link":
                stamp += int(np.clip(rng.normal(0, JITTER_SIGMA), -4 * MS, 4 * MS))
            if t.child == "odom" and DROP[0] <= stamp - START < DROP[1]:
                continue
            delay = LAG[0] + int(rng.integers(0, LAG[1])) if t.child == "camera" else int(rng.integers(1 * MS, 4 * MS))
            t.stamps.append(stamp)
            t.records.append(stamp + delay)
            messages.append(TfMessage("/tf", stamp + delay, [_transform(t.parent, t.child, stamp)], t.publisher))
    messages.sort(key=lambda m: m.record_time)
    return Scene(messages, truth, [("base_link", "laser")])


def _transform(parent: str, child: str, stamp: int) -> Transform:
    return Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, parent, child)


def scene_buffer(messages: list[TfMessage], cache_time: int | None = None) -> Buffer:
    """The messages straight into a buffer, publishers kept (as a ROS1 bag or live ROS1 does)."""
    builder = BatchBuilder()
    for m in messages:
        for t in m.transforms:
            builder.add(
                t.frame_id, t.child_frame_id, t.stamp, t.translation, t.rotation,
                static=m.topic == "/tf_static", record_time=m.record_time, authority=m.publisher,
            )  # fmt: skip
    buffer = Buffer(cache_time=cache_time, clock=SimClock(messages[-1].record_time))
    buffer.insert(builder.take())
    return buffer


#: Every bag format tftools writes and reads.
FORMATS = list(BagFormat)


def write_scene(directory: Path, fmt: BagFormat, messages: list[TfMessage]) -> Path:
    return write_bag(directory / ("scene.bag" if fmt is BagFormat.ros1 else f"scene_{fmt.value}"), messages, fmt)
