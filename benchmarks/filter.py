"""``tfx filter``'s replay at scale: a 1-hour recording with 10 sensor streams (about 2 million stamped messages).

Builds the benchmark robot's tf for an hour straight into a buffer (no bag: only the replay is timed), and ten
streams of stamped messages at 10 to 200 Hz on frames along the robot's chains, each arriving a few ms after its
stamp; then times ``filter_streams`` into ``odom`` (every message's fate, the per-stream figures and the
suggested settings). Prints the figures; asserts nothing.

    .venv/bin/python benchmarks/filter.py [--minutes 60]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.buffer import Buffer
from tftools.sources.contents import StampedMessages

NS = 1_000_000_000
MS = 1_000_000
#: (topic, frame, Hz, arrival delay in ms): ten sensors of a mobile manipulator.
STREAMS = [
    ("/scan", "laser", 40, 12), ("/scan_rear", "laser", 40, 30), ("/imu", "imu_link", 200, 1),
    ("/camera/image_raw", "camera_optical_frame", 30, 40), ("/camera/depth", "camera_optical_frame", 30, 45),
    ("/points", "laser", 10, 80), ("/wheel_odom", "base_link", 100, 3), ("/gripper/force", "gripper", 100, 2),
    ("/arm/camera", "arm_link6", 15, 35), ("/sonar", "base_link", 20, 5),
]  # fmt: skip
#: The robot: (parent, child, Hz) moving edges, then static ones.
MOVING = [
    ("map", "odom", 10),
    ("odom", "base_link", 50),
    ("base_link", "arm_base", 100),
    ("arm_base", "arm_link6", 100),
]
STATIC = [("base_link", "laser"), ("base_link", "imu_link"), ("base_link", "camera_optical_frame"),
          ("arm_link6", "gripper")]  # fmt: skip


def robot(seconds: int) -> Buffer:
    builder = BatchBuilder()
    for parent, child in STATIC:
        builder.add(parent, child, 0, (0.1, 0.0, 0.2), (0.0, 0.0, 0.0, 1.0), static=True, record_time=MS)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    for parent, child, hz in MOVING:
        stamps = np.arange(seconds * hz, dtype=np.int64) * (NS // hz)
        n = len(stamps)
        angle = np.linspace(0.0, 100.0, n)
        rotations = np.stack([np.zeros(n), np.zeros(n), np.sin(angle / 2), np.cos(angle / 2)], axis=1)
        translations = np.stack([np.linspace(0, 100, n), np.zeros(n), np.zeros(n)], axis=1)
        buffer.insert(
            TransformBatch(
                [parent, child], ["/node"], np.zeros(n, np.int32), np.ones(n, np.int32), stamps,
                translations, rotations, np.zeros(n, bool), stamps + 2 * MS,
            )
        )  # fmt: skip
    return buffer


def streams(seconds: int) -> list[StampedMessages]:
    out = []
    for topic, frame, hz, delay in STREAMS:
        stamps = np.arange(1, seconds * hz, dtype=np.int64) * (NS // hz) + 3 * MS
        out.append(
            StampedMessages(topic, "sensor", stamps + delay * MS, stamps, np.zeros(len(stamps), np.int32), [frame])
        )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=60.0)
    seconds = round(parser.parse_args().minutes * 60)
    started = time.perf_counter()
    buffer, data = robot(seconds), streams(seconds)
    built = time.perf_counter() - started
    messages = sum(len(s) for s in data)
    best = float("inf")
    for _ in range(3):
        started = time.perf_counter()
        report = filter_streams(buffer, data, FilterQuery(target="odom"))
        best = min(best, time.perf_counter() - started)
    waited = sum(s.later for s in report.streams)
    print(f"filter: {seconds / 60:g} min, {len(data)} streams, {messages:,} messages, tf built in {built:.1f} s")
    print(f"filter: replay into odom {best:.2f} s (fastest of 3), {best / messages * 1e9:.0f} ns per message; "
          f"{waited:,} waited")  # fmt: skip


if __name__ == "__main__":
    main()
