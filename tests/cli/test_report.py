"""``tfx report``: the page's content on bags of every format, fleets, and bad input (tests/render has the
browser's view of it)."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.analysis.wtf_scenes import START, simulated, write
from tests.bags import BagFormat, TfMessage, write_bag
from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tests.cli.test_bad_input import check_stderr
from tests.cli.test_filter import scan, sensor_bags
from tests.render.report_scenes import (
    EKF_STOPS,
    GAP,
    REPARENTED,
    page_data,
    troubled_bags,
    troubled_sensors,
    troubled_tf,
)
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

FORMATS = list(SAMPLE_BAGS)


@pytest.fixture(scope="module")
def troubled(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return troubled_bags(tmp_path_factory.mktemp("troubled"))


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_page_shows_each_problem_on_its_edge_and_at_its_time(
    tfx: Tfx, troubled: dict[str, Path], tmp_path: Path, fmt: str
) -> None:
    page = tmp_path / "report.html"
    result = tfx("report", "-b", troubled[fmt], "-o", page)
    assert result.code == 1 and result.stdout == "", result.stderr
    assert result.stderr == f"wrote {page}: 3 errors, 2 warnings\n"
    (data,) = page_data(page)
    edges = {e["name"]: e for e in data["edges"]}
    assert list(edges) == ["map -> odom", "odom -> base_link", "map -> base_link", "base_link -> wheel"]  # tree order
    step = data["axis"]["step"]
    assert data["axis"]["count"] * step == pytest.approx(10.0, abs=0.1) and step == 0.02  # 9.95 s in 500 bins

    gaps = edges["map -> odom"]["gaps"]
    assert gaps == [pytest.approx([GAP[0] - 0.1, GAP[1]])]  # from the last sample before the pause to the first after
    odom = edges["odom -> base_link"]
    samples = np.array(odom["samples"])
    stop = round(EKF_STOPS / step)
    assert samples[:stop].sum() == EKF_STOPS * 50 and samples[stop:].sum() == 0
    assert np.nanmedian(np.array(odom["rate"], float)) == pytest.approx(50.0)
    assert np.nanmedian(np.array(odom["delayMean"], float)) == pytest.approx(2.0)  # ms: recorded 2 ms after the stamp
    changes = odom["reparentings"]
    assert len(changes) == 20 and [c[1] for c in changes[:2]] == ["base_link: odom -> map", "base_link: map -> odom"]
    assert all(REPARENTED[0] <= t <= REPARENTED[1] for t, _ in changes)
    assert edges["map -> base_link"]["reparentings"] == changes

    findings = {f["code"]: f for f in data["findings"]}
    assert set(findings) == {"sensor_frame", "sensor_lost", "multiple_parents", "stale", "rate"}
    rows = list(edges)
    stale = findings["stale"]
    assert [rows[i] for i in stale["rows"]] == ["odom -> base_link"] and stale["severity"] == "error"
    assert stale["from"] == pytest.approx(EKF_STOPS - 0.02) and stale["to"] == pytest.approx(9.962)
    assert [rows[i] for i in findings["rate"]["rows"]] == ["map -> odom"]
    assert {rows[i] for i in findings["multiple_parents"]["rows"]} == {"map -> base_link", "odom -> base_link"}
    assert all(re.fullmatch(r"r0-edge\d+", drawn) for drawn in stale["svg"])

    streams = {s["topic"]: s["fates"] for s in data["streams"]}
    camera, scan = streams["/camera/image_raw"], streams["/scan"]
    assert sum(camera["lost"]) == 19 and sum(camera["on_arrival"]) + sum(camera["later"]) == 0
    assert sum(sum(counts) for counts in scan.values()) == 199
    # its tf stopped at 8 s, 2 s before the recording ended: the scans waiting for it are lost (issue 29's B)
    assert sum(scan["lost"][:stop]) == 0 and sum(scan["lost"][stop + 1 :]) > 30 and sum(scan["undecided"]) == 0

    text = page.read_text()
    for shown in ("sensor_frame", "did you mean &#x27;camera&#x27;?", "went silent", "stopped", "Files", "Clocks"):
        assert shown in text
    assert re.search(r'<g id="r0-edge\d+" class="edge">', text) and "<title>base_link</title>" in text  # the tree
    assert "19 lost (unknown frame 19)" in text  # in words, as tfx filter says them: not 'unknown_frame'


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_healthy_robot_passes(tfx: Tfx, tmp_path: Path, fmt: str) -> None:
    page = tmp_path / "robot.html"
    result = tfx("report", "-b", SAMPLE_BAGS[fmt], "-o", page)
    assert result.code == 0 and result.stderr == f"wrote {page}: no problems\n"
    (data,) = page_data(page)
    assert len(data["edges"]) == 10 and data["findings"] == [] and data["streams"] == []
    text = page.read_text()
    assert "No problems found." in text and 'class="verdict passed"' in text
    assert "Static transforms" in text and "camera_link &#8594; camera_optical_frame" in text


def test_the_page_needs_nothing_from_outside(tfx: Tfx, tmp_path: Path) -> None:
    page = tmp_path / "robot.html"
    tfx("report", "-b", SAMPLE_BAGS["ros1"], "-o", page)
    text = page.read_text()
    assert not re.search(r"<(link|img|iframe)\b", text, re.I)
    assert not re.search(r"""\b(src|href)\s*=\s*["']?(https?:|//)""", text, re.I)
    assert not re.search(r"@import|url\(\s*['\"]?(https?:|//)", text, re.I)
    # the plotting library, the page's script, three.js and the 3D view's script, inline
    assert text.count("<script>") == 4 and "uPlot" in text and "tfxScene3d" in text
    assert 600_000 < len(text.encode()) < 900_000  # three.js's part is 550 KB of it


