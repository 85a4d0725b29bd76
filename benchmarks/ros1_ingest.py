"""Transforms per second of ``BagReader`` on ROS1 bags of a 17-frame robot recorded 600 s (252k transforms).

Run: ``python3 benchmarks/ros1_ingest.py [--images]``; bags are written once under /tmp/tftools-bench.
Prints figures, asserts nothing. ``--images`` adds a 640x480 mono camera at 10 Hz (1.8 GB of the
uncompressed bag; those bags are removed afterwards): every chunk then holds images and transforms.
"""

from __future__ import annotations

import argparse
import math
import struct
from pathlib import Path

from rosbags.rosbag1 import Writer
from timing import read_whole, rosbags_transforms, timed

NS = 1_000_000_000
START = 1_700_000_000 * NS
SECONDS = 600
OUT = Path("/tmp/tftools-bench")
TF_DEFINITION = "geometry_msgs/TransformStamped[] transforms"
ARM = [f"arm_link{i}" for i in range(1, 7)]
PUBLISHERS = [  # callerid, Hz, (parent, child) pairs
    ("/amcl", 10, [("map", "odom")]),
    ("/ekf_localization", 50, [("odom", "base_footprint")]),
    ("/robot_state_publisher", 30, [("base_link", "left_wheel"), ("base_link", "right_wheel")]),
    ("/arm/robot_state_publisher", 50, list(zip(["arm_base", *ARM[:-1]], ARM, strict=True))),
]
STATIC = [("base_footprint", "base_link"), ("base_link", "laser"), ("base_link", "imu_link"),
          ("base_link", "camera_link"), ("camera_link", "camera_optical_frame"), ("base_link", "arm_base"),
          ("arm_link6", "gripper")]  # fmt: skip


def tf_message(stamp: int, pairs: list[tuple[str, str]], phase: float) -> bytes:
    sec, nsec = divmod(stamp, NS)
    parts = [struct.pack("<I", len(pairs))]
    for i, (parent, child) in enumerate(pairs):
        angle = 0.3 * math.sin(stamp / NS + phase + i)
        parts.append(struct.pack("<III", 0, sec, nsec))
        for name in (parent, child):
            parts.append(struct.pack("<I", len(name)) + name.encode())
        parts.append(struct.pack("<7d", 0.1 * i, 0.0, 0.05, 0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2)))
    return b"".join(parts)


def messages(images: bool) -> list[tuple[int, str, str, bytes]]:
    """(record time, topic, callerid, payload) in record order."""
    out = [(START + 1_000_000, "/tf_static", "/robot_state_publisher", tf_message(START, STATIC, 0.0))]
    for callerid, hz, pairs in PUBLISHERS:
        period = NS // hz
        for k, stamp in enumerate(range(START + period // 3, START + SECONDS * NS, period)):
            out.append((stamp + 1_000_000 + (k * 7919) % 3_000_000, "/tf", callerid, tf_message(stamp, pairs, hz)))
    if images:
        image = struct.pack("<III", 0, 0, 0) + struct.pack("<I", 0) + bytes(640 * 480)
        out += [(t, "/camera/image_raw", "/camera", image) for t in range(START, START + SECONDS * NS, NS // 10)]
    return sorted(out, key=lambda m: m[0])


def write(path: Path, compression: str, images: bool) -> Path:
    if path.exists():
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    writer = Writer(path)
    if compression != "none":
        writer.set_compression(Writer.CompressionFormat[compression.upper()])
    with writer:
        connections = {}
        for record_time, topic, callerid, payload in messages(images):
            if (topic, callerid) not in connections:
                msgtype = "sensor_msgs/msg/Image" if "image" in topic else "tf2_msgs/msg/TFMessage"
                definition = "uint8[] data" if "image" in topic else TF_DEFINITION
                connections[(topic, callerid)] = writer.add_connection(
                    topic, msgtype, msgdef=definition, md5sum="0" * 32, callerid=callerid
                )
            writer.write(connections[(topic, callerid)], record_time, payload)
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--images", action="store_true", help="add a camera topic")
    images = parser.parse_args().images
    suffix = "_images" if images else ""
    for compression in ("none", "lz4", "bz2"):
        bag = write(OUT / f"robot_600s_{compression}{suffix}.bag", compression, images)
        size = bag.stat().st_size / 1e6
        timed(f"BagReader, {compression} ({size:.0f} MB)", lambda bag=bag: len(read_whole([bag]).transforms))
    bag = OUT / f"robot_600s_none{suffix}.bag"
    timed("rosbags' reader and deserializer, none", lambda: rosbags_transforms(bag), repeat=1)
    if images:
        for big in OUT.glob("*_images.bag"):
            big.unlink()


if __name__ == "__main__":
    main()
