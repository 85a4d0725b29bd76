"""``tfx report``'s page in a real browser (Debian's headless Chromium): it renders without script errors,
shows the findings and the frames, zooms every timeline together, and a finding leads to its edges and time.

``TFTOOLS_SCREENSHOTS=DIR`` keeps the screenshots there (the README's is docs/report.png, from ros1)."""

from __future__ import annotations

import itertools
import os
import shutil
from pathlib import Path

import pytest

from tests.bags import TfMessage, write_bag
from tests.browser import chromium, open_page, png_size, screenshot
from tests.cli.conftest import HOSTILE_NAMES, SAMPLE_BAGS, Tfx, tfx
from tests.cli.test_filter import sensor_bags
from tests.cli.test_report import _scans
from tests.render.report_scenes import EKF_STOPS, troubled_bags
from tftools.core.transform import Transform

__all__ = ["chromium", "tfx"]  # fixtures, for pytest

#: Run in the page once it loaded: the plots' x ranges at rest, after a zoom, and after a click on the
#: finding about the stopped edge; which rows and tree elements that click marked.
INTERACT = """
var section = tfxReport.sections[WHICH];
var ranges = function () { return section.plots.map(function (u) { return [u.scales.x.min, u.scales.x.max]; }); };
var result = { sections: tfxReport.sections.length, plots: section.plots.length, rest: ranges() };
section.zoom(2, 4);
await settled();
result.zoomed = ranges();
var stale = Array.from(document.querySelectorAll(".finding")).filter(function (item) {
  return item.querySelector("code").textContent === "stale";
})[0];
stale.click();
await settled();
result.focused = ranges();
result.rows = Array.from(document.querySelectorAll(".row.edge.active b")).map(function (b) { return b.textContent; });
result.drawn = Array.from(document.querySelectorAll(".tree .active")).map(function (e) { return e.id; });
result.canvases = document.querySelectorAll(".row canvas").length;
result.others = tfxReport.sections.filter(function (s) { return s !== section; }).map(function (s) {
  return s.plots[0].scales.x.max;
});
return result;
"""


@pytest.fixture(scope="module")
def troubled(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return troubled_bags(tmp_path_factory.mktemp("troubled"))


def _keep(picture: Path, name: str) -> None:
    folder = os.environ.get("TFTOOLS_SCREENSHOTS")
    if folder:
        shutil.copy(picture, Path(folder) / name)


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
def test_the_troubled_robot_in_a_browser(
    tfx: Tfx, chromium: str, troubled: dict[str, Path], tmp_path: Path, fmt: str
) -> None:
    page = tmp_path / "report.html"
    assert tfx("report", "-b", troubled[fmt], "-o", page).code == 1
    opened = open_page(page, INTERACT.replace("WHICH", "0"))
    assert opened.errors == []
    for code in ("sensor_frame", "multiple_parents", "stale", "rate"):
        assert code in opened.text
    for frame in ("map", "odom", "base_link", "wheel", "laser", "camera", "/scan", "/camera/image_raw"):
        assert frame in opened.text
    result = opened.results
    assert result["plots"] == 6 and result["canvases"] == 6  # 4 moving edges, 2 sensor streams
    assert len(set(map(tuple, result["rest"]))) == 1 and result["rest"][0][1] > 9.9
    assert result["zoomed"] == [[2, 4]] * 6  # one zoom, every timeline
    first, last = result["focused"][0]
    assert len(set(map(tuple, result["focused"]))) == 1 and first < EKF_STOPS < last < 12
    assert result["rows"] == ["odom \u2192 base_link"]
    assert len(result["drawn"]) == 1 and result["drawn"][0].startswith("r0-edge")

    picture = screenshot(page, tmp_path / f"report-{fmt}.png")
    assert png_size(picture) == (1400, 2200) and picture.stat().st_size > 100_000
    _keep(picture, f"report-{fmt}.png")


def test_a_fleet_in_a_browser(tfx: Tfx, chromium: str, troubled: dict[str, Path], tmp_path: Path) -> None:
    page = tmp_path / "fleet.html"
    bags = [SAMPLE_BAGS["ros1"], troubled["db3"], tmp_path / "missing.bag"]
    assert tfx("report", *bags, "-o", page).code == 1
    opened = open_page(page, INTERACT.replace("WHICH", "1"))
    assert opened.errors == []
    assert "3 recordings, 2 failed" in opened.text
    assert "No problems found." in opened.text and "could not be read" in opened.text
    result = opened.results
    assert result["sections"] == 2 and result["zoomed"] == [[2, 4]] * 6
    assert result["others"][0] > 14  # the other recording (15 s) keeps its own axis
    picture = screenshot(page, tmp_path / "fleet.png", height=1200)
    assert png_size(picture) == (1400, 1200)


#: A frame name that, were it pasted into the page as HTML or script, would run and say so.
INJECTION = '</script><img src=x onerror="__errors.push(\'injected\')"><b id="injected">'


def test_names_from_the_bag_stay_text(tfx: Tfx, chromium: str, tmp_path: Path) -> None:
    start = 1_700_000_000 * 10**9
    frames = ["map", INJECTION, *HOSTILE_NAMES[:5]]
    messages = [
        TfMessage("/tf", start + i * 10**8 + 10**6, [
            Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), start + i * 10**8, parent, child)
            for parent, child in itertools.pairwise(frames)
        ], INJECTION)
        for i in range(20)
    ]  # fmt: skip
    page = tmp_path / "hostile.html"
    assert tfx("report", "-b", write_bag(tmp_path / "hostile.bag", messages), "-o", page).code in (0, 1)
    opened = open_page(page, 'return [document.getElementById("injected"), document.querySelectorAll("b").length];')
    assert opened.errors == [] and opened.results[0] is None
    assert INJECTION in opened.text and "<b>html</b>" in opened.text  # shown, as text


def test_the_page_of_a_recording_without_transforms_in_a_browser(tfx: Tfx, chromium: str, tmp_path: Path) -> None:
    """A recording of laser scans and no tf (as ros2_mcap_abitobot_no_tf holds /imu/data and /joint_states only):
    the page says there are no transforms, what the recording holds and wtf's no_tf finding, draws no tree or
    timeline, and its scripts run without an error, a click on the finding too."""
    (tmp_path / "bags").mkdir()
    bag = sensor_bags(tmp_path / "bags", [], _scans)["db3"]
    page = tmp_path / "report.html"
    assert tfx("report", "-b", bag, "-o", page).code == 1
    opened = open_page(page, 'document.querySelector(".finding").click(); await settled(); return null;')
    assert opened.errors == []
    for said in ("No transforms", "no_tf", "/scan (sensor_msgs/msg/LaserScan)"):
        assert said in opened.text, said
    assert "<svg" not in opened.dom and "<canvas" not in opened.dom