def test_a_fleet_gets_a_section_and_a_verdict_each(tfx: Tfx, troubled: dict[str, Path], tmp_path: Path) -> None:
    page = tmp_path / "fleet.html"
    missing = tmp_path / "missing.bag"
    result = tfx("report", SAMPLE_BAGS["ros1"], troubled["mcap"], missing, "-o", page)
    assert result.code == 1
    check_stderr(result.stderr, result.code)
    assert result.stderr.endswith(f"wrote {page}: 2 of 3 failed\n") and str(missing) in result.stderr
    assert len(page_data(page)) == 2  # the unreadable one has no plots
    text = page.read_text()
    verdicts = re.findall(r'<section class="recording (\w+)" id="(r\d)">', text)
    assert verdicts == [("passed", "r0"), ("failed", "r1"), ("failed", "r2")]
    assert "3 recordings, 2 failed" in text and text.count('<a href="#r') == 3
    assert "could not be read" in text


def test_a_fleet_read_in_several_processes_gives_the_same_page(
    tfx: Tfx, troubled: dict[str, Path], tmp_path: Path
) -> None:
    fleet = [SAMPLE_BAGS["ros1"], troubled["mcap"], tmp_path / "missing.bag"]
    one, two = tmp_path / "one.html", tmp_path / "two.html"
    serial, parallel = tfx("report", *fleet, "-o", one), tfx("report", *fleet, "-o", two, "--jobs", "2")
    assert serial.code == parallel.code == 1
    assert one.read_bytes() == two.read_bytes()
    assert parallel.stderr.replace(str(two), str(one)) == serial.stderr


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (("-b", "MISSING"), "no such file"),
        (("MISSING", "MISSING"), "no such file"),
        (("-b", "BAG", "-o", "NOFOLDER"), "does not exist"),
        (("-b", "BAG", "-o", "FOLDER"), "is a directory"),
        (("-b", "BAG", "-o", "BAG"), "is the input"),
        (("-b", "BAG", "--tf2", "ros3"), "Invalid value"),
    ],
)
def test_bad_input_is_one_line_and_writes_nothing(tfx: Tfx, tmp_path: Path, args: tuple[str, ...], said: str) -> None:
    names = {
        "MISSING": str(tmp_path / "missing.bag"),
        "BAG": str(SAMPLE_BAGS["ros1"]),
        "NOFOLDER": str(tmp_path / "no" / "such" / "report.html"),
        "FOLDER": str(tmp_path),
    }
    arguments = [names.get(a, a) for a in args] + ([] if "-o" in args else ["-o", str(tmp_path / "out.html")])
    before = sorted(tmp_path.iterdir())
    result = tfx("report", *arguments)
    assert result.code == 2 and result.stdout == ""
    check_stderr(result.stderr, result.code)
    assert said in result.stderr
    assert sorted(tmp_path.iterdir()) == before


