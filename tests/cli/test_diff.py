"""``tfx diff A B`` and ``tfx wtf --init`` / ``--expect`` as a user runs them, on bags of every format."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from tests.analysis.wtf_scenes import FORMATS, healthy, map_odom, periodic, statics, write
from tests.bags import BagFormat
from tests.cli.conftest import Tfx


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A healthy run (ROS 1), the same run again in each format, and a run whose laser moved 10 mm
    and whose localization slowed to 4 Hz, in each format."""
    directory = tmp_path_factory.mktemp("runs")
    made = {"good": write(directory, "good", BagFormat.ros1, healthy())}
    for fmt in FORMATS:
        made[f"same_{fmt.value}"] = write(directory, "same", fmt, healthy())
        changed = healthy(statics=[statics(laser_x=0.21)], amcl=periodic("/amcl", 4, map_odom))
        made[f"changed_{fmt.value}"] = write(directory, "changed", fmt, changed)
    return made


@pytest.mark.parametrize("fmt", FORMATS)
def test_diff_of_the_same_run_in_another_format_is_empty_and_exits_0(
    tfx: Tfx, runs: dict[str, Path], fmt: BagFormat
) -> None:
    result = tfx("diff", runs["good"], runs[f"same_{fmt.value}"])
    assert result.code == 0, result.stderr
    assert "no differences beyond the tolerances (1 mm, 0.1°, rates 20%)" in result.stdout


@pytest.mark.parametrize("fmt", FORMATS)
def test_diff_says_how_far_a_static_edge_moved_and_how_a_rate_fell(
    tfx: Tfx, runs: dict[str, Path], fmt: BagFormat
) -> None:
    result = tfx("diff", runs["good"], runs[f"changed_{fmt.value}"])
    assert result.code == 1
    assert "moved       base_link -> laser (static) moved by 10.0 mm and 0.00°" in result.stdout
    assert "rate        map -> odom at 4.0 Hz in B, 10.0 Hz in A (-60%)" in result.stdout
    assert "2 differences beyond the tolerances" in result.stdout
    loose = tfx("diff", runs["good"], runs[f"changed_{fmt.value}"], "--tolerance-mm", "11", "--tolerance-rate", "70")
    assert loose.code == 0, loose.stdout


def test_diff_json_lists_each_difference_with_its_figures(tfx: Tfx, runs: dict[str, Path]) -> None:
    result = tfx("diff", runs["good"], runs["changed_rosbag2-mcap"], "--format", "json")
    document = json.loads(result.stdout)
    assert result.code == document["exit_code"] == 1 and document["differ"]
    by_change = {d["change"]: d for d in document["differences"]}
    assert set(by_change) == {"moved", "rate"}
    assert by_change["moved"]["translation_mm"] == pytest.approx(10.0)
    assert by_change["moved"]["a"]["translation"] == pytest.approx([0.2, 0.0, 0.1])
    assert by_change["moved"]["b"]["translation"] == pytest.approx([0.21, 0.0, 0.1])
    assert by_change["rate"]["rate_change"] == pytest.approx(-0.6, abs=0.01)


def test_diff_of_a_tree_file_and_a_recording_uses_the_files_tolerances(
    tfx: Tfx, runs: dict[str, Path], tmp_path: Path
) -> None:
    init = tfx("wtf", "--init", runs["good"])
    assert init.code == 0, init.stderr
    tree = tmp_path / "tree.yaml"
    tree.write_text(init.stdout.replace("translation_mm: 1.0", "translation_mm: 15.0"))
    result = tfx("diff", tree, runs["changed_rosbag2-sqlite3"])
    assert result.code == 1
    assert [line.split()[0] for line in result.stdout.splitlines()[2:-1]] == ["rate"]  # the laser's 10 mm: within
    assert "(15 mm, 0.1°, rates 20%)" in result.stdout


def test_diff_of_unusable_input_exits_2_with_one_line(tfx: Tfx, runs: dict[str, Path], tmp_path: Path) -> None:
    missing = tfx("diff", runs["good"], tmp_path / "nope.bag")
    assert missing.code == 2 and missing.stderr.count("\n") == 1 and "nope.bag" in missing.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text("frames: {a: {parnet: b}}\n")
    broken = tfx("diff", bad, runs["good"])
    assert broken.code == 2 and "unknown key 'parnet'" in broken.stderr and "Traceback" not in broken.stderr
    negative = tfx("diff", runs["good"], runs["good"], "--tolerance-mm", "-1")
    assert negative.code == 2 and "translation_mm" in negative.stderr


@pytest.mark.parametrize("fmt", FORMATS)
def test_wtf_expect_reports_what_differs_from_the_init_file(
    tfx: Tfx, runs: dict[str, Path], tmp_path: Path, fmt: BagFormat
) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text(tfx("wtf", "--init", runs["good"]).stdout)
    assert tfx("wtf", "--expect", tree, runs[f"same_{fmt.value}"]).code == 0
    result = tfx("wtf", "--expect", tree, runs[f"changed_{fmt.value}"], "--format", "json")
    assert result.code == 1
    findings = json.loads(result.stdout)["bags"][0]["findings"]
    assert [(f["code"], f["severity"]) for f in findings] == [("expect_static", "error"), ("expect_rate", "warning")]
    loose = tfx("wtf", "--expect", tree, runs[f"changed_{fmt.value}"], "--tolerance-mm", "11", "--strict")
    assert loose.code == 1 and "expect_static" not in loose.stdout and "expect_rate" in loose.stdout


def test_wtf_expect_findings_reach_junit_and_can_be_ignored(tfx: Tfx, runs: dict[str, Path], tmp_path: Path) -> None:
    tree = tmp_path / "tree.yaml"
    tree.write_text(tfx("wtf", "--init", runs["good"]).stdout)
    junit = ET.fromstring(tfx("wtf", "--expect", tree, runs["changed_ros1"], "--format", "junit").stdout)
    failed = {case.get("name") for case in junit.iter("testcase") if case.find("failure") is not None}
    assert "expect_static" in failed
    ignored = tfx("wtf", "--expect", tree, runs["changed_ros1"], "--ignore", "expect_static")
    assert ignored.code == 0 and "expect_rate" in ignored.stdout


def test_wtf_init_and_tolerances_refuse_what_cannot_work(tfx: Tfx, runs: dict[str, Path]) -> None:
    two = tfx("wtf", "--init", runs["good"], runs["same_ros1"])
    assert two.code == 2 and "one recording" in two.stderr
    assert tfx("wtf", runs["good"], "--tolerance-mm", "2").code == 2
    missing = tfx("wtf", "--expect", "nope.yaml", runs["good"])
    assert missing.code == 2 and "nope.yaml: no such file" in missing.stderr
