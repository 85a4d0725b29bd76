"""``tfx report`` on the Nav2 TurtleBot 4 recording in Chromium, at 800 and 1400 pixels: nothing on the
page that the legend does not explain or that says nothing. A finding over two ~2 s gaps bands those
gaps, not the 46 s between them; a note bands nothing; no delay axis where delays are unavailable; the
tree without scrollbars at 1400 px; the page never scrolls sideways; the 3D view's 34 frames unnamed
until asked (their names were one blob), over a grid."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from tests.browser import chromium, open_page, screenshot
from tests.cli.conftest import Tfx, tfx
from tests.corpus.fetch import shared_dir

__all__ = ["chromium", "tfx"]  # fixtures, for pytest

MEASURE = """
var section = tfxReport.sections[0];
var data = section.data;
// the share of a plot's column at time t drawn on: a band fills it, the rate line and the grid a few pixels
var tinted = function (row, t) {
  var u = section.plots[row];
  var x = Math.round(u.valToPos(t, "x", true));
  var column = u.ctx.getImageData(x, u.bbox.top, 1, u.bbox.height).data;
  var n = 0;
  for (var k = 0; k < column.length; k += 4) {
    if (column[k + 3] > 25) n += 1;  // the canvas is clear but for what is drawn
  }
  return n / (column.length / 4);
};
var rows = data.edges.map(function (e) { return e.name; });
var map = rows.indexOf("map -> odom");
var tree = document.querySelector(".tree");
var view = tfxScene3d.views[0];
var names = document.querySelectorAll(".scene3d-stage span").length;
var first = data.findings[0];
document.querySelector('.finding[data-finding="0"]').click();  // the 3D view goes to the finding's time
await settled();
return {
  clicked: [first.from, view.data.times[view.index], Number(view.data.stamps[view.index])],
  rows: rows,
  gaps: data.edges[map].gaps,
  inGap: tinted(map, (data.edges[map].gaps[0][0] + data.edges[map].gaps[0][1]) / 2),
  between: tinted(map, 63.3),  // off the grid's vertical lines
  noteOnly: tinted(map, 21.7),
  series: section.plots.slice(0, rows.length).map(function (u) {
    return u.series.map(function (s) { return s.label; });
  }),
  axes: section.plots[0].axes.length,
  page: [document.documentElement.scrollWidth, window.innerWidth],
  tree: [tree.scrollWidth, tree.clientWidth, tree.scrollHeight, tree.clientHeight],
  names: names,
  frames: view.data.frames.length,
  grid: view.gridCell,
};
"""


@pytest.mark.parametrize("width", [1400, 800])
def test_the_nav2_page_shows_no_noise(tfx: Tfx, chromium: str, tmp_path: Path, width: int) -> None:
    bag = shared_dir() / "corpus" / "ros2_mcap_nav2_turtlebot4.mcap"
    if not bag.exists():
        pytest.skip(f"{bag.name} is not in {bag.parent} ($TFTOOLS_SHARED_DIR/corpus)")
    page = tmp_path / "nav2.html"
    assert tfx("report", "-b", bag, "-o", page).code == 0
    opened = open_page(page, MEASURE, width=width)
    assert opened.errors == []
    result = opened.results

    assert len(result["gaps"]) == 2 and result["inGap"] > 0.5  # map -> odom's two gaps are shaded
    assert result["between"] < 0.2  # the rate warning bands its gaps, not 41.6 s to 87.6 s
    assert result["noteOnly"] < 0.2  # map_corrections, a note from 6.8 s to 91.2 s, bands nothing
    assert all(labels == ["time", "rate", "samples"] for labels in result["series"])  # no delays on sim time
    assert result["axes"] == 2  # time and rate: no empty delay axis

    scroll, inner = result["page"]
    assert scroll <= inner  # never sideways
    if width == 1400:
        wide, box, tall, height = result["tree"]
        assert wide <= box and tall <= height  # the tree needs no scrollbars
    assert result["frames"] == 34 and result["names"] == 0 and result["grid"] > 0

    since, shown, stamp = result["clicked"]  # the finding at +40.824 s, stamp 969.624 (was shown at 964.585)
    assert since == pytest.approx(40.824) and shown == pytest.approx(since, abs=0.5)
    assert stamp == pytest.approx(969.624, abs=0.5)

    picture = screenshot(page, tmp_path / f"nav2-{width}.png", width=width, height=3000)
    folder = os.environ.get("TFTOOLS_SCREENSHOTS")
    if folder:
        shutil.copy(picture, Path(folder) / f"nav2-{width}.png")