def test_an_edge_names_no_delay_where_the_clocks_give_none(tfx: Tfx, tmp_path: Path) -> None:
    bag = write(tmp_path, "simulated", BagFormat.rosbag2_sqlite3, simulated())  # sim stamps, wall-clock record times
    page = tmp_path / "report.html"
    result = tfx("report", "-b", bag, "-o", page)
    assert result.code == 0, result.stderr
    html = page.read_text()
    assert "Delays unavailable" in html
    labels = re.findall(r'<div class="row edge".*?<small>(.*?)</small>', html)
    assert labels and all("Hz" in label and "delay" not in label for label in labels)


def test_the_3d_view_and_the_timelines_count_from_one_zero(tfx: Tfx, tmp_path: Path) -> None:
    """A scan stamped 2 s before the first tf starts the timelines' bins before their zero (on the Nav2
    TurtleBot 4 recording the 3D view counted from there, and a finding's click showed it 5 s early): the
    3D view's times are seconds from the same zero as the timelines' and the findings'."""

    def early_scan(store: Any) -> list[tuple[str, str, int, object]]:
        stamp = START - 2 * NS_PER_S
        return [("/scan", "sensor_msgs/msg/LaserScan", stamp + 5_000_000, scan(store, "laser", stamp))]

    bags = sensor_bags(tmp_path, troubled_tf(), lambda store: early_scan(store) + troubled_sensors(store))
    page = tmp_path / "report.html"
    tfx("report", "-b", bags["ros1"], "-o", page)
    (data,) = page_data(page)
    assert data["axis"]["start"] < -1.9  # the bins begin at the early scan
    zero = re.search(r"Time in seconds from ([0-9.]+)", page.read_text())
    assert zero is not None and float(zero.group(1)) == START / NS_PER_S
    scene = data["scene3d"]
    assert [float(stamp) - START / NS_PER_S for stamp in scene["stamps"]] == pytest.approx(scene["times"], abs=1e-6)
    stale = next(f for f in data["findings"] if f["code"] == "stale")
    assert stale["from"] == pytest.approx(EKF_STOPS - 0.02)  # the finding, on the same axis


def test_a_finding_stamped_on_a_replays_clock_is_not_placed_days_before_the_recording(tfx: Tfx, tmp_path: Path) -> None:
    """The real raspimouse_replay_beside_live_gmapping_2018: odom -> base_link replayed with stamps 7 days behind
    the live map -> odom, and stopping 2.5 s before the end; its stale finding read "-603788.935 s to +53.950 s"
    of a 54 s recording. Its last stamp is on another clock: said as such, and off the timelines' axis."""
    week = 7 * 86_400 * NS_PER_S
    messages = []
    for k in range(200):
        now = START + k * 100_000_000
        live = Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), now, "map", "odom")
        messages.append(TfMessage("/tf", now, [live], "/slam"))
        if k < 170:  # the replay ends 3 s before the recording does
            old = Transform((0.01 * k, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), now - week, "odom", "base_link")
            messages.append(TfMessage("/tf", now + 1_000_000, [old], "/play"))
    bag = write_bag(tmp_path / "replayed.bag", messages, BagFormat.ros1)
    page = tmp_path / "report.html"
    tfx("report", "-b", bag, "-o", page)
    whens = re.findall(r'<span class="when">(.*?)</span>', page.read_text())
    assert any("(another clock)" in when for when in whens), whens
    offsets = [float(s) for when in whens for s in re.findall(r"([+-][\d.]+) s\b", when)]
    assert offsets and all(-1 < s < 21 for s in offsets), whens  # nothing days before a 20 s recording
    stale = next(f for (data,) in [page_data(page)] for f in data["findings"] if f["code"] == "stale")
    assert stale["from"] is None and stale["to"] == pytest.approx(19.9, abs=0.01)


