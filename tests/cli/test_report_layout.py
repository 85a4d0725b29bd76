"""``tfx report``'s page measured as Chromium renders it, at 1400 and 800 pixels wide: the tree's labels
are read at a readable size, every axis is as wide as its longest label (no "0 Hz" for 10 Hz, no "0.01 m"
for 0.01 ms), and every edge's delay is drawn as a line wherever it has samples, at 10 Hz as at 50 Hz.

``TFTOOLS_SCREENSHOTS=DIR`` keeps a screenshot of each width there (docs/report.png is the 1400 one)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from tests.browser import chromium, open_page, screenshot
from tests.cli.conftest import Tfx, tfx
from tests.render.report_scenes import troubled_bags

__all__ = ["chromium", "tfx"]  # fixtures, for pytest

#: The smallest text the tree may be drawn at, in CSS pixels (a browser's default is 16, small print 10-12).
READABLE_PX = 10.0

MEASURE = """
var result = { tree: [], axes: [], delays: [], canvases: document.querySelectorAll(".row canvas").length, plots: 0 };
document.querySelectorAll(".tree svg text").forEach(function (t) {
  result.tree.push([t.textContent, t.getBoundingClientRect().height]);
});
var violet = function (d, k) { return d[k + 2] > d[k + 1] + 30 && d[k] > d[k + 1] + 15 && d[k + 3] > 0; };
tfxReport.sections.forEach(function (section) {
  result.plots += section.plots.length;
  section.plots.forEach(function (u, p) {
    u.axes.forEach(function (axis, i) {
      if (axis.side % 2 === 0 || !axis._values) return;  // the time axis runs along the bottom
      u.ctx.font = axis.font[0];
      var widths = axis._values.map(function (v) { return u.ctx.measureText(String(v)).width / devicePixelRatio; });
      result.axes.push({ plot: p, labels: axis._values, widest: Math.max.apply(null, widths),
                         room: axis._size - axis.ticks.size - axis.gap });
    });
  });
  section.data.edges.forEach(function (edge, row) {
    var u = section.plots[row];
    var box = u.bbox;
    var pixels = u.ctx.getImageData(box.left, box.top, box.width, box.height);
    var drawn = 0, bins = 0;
    edge.delayMean.forEach(function (value, i) {
      if (value == null) return;
      bins += 1;
      var x = Math.round(u.valToPos(section.xs[i], "x", true) - box.left);
      for (var dx = -1; dx <= 1; dx++) {
        for (var y = 0; y < box.height; y++) {
          var k = (y * box.width + x + dx) * 4;
          if (x + dx >= 0 && x + dx < box.width && violet(pixels.data, k)) { drawn += 1; return; }
        }
      }
    });
    result.delays.push({ edge: edge.name, bins: bins, drawn: drawn });
  });
});
return result;
"""


@pytest.mark.parametrize("width", [1400, 800])
def test_every_label_readable_and_every_figure_drawn(tfx: Tfx, chromium: str, tmp_path: Path, width: int) -> None:
    bag = troubled_bags(tmp_path)["ros1"]
    page = tmp_path / "report.html"
    assert tfx("report", "-b", bag, "-o", page).code == 1
    opened = open_page(page, MEASURE, width=width)
    assert opened.errors == []
    result = opened.results

    assert len(result["tree"]) > 10  # frames, rates, publishers, findings' marks
    small = [(text, round(height, 1)) for text, height in result["tree"] if height < READABLE_PX]
    assert small == [], f"tree labels drawn too small to read at {width} px"

    assert result["plots"] == result["canvases"] == 6  # 4 moving edges, 2 sensor streams: each drawn
    assert len(result["axes"]) == 12  # two vertical axes a plot
    cut = [(a["labels"], a["widest"], a["room"]) for a in result["axes"] if a["widest"] > a["room"] + 0.5]
    assert cut == [], "axis labels wider than their axis: cut off at the page's edge"

    for delay in result["delays"]:  # 10, 50, 10 and 20 Hz edges, 20 ms bins
        assert delay["bins"] > 5 and delay["drawn"] >= 0.9 * delay["bins"], delay

    picture = screenshot(page, tmp_path / f"report-{width}.png", width=width, height=2100)
    folder = os.environ.get("TFTOOLS_SCREENSHOTS")
    if folder:
        shutil.copy(picture, Path(folder) / f"report-{width}.png")
