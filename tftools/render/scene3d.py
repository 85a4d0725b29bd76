"""The report's 3D view: every frame's poses over time (``analysis.report.poses``) as the page's data, and the
element ``page/scene3d.js`` draws them in with three.js (vendored: ``page/vendor/three.iife.min.js``)."""

from __future__ import annotations

import html
from typing import Any

import numpy as np

from tftools.analysis.report.poses import MAX_FRAMES, FramePoses
from tftools.core.time import NS_PER_S, format_sec
from tftools.render.escape import printable

#: Decimals kept: translations to 0.1 mm, quaternions to 1e-5 (~0.001°): below what can be seen.
TRANSLATION_DECIMALS = 4
ROTATION_DECIMALS = 5
#: The vendored scripts the view needs, in load order, after the page's own.
SCRIPTS = ("vendor/three.iife.min.js", "scene3d.js")


def poses_data(poses: FramePoses | None, origin: int) -> dict[str, Any] | None:
    """The poses as the page's JSON: times in seconds from ``origin`` (the timelines' 0) and as absolute
    stamps; a frame that holds still over the whole recording has one ``pose``, another a ``poses`` list
    (null where tf2 could not place it)."""
    if poses is None:
        return None
    frames = []
    for k, name in enumerate(poses.frames):
        with np.errstate(over="ignore", invalid="ignore"):  # rounding 1e308 overflows: such a pose is not drawn
            translations = poses.translations[k].round(TRANSLATION_DECIMALS)
        values = np.concatenate([translations, poses.rotations[k].round(ROTATION_DECIMALS)], axis=1)
        valid = poses.valid[k] & np.isfinite(values).all(axis=1)
        entry: dict[str, Any] = {"name": printable(name), "parent": printable(poses.parents[k] or "")}
        if valid.all() and np.ptp(values, axis=0).max() == 0.0:
            entry["pose"] = values[0].tolist()
        else:
            entry["poses"] = [v if ok else None for v, ok in zip(values.tolist(), valid.tolist(), strict=True)]
        frames.append(entry)
    return {
        "fixed": printable(poses.fixed),
        "times": [round((t - origin) / NS_PER_S, 6) for t in poses.times.tolist()],
        "stamps": [format_sec(t, 9) for t in poses.times.tolist()],
        "frames": frames,
        "unplaced": len(poses.unplaced),
    }


def scene_html(poses: FramePoses | None) -> str:
    """The view's heading and element (the script fills it in), or nothing without frames."""
    if poses is None:
        return ""
    fixed = html.escape(printable(poses.fixed), quote=True)
    unplaced = (
        f" Not drawn (in another tree than {fixed}'s, or beyond {MAX_FRAMES} frames): {_listed(poses.unplaced)}."
        if poses.unplaced
        else ""
    )
    own_clock = (
        " Stamped on another clock, placed as far into their own stamps as the slider is into the recording's: "
        f"{_listed(poses.own_clock)}."
        if poses.own_clock
        else ""
    )
    return (
        f'<h3>Frames in 3D</h3><p class="axis">Every frame in <b>{fixed}</b> as tf2 placed it: x red, y green, '
        f"z blue; grey lines join each frame to its parent. Drag to orbit, shift-drag to pan, scroll to zoom; "
        f"hover for names; the slider moves through the recording; click a finding to see its frames at its "
        f'time.{unplaced}{own_clock}</p><div class="scene3d"></div>'
    )


def _listed(names: tuple[str, ...], most: int = 20) -> str:
    """Frame names for the page, the first ``most`` of them."""
    shown = ", ".join(names[:most]) + (f" and {len(names) - most} more" if len(names) > most else "")
    return html.escape(printable(shown))
