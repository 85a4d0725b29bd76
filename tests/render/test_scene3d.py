"""The report's 3D view in Debian's headless Chromium: every frame drawn where ``tfx echo`` places it at the
slider's time, a finding's click showing its frames at its time, a flipped sensor's z axis pointing down,
on a designed robot and on the real Franka Panda.

``TFTOOLS_SCREENSHOTS=DIR`` keeps the screenshots there."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.analysis.robot_scenes import FLIPPED, Setup, robot_bag, urdf_file
from tests.browser import chromium, open_page, png_size, screenshot
from tests.cli.conftest import Tfx, tfx
from tests.corpus.fetch import shared_dir

__all__ = ["chromium", "tfx"]  # fixtures, for pytest

#: The view's frames at time ``INDEX`` (its positions and axes as drawn), the time itself, then the same
#: after a click on the finding coded ``CODE``.
READ_BACK = """
var view = tfxScene3d.views[0];
var result = { views: tfxScene3d.views.length, times: view.data.times.length, fixed: view.data.fixed };
view.setTime(INDEX);
await settled();
result.at = { index: view.index, stamp: view.data.stamps[view.index], positions: view.positions(), axes: view.axes(),
  screen: view.screen(), canvas: document.querySelectorAll(".scene3d canvas").length };
var item = Array.from(document.querySelectorAll(".finding")).filter(function (i) {
  return i.querySelector("code").textContent === "CODE";
})[0];
var canvas = document.querySelector(".scene3d canvas");
var box = canvas.getBoundingClientRect();
var spots = view.screen();
var name = Object.keys(spots).filter(function (n) { return n !== view.data.fixed; }).pop();
var at = spots[name];
var move = function (type, x, y, extra) {
  canvas.dispatchEvent(new PointerEvent(type, Object.assign({ clientX: box.left + x, clientY: box.top + y,
    bubbles: true, pointerId: 1 }, extra || {})));
};
move("pointermove", at[0] + 2, at[1] + 1);
result.hover = [name, document.querySelector(".scene3d-tip").style.display === "block" ?
  document.querySelector(".scene3d-tip").textContent : null];
var before = view.screen()[name];
move("pointerdown", 300, 200);
move("pointermove", 380, 230);
move("pointerup", 380, 230);
var distance = view.distance;
var wheel = { deltaY: 500, clientX: box.left + 300, clientY: box.top + 200, bubbles: true };
canvas.dispatchEvent(new WheelEvent("wheel", wheel));
result.orbit = { moved: view.screen()[name][0] !== before[0], zoomed: view.distance / distance };
if (item) {
  item.click();
  await settled();
  result.focused = { index: view.index, frames: view.focused, stamp: view.data.stamps[view.index],
    labels: Array.from(document.querySelectorAll(".scene3d span")).map(function (s) { return s.textContent; }) };
}
return result;
"""


def _keep(picture: Path, name: str) -> None:
    folder = os.environ.get("TFTOOLS_SCREENSHOTS")
    if folder:
        shutil.copy(picture, Path(folder) / name)


def _echo(tfx: Tfx, bag: Path, fixed: str, frame: str, stamp: str) -> dict[str, Any]:
    result = tfx("echo", fixed, frame, "-b", bag, "--at", stamp, "--format", "json")
    assert result.code == 0, result.stderr
    echoed: dict[str, Any] = json.loads(result.stdout)
    return echoed


def _agree(tfx: Tfx, bag: Path, at: dict[str, Any], fixed: str) -> int:
    """Every drawn frame's origin and axes against ``tfx echo fixed frame --at stamp``; how many agreed."""
    agreed = 0
    for frame, position in at["positions"].items():
        if frame == fixed:
            assert position == [0, 0, 0]
            continue
        echoed = _echo(tfx, bag, fixed, frame, at["stamp"])
        assert position == pytest.approx(echoed["translation"], abs=6e-5), frame  # 0.1 mm: the page's rounding
        qx, qy, qz, qw = echoed["rotation"]
        matrix = np.array(
            [
                [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
            ]
        )
        assert np.array(at["axes"][frame]) == pytest.approx(matrix.T, abs=1e-4), frame  # rows: x, y, z axes
        agreed += 1
    return agreed


def test_a_flipped_laser_in_3d(tfx: Tfx, chromium: str, tmp_path: Path) -> None:
    bag = robot_bag(tmp_path, "rover", Setup(real_origins={"laser_joint": FLIPPED}))
    page = tmp_path / "report.html"
    result = tfx("report", "-b", bag, "--urdf", urdf_file(tmp_path), "-o", page)
    assert result.code == 1, result.stderr
    opened = open_page(page, READ_BACK.replace("INDEX", "75").replace("CODE", "urdf_moved"))
    assert opened.errors == []
    r = opened.results
    assert r["views"] == 1 and r["fixed"] == "odom" and r["times"] == 120 and r["at"]["canvas"] == 1
    at = r["at"]
    assert at["index"] == 75 and set(at["positions"]) == {
        "odom",
        "base_footprint",
        "base_link",
        "laser",
        "camera_link",
        "wheel_left_link",
        "wheel_right_link",
    }
    assert _agree(tfx, bag, at, "odom") == 6
    assert at["axes"]["laser"][2] == pytest.approx([0, 0, -1], abs=1e-6)  # upside down: its z points at the floor
    assert at["axes"]["base_link"][2] == pytest.approx([0, 0, 1], abs=1e-6)
    assert all(0 <= x <= 1400 and 0 <= y <= 520 for x, y in at["screen"].values())  # every frame in the picture
    name, tip = r["hover"]
    assert tip is not None and tip.startswith(f"{name}  [")  # its name and place on hover
    assert r["orbit"]["moved"] and r["orbit"]["zoomed"] > 1.5  # a drag orbits, the wheel zooms out
    focused = r["focused"]
    assert focused["frames"] == ["base_link", "laser"] and focused["index"] == 0  # the finding's time: the statics'
    assert any("laser" in label for label in focused["labels"])

    picture = screenshot(page, tmp_path / "flipped.png", 1400, 1300)
    assert png_size(picture) == (1400, 1300)
    _keep(picture, "report-3d-flipped.png")


def test_the_panda_in_3d_where_tf_echo_puts_it(tfx: Tfx, chromium: str, tmp_path: Path) -> None:
    bag = shared_dir() / "corpus" / "tfbag-franka-panda.bag"
    if not bag.exists():
        pytest.skip(f"{bag.name} is not in {bag.parent} ($TFTOOLS_SHARED_DIR/corpus)")
    page = tmp_path / "panda.html"
    assert tfx("report", "-b", bag, "-o", page).code == 0
    for index in (30, 100):  # the arm moves between them
        opened = open_page(page, READ_BACK.replace("INDEX", str(index)).replace("CODE", "none"))
        assert opened.errors == []
        at = opened.results["at"]
        assert opened.results["fixed"] == "world" and len(at["positions"]) == 23
        assert _agree(tfx, bag, at, "world") == 22