@pytest.mark.parametrize("recorded", ["without tf", "tf on other topics"])
def test_a_recording_without_transforms_gets_the_same_hint_from_every_command(
    tfx: Tfx, tmp_path: Path, recorded: str
) -> None:
    """Issue 39, ros2_db3_webots_epuck_ranges_no_tf_2025 and ros2_mcap_kth_robp_arm_joy_no_tf_2025: report said
    "(was /tf recorded? read other topics)", the library's hint (its error went through ``Unreadable``), where
    the other commands said "pick other topics with --topic"; and "read /tf and /tf_static, of a transform
    type" where they said "leave out --topic". The report words the error it carries as they do; tfx filter,
    which has no --topic, names none; wtf's no_tf finding gave its own longer hint, and gives theirs now. The
    report, which exited 2 without a page, writes its page with wtf's no_tf finding and exits 1, as wtf does."""
    if recorded == "without tf":
        (tmp_path / "bags").mkdir()
        bag = sensor_bags(tmp_path / "bags", [], _scans)["db3"]
        recorded_tf = "was /tf recorded? record it with ros2 bag record /tf /tf_static"  # the bag's ROS's words
        topic, hint = [], f"{recorded_tf}, or pick other topics with --topic"
        filtered = tfx("filter", "-b", bag)
        only = f"; {recorded_tf}; tfx filter reads /tf and /tf_static only; a tree for its data must hold laser: "
        assert filtered.code == 2 and only in filtered.stderr, filtered.stderr
        # the frame its data is stamped in: what the tree it needs must hold (issue 39, notf39)
        assert "its data is stamped in laser (/scan)" in filtered.stderr, filtered.stderr
    else:
        bag, topic, hint = SAMPLE_BAGS["ros1"], ["--topic", "/nothing"], "/tf and /tf_static carry transforms: leave"
    commands: dict[str, list[str | Path]] = {
        "frames": ["frames", "-b", bag],
        "echo": ["echo", "odom", "base_link", "-b", bag],
        "monitor": ["monitor", "-b", bag],
        "view-frames": ["view-frames", "-b", bag, "-o", tmp_path / "frames.pdf"],
    }
    if recorded == "without tf":  # an empty tree to diff (brief review39), said so; no tf read where tf is recorded
        itself = tfx("diff", bag, bag)
        assert itself.code == 0 and "(0 frames: no transforms on /tf, /tf_static)" in itself.stdout, itself.stdout
    else:
        commands["diff"] = ["diff", bag, bag]
    hints = {}
    for name, args in commands.items():
        result = tfx(*args, *topic)
        assert result.code == 2, name
        check_stderr(result.stderr, result.code)
        said = result.stderr.rstrip("\n")
        hints[name] = said[said.index(hint) :].removesuffix(")")  # "(hint)", or "; hint" after parentheses
    assert set(hints.values()) == {hints["frames"]}, hints
    assert ("; a tree for its data must hold laser: " in hints["frames"]) is (recorded == "without tf"), hints
    # wtf, which reads on and says it as its no_tf finding, gives the same hint, and so does the report's page
    wtf = tfx("wtf", "-b", bag, *topic, "-f", "json")
    (no_tf,) = [f for b in json.loads(wtf.stdout)["bags"] for f in b["findings"] if f["code"] == "no_tf"]
    assert no_tf["hint"] == hints["frames"], (no_tf["hint"], hints)
    page = tmp_path / "report.html"
    assert wtf.code == tfx("report", "-b", bag, *topic, "-o", page).code == 1
    assert no_tf["hint"] in html.unescape(page.read_text())


def _scans(store: Any) -> list[tuple[str, str, int, object]]:
    """Four laser scans, a second apart: a recording without tf."""
    stamps = [START + i * NS_PER_S for i in range(1, 5)]
    return [("/scan", "sensor_msgs/msg/LaserScan", t, scan(store, "laser", t)) for t in stamps]
