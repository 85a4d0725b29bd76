"""A sensor's frame that no transform names, beside a frame of the tree named like it that no data is in: one
sensor, two names (the driver's frame_id and its mount's link), the commonest reason a mount seems missing."""

from __future__ import annotations

import re
from collections.abc import Collection, Sequence

from tftools.core.frames import frame_name


def namesakes(missing: Sequence[str], tree_frames: Collection[str], data_frames: Collection[str]) -> dict[str, str]:
    """For each of the ``missing`` frames (as the data names them), the one frame of the tree that holds its name as
    a word ('laser' in 'base_laser', 'imu' in 'imu_frame') and that none of the ``data_frames`` is: its mount under
    another name. Those with none, or several, left out: a guess said only where one frame fits."""
    found = {}
    for frame in missing:
        name = frame_name(frame).lower()
        alike = [f for f in tree_frames if f not in data_frames and f.lower() != name and name in _words(f)]
        if name and len(alike) == 1:
            found[frame] = alike[0]
    return found


def _words(frame: str) -> list[str]:
    return re.split(r"[_/.\-]+", frame.lower())


def renamed_in_words(pairs: Sequence[tuple[str, str, str | None]]) -> str:
    """What to do where data in a frame no transform names has a namesake in the tree: ``pairs`` of the data's frame,
    the tree's frame named like it, and that frame's parent (None: a root)."""
    said = [
        f"'{mount}'" + (f" ({parent} -> {mount})" if parent else "") + f" for '{frame}'"
        for frame, mount, parent in pairs
    ]
    shown = ", ".join(said[:3]) + (f" and {len(said) - 3} more" if len(said) > 3 else "")
    return (
        f"the tree has {shown}, a frame named like it that no data is in: where it is this sensor's mount, the two "
        "names differ; set the driver's frame_id parameter to the tree's name, or name the mount (the URDF's link, "
        "static_transform_publisher's child) as the data does"
    )
