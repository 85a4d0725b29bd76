"""A robot whose problems a person should see in ``tfx report``, in all three bag formats: map -> odom
pauses, odom -> base_link stops early, base_link is re-parented to map for a second, a laser's scans
are lost once its tf stops, and a camera names a frame that is not in the tree."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from tests.analysis.wtf_scenes import START, amcl, ekf, periodic, with_extra
from tests.bags import TfMessage
from tests.cli.test_filter import image, scan, sensor_bags
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

MS = 1_000_000
#: Where each problem is, in seconds after START.
GAP = (3.0, 5.0)
REPARENTED = (5.0, 6.0)
EKF_STOPS = 8.0


def troubled_tf() -> list[TfMessage]:
    def rogue(stamp: int) -> list[Transform]:
        return [Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "map", "base_link")]

    return with_extra(
        periodic("/rogue", 10, rogue, start=REPARENTED[0], end=REPARENTED[1], phase=0.013),
        amcl=amcl(skip=GAP),
        ekf=ekf(end=EKF_STOPS),
    )


def troubled_sensors(store: Any) -> list[tuple[str, str, int, object]]:
    """(topic, type, record time, message): a laser at 20 Hz in frame laser, a camera at 2 Hz in 'camra'."""
    out: list[tuple[str, str, int, object]] = []
    for i in range(1, 200):
        stamp = START + i * 50 * MS + 7 * MS
        out.append(("/scan", "sensor_msgs/msg/LaserScan", stamp + 5 * MS, scan(store, "laser", stamp)))
    for i in range(1, 20):
        stamp = START + i * NS_PER_S // 2
        out.append(("/camera/image_raw", "sensor_msgs/msg/Image", stamp + 3 * MS, image(store, "camra", stamp)))
    return out


def troubled_bags(folder: Path) -> dict[str, Path]:
    """The troubled robot as a ROS1 bag and its ROS2 copies: {"ros1": ..., "db3": ..., "mcap": ...}."""
    return sensor_bags(folder, troubled_tf(), troubled_sensors)


def page_data(page: Path) -> list[dict[str, Any]]:
    """The data each readable recording's section of a ``tfx report`` page carries for its plots."""
    text = page.read_text(encoding="utf-8")
    found = re.findall(r'<script type="application/json" class="report-data">(.*?)</script>', text, flags=re.S)
    return [json.loads(data) for data in found]
