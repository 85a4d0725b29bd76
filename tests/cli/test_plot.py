"""``tfx echo --plot`` and ``tfx monitor --plot``: pictures of the transform, and of each edge's rate and delay,
over time; their files checked for size, axes and content, their figures for what each line holds."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib import image

from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tests.cli.test_bad_input import check_stderr
from tests.render.report_scenes import EKF_STOPS, GAP, troubled_bags
from tftools.analysis.echo import chain_span, lookups, sample_times
from tftools.analysis.timelines import edge_series
from tftools.core.time import NS_PER_S
from tftools.render.plots import DPI, WIDTH_IN, echo_figure, monitor_figure
from tftools.sources.recording import read_recording


@pytest.fixture(scope="module")
def troubled(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return troubled_bags(tmp_path_factory.mktemp("troubled"))


def labels(svg: Path) -> list[str]:
    """The texts of an SVG matplotlib wrote (each glyph run follows a comment with its text)."""
    return re.findall(r"<!-- (.*?) -->", svg.read_text())


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
def test_echo_plots_every_sample_of_the_chain(tfx: Tfx, tmp_path: Path, fmt: str) -> None:
    picture = tmp_path / "pose.png"
    result = tfx("echo", "map", "gripper", "-b", SAMPLE_BAGS[fmt], "--plot", picture)
    buffer = read_recording([SAMPLE_BAGS[fmt]]).buffer
    span = chain_span(buffer, "map", "gripper")
    assert span is not None
    samples = len(sample_times(buffer, "map", "gripper", *span))
    assert result.code == 0 and result.stdout == ""
    assert result.stderr == f"wrote {picture}: {samples} lookups of map <- gripper\n"
    pixels = image.imread(picture)
    height, width = pixels.shape[:2]
    assert abs(width - WIDTH_IN * DPI) < 150 and 500 < height < 900 and picture.stat().st_size > 40_000
    assert len(np.unique(pixels.reshape(-1, pixels.shape[2]), axis=0)) > 100  # six curves, not a blank canvas


def test_echo_svg_names_its_axes(tfx: Tfx, tmp_path: Path) -> None:
    picture = tmp_path / "pose.svg"
    assert tfx("echo", "map", "base_link", "-b", SAMPLE_BAGS["mcap"], "--plot", picture, "-r", "10").code == 0
    texts = labels(picture)
    for label in ("translation (m)", "rotation (degrees)", "x", "y", "z", "roll", "pitch", "yaw"):
        assert label in texts
    assert "base_link in map (map &lt;- base_link)" in texts and any(
        t.startswith("time (s) from 17000000") for t in texts
    )


def test_echo_figure_holds_each_coordinate_and_leaves_failures_out() -> None:
    buffer = read_recording([SAMPLE_BAGS["ros1"]]).buffer
    start = 1_700_000_001 * NS_PER_S
    times = [start + i * NS_PER_S // 10 for i in range(50)] + [start + 3600 * NS_PER_S]  # the last: far too late
    series = lookups(buffer, "map", "base_link", times)
    moves, turns = echo_figure(series).axes
    assert [line.get_label() for line in moves.get_lines()] == ["x", "y", "z"]
    assert [line.get_label() for line in turns.get_lines()] == ["roll", "pitch", "yaw"]
    seconds = moves.get_lines()[0].get_xdata()
    assert np.allclose(seconds, (np.array(times) - start) / NS_PER_S)
    for column, line in enumerate(moves.get_lines()):
        ys = np.asarray(line.get_ydata())
        assert np.allclose(ys[:-1], series.translations[:-1, column]) and np.isnan(ys[-1])
    assert np.allclose(np.asarray(turns.get_lines()[2].get_ydata())[:-1], np.degrees(series.rpy[:-1, 2]))
    assert moves.get_title().endswith("1 of 51 lookups failed")


def test_monitor_plots_each_edges_rate_and_delay(tfx: Tfx, troubled: dict[str, Path], tmp_path: Path) -> None:
    picture = tmp_path / "rates.svg"
    result = tfx("monitor", "-b", troubled["db3"], "--plot", picture)
    assert result.code == 0 and result.stdout == "" and "rate and delay of 4 edges" in result.stderr
    texts = labels(picture)
    assert {"rate (Hz)", "mean delay (ms)"} <= set(texts)
    assert {"odom -&gt; base_link", "map -&gt; odom", "map -&gt; base_link", "base_link -&gt; wheel"} <= set(texts)


def test_monitor_figure_shows_the_gap_and_the_stop() -> None:
    recording = read_recording([SAMPLE_BAGS["ros1"]])
    figure = monitor_figure(edge_series(recording.buffer, recording.timeline), "robot")
    rates, delays = figure.axes
    assert len(rates.get_lines()) == len(delays.get_lines()) == 10
    assert rates.get_ylabel() == "rate (Hz)" and delays.get_ylabel() == "mean delay (ms)"
    assert {round(float(np.nanmedian(np.asarray(line.get_ydata())))) for line in rates.get_lines()} == {10, 30, 50}


def test_a_chain_plots_its_own_edges(tfx: Tfx, troubled: dict[str, Path], tmp_path: Path) -> None:
    picture = tmp_path / "chain.svg"
    assert tfx("monitor", "map", "wheel", "-b", troubled["ros1"], "--plot", picture).code == 0
    named = {t for t in labels(picture) if "-&gt;" in t}
    assert named == {"map -&gt; odom", "odom -&gt; base_link", "base_link -&gt; wheel"}


def test_troubled_rates_drop_where_the_edge_paused_and_stop_where_it_stopped(troubled: dict[str, Path]) -> None:
    recording = read_recording([troubled["mcap"]])
    series = {(s.parent, s.child): s for s in edge_series(recording.buffer, recording.timeline)}
    origin = recording.timeline.tf_start
    odom, amcl = series[("odom", "base_link")], series[("map", "odom")]
    seconds = (odom.times - origin) / NS_PER_S
    assert np.all(np.isnan(odom.rate_hz[seconds > EKF_STOPS + 0.1]))
    assert np.allclose(odom.rate_hz[(seconds > 1) & (seconds < EKF_STOPS - 1)], 50.0)
    inside = (seconds > GAP[0]) & (seconds < GAP[1] - 0.1)
    assert np.allclose(amcl.rate_hz[inside], 1 / (GAP[1] - GAP[0] + 0.1))  # one interval of 2.1 s


def test_monitor_play_plots_each_refresh(tfx: Tfx, tmp_path: Path) -> None:
    picture = tmp_path / "replay.png"
    result = tfx("monitor", "-b", SAMPLE_BAGS["ros1"], "--play", "--start", "-2.5", "--rate", "1", "--plot", picture)
    assert result.code == 0, result.stderr
    said = re.search(r"rate and delay of 10 edges over (\d+) points", result.stderr)
    assert said is not None
    points = int(said.group(1))
    assert points >= 2 and picture.stat().st_size > 20_000


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (("echo", "map", "odom", "-b", "BAG", "--plot", "out.txt"), "not a picture tfx draws"),
        (("monitor", "-b", "BAG", "--plot", "FOLDER"), "not a picture tfx draws"),
        (("echo", "map", "odom", "-b", "BAG", "--plot", "no/such/out.png"), "does not exist"),
    ],
)
def test_a_bad_plot_is_one_line(
    tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: tuple[str, ...], said: str
) -> None:
    monkeypatch.chdir(tmp_path)
    names = {"BAG": str(SAMPLE_BAGS["ros1"]), "FOLDER": str(tmp_path)}
    result = tfx(*(names.get(a, a) for a in args))
    assert result.code == 2 and result.stdout == "" and said in result.stderr
    check_stderr(result.stderr, result.code)
    assert list(tmp_path.iterdir()) == []


def test_without_matplotlib_plot_says_how_to_get_it(tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as if not installed: importing it fails
    result = tfx("monitor", "-b", SAMPLE_BAGS["ros1"], "--plot", tmp_path / "rates.png")
    assert result.code == 2 and result.stdout == ""
    assert result.stderr.startswith("tfx: error: --plot needs matplotlib, which is not installed")
    assert result.stderr.endswith("(install it: pip install 'tftools[plot]')\n")


def test_echo_play_prints_its_lines_and_plots_them_when_it_ends(tfx: Tfx, tmp_path: Path) -> None:
    picture = tmp_path / "replay.svg"
    result = tfx("echo", "map", "base_footprint", "-b", SAMPLE_BAGS["db3"], "--play", "--start", "-1", "--rate", "4",
                 "-f", "csv", "--plot", picture)  # fmt: skip
    assert result.code == 0, result.stderr
    lines = result.stdout.splitlines()[1:]  # below the CSV header
    assert len(lines) >= 3 and result.stderr == f"wrote {picture}: {len(lines)} lookups of map <- base_footprint\n"
    assert "translation (m)" in labels(picture)
