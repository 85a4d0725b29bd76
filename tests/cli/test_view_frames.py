"""``tfx view-frames`` on the sample bags and on a bag full of problems: files, their text, exit codes."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path

import graphviz
import pytest

from tests.analysis import robot_scenes
from tests.bags import BagFormat, TfMessage, write_bag
from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tftools.analysis.edges import edge_stats
from tftools.analysis.findings import Severity
from tftools.analysis.monitor import MonitorQuery, monitor
from tftools.analysis.wtf.fleet import check
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.graph import COLOURS, SIGNATURE
from tftools.sources import read_recording

START = 1_700_000_000 * NS_PER_S
MAGIC = {"pdf": b"%PDF", "png": b"\x89PNG", "svg": b"<svg", "dot": f"// {SIGNATURE}".encode()}
WRITE_FORMATS = {"ros1": BagFormat.ros1, "db3": BagFormat.rosbag2_sqlite3, "mcap": BagFormat.rosbag2_mcap}


def bag_formats() -> list[str]:
    return list(SAMPLE_BAGS)


def need(program: str) -> None:
    if shutil.which(program) is None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must have {program}")
        pytest.skip(f"{program} is not installed")


def pdf_lines(path: Path) -> list[str]:
    need("pdftotext")
    text = subprocess.run(["pdftotext", "-raw", str(path), "-"], check=True, capture_output=True, text=True).stdout
    return [line.strip() for line in text.splitlines()]


def contains_block(lines: list[str], block: list[str]) -> bool:
    """Whether ``block`` appears as consecutive lines of ``lines``."""
    n = len(block)
    return any(lines[i : i + n] == block for i in range(len(lines) - n + 1))


def _t(parent: str, child: str, stamp: int, q: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)) -> Transform:
    return Transform((0.1 + (stamp - START) / 1e10, 0.0, 0.0), q, stamp, parent, child)  # moving: not static


def problem_messages() -> list[TfMessage]:
    """10 s of a small robot with a second tree, a loop, a re-parented frame, a stale edge, a gap, a NaN."""
    statics = [_t("base_link", "laser", START), _t("world", "rig", START), _t("rig", "rig_camera", START)]
    messages = [TfMessage("/tf_static", START + 1000, statics, "/rsp")]
    for i in range(100):
        stamp = START + i * 100_000_000
        ts = [] if 30 <= i < 60 else [_t("map", "odom", stamp)]  # silent from 3 s to 6 s
        ts += [_t("odom", "base_link", stamp), _t("loop_a", "loop_b", stamp), _t("loop_b", "loop_a", stamp)]
        if i < 40:
            ts.append(_t("base_link", "wheel", stamp))  # stops at 4 s
        if i % 10 == 0:
            ts.append(_t("base_link" if i < 50 else "odom", "imu", stamp))  # re-parented at 5 s
        if i == 70:
            ts.append(_t("base_link", "arm", stamp, (math.nan, 0.0, 0.0, 1.0)))
        messages.append(TfMessage("/tf", stamp + 2_000_000, ts, "/node"))
    return messages


@pytest.fixture(scope="module")
def problem_bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("problems")
    return {
        name: write_bag(folder / f"problems_{name}", problem_messages(), fmt) for name, fmt in WRITE_FORMATS.items()
    }


@pytest.mark.parametrize("bag", bag_formats())
@pytest.mark.parametrize("fmt", ["pdf", "svg", "png", "dot"])
def test_sample_bag_in_every_format(tfx: Tfx, tmp_path: Path, bag: str, fmt: str) -> None:
    need("dot")
    output = tmp_path / f"graph.{'gv' if fmt == 'dot' else fmt}"
    result = tfx("view-frames", "-b", SAMPLE_BAGS[bag], "-o", output)
    assert result.code == 0, result.stderr
    assert MAGIC[fmt] in output.read_bytes()[:300]
    assert f"wrote {output}: 18 frames, 17 transforms, no problems" in result.stderr
    assert list(tmp_path.iterdir()) == [output]  # nothing else written


def test_an_output_named_without_a_suffix_gets_its_format_s(tfx: Tfx, tmp_path: Path) -> None:
    """ROS 2's ``view_frames -o NAME`` writes NAME.pdf: tfx wrote a PDF named NAME, without a suffix. It writes
    NAME.pdf (NAME.svg with --format svg); ``--wait-time``, view_frames' listening time, is --duration."""
    need("dot")
    named = tfx("view-frames", "-b", SAMPLE_BAGS["db3"], "-o", tmp_path / "tree")
    assert named.code == 0 and f"wrote {tmp_path / 'tree.pdf'}: 18 frames" in named.stderr
    assert tfx("view-frames", "-b", SAMPLE_BAGS["db3"], "-o", tmp_path / "tree", "-f", "svg").code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tree.pdf", "tree.svg"]
    waited = tfx("view-frames", "--wait-time", "10")
    assert waited.code == 2 and "No such option: --wait-time (did you mean --duration?" in waited.stderr
    waited = tfx("view-frames", "-b", SAMPLE_BAGS["db3"], "-t", "10")  # view_frames' -t: tfx's --topic
    assert waited.code == 2 and "tfx view-frames --duration 10" in waited.stderr, waited.stderr
    assert "no transforms on 10" not in waited.stderr


@pytest.mark.parametrize("bag", bag_formats())
def test_pdf_shows_every_frame_and_each_edges_numbers(tfx: Tfx, tmp_path: Path, bag: str) -> None:
    need("dot")
    output = tmp_path / "frames.pdf"
    assert tfx("view-frames", "-b", SAMPLE_BAGS[bag], "-o", output).code == 0
    lines = pdf_lines(output)
    recording = read_recording([SAMPLE_BAGS[bag]])
    for frame in recording.buffer.frames:
        assert frame in lines
    silent = {e.key: e.silent_for for e in monitor(recording, MonitorQuery()).edges}  # monitor's figure
    for s in edge_stats(recording.buffer):
        who = f"Broadcaster: {', '.join(s.authorities)}"
        if s.static:
            assert contains_block(lines, [who, "static"]), s.key
            continue
        age, quiet = (recording.end - s.last_stamp) / NS_PER_S, silent[s.key]
        assert quiet is not None
        block = [
            who,
            f"Average rate: {s.rate_hz:.2f} Hz",
            f"Samples: {s.count}",
            f"Most recent transform: {s.last_stamp / NS_PER_S:.3f} ({age:.3f} s old)",
            f"Silent for the last {seconds(quiet):.3f} s (since it last arrived)",
            f"Oldest transform: {s.first_stamp / NS_PER_S:.3f}",
            f"Buffer length: {(s.last_stamp - s.first_stamp) / NS_PER_S:.3f} s",
            f"Largest gap: {seconds(s.longest_interval):.3f} s",
        ]
        assert contains_block(lines, block), s.key
    span = (recording.end - recording.start) / NS_PER_S
    recorded = f"Recorded at time: {recording.start / NS_PER_S:.3f} to {recording.end / NS_PER_S:.3f} ({span:.3f} s)"
    assert recorded in lines
    assert f"Bag: {SAMPLE_BAGS[bag].name}" in lines
    assert "No problems found" in lines


EXPECTED_CODES = {"cycle", "disconnected", "multiple_parents", "stale", "invalid_values", "rate"}
PINNED = {  # where each problem must be drawn: edges (parent, child) or frames
    "cycle": {"loop_a -> loop_b", "loop_b -> loop_a"},
    "disconnected": {"map", "world"},
    "multiple_parents": {"base_link -> imu", "odom -> imu"},
    "stale": {"base_link -> wheel"},
    "invalid_values": {"base_link -> arm"},
    "rate": {"map -> odom"},
}


@pytest.mark.parametrize("bag", bag_formats())
def test_problems_are_drawn_listed_and_fail_the_exit_code(
    tfx: Tfx, tmp_path: Path, problem_bags: dict[str, Path], bag: str
) -> None:
    need("dot")
    findings = check(read_recording([problem_bags[bag]])).findings
    assert {f.code for f in findings} == EXPECTED_CODES  # the bag shows what it was written to show
    output = tmp_path / "problems.pdf"
    result = tfx("view-frames", "-b", problem_bags[bag], "-o", output)
    assert result.code == 1, result.stderr
    assert "5 errors, 1 warning" in result.stderr
    lines = pdf_lines(output)
    text = "\n".join(lines)
    for number, finding in enumerate(findings, 1):  # listed in the legend, numbered, as tfx wtf says them
        first_words = " ".join(finding.message.split()[:6])
        assert f"[{number}] {finding.severity.value} {first_words}" in text
        marks = [line for line in lines if line == f"[{number}] {finding.code}"]
        assert len(marks) == len(PINNED[finding.code]), finding.code  # on each edge or frame it is about
    assert "rejected: 1 x TF_NAN_INPUT" in lines and "no sample accepted" in lines


def test_dot_on_stdout_carries_the_colours(tfx: Tfx, problem_bags: dict[str, Path]) -> None:
    need("dot")
    result = tfx("view-frames", "-b", problem_bags["mcap"], "--format", "dot", "-o", "-")
    assert result.code == 1
    data = json.loads(graphviz.Source(result.stdout).pipe(format="json0"))
    names = {o["_gvid"]: o["name"] for o in data["objects"]}
    nodes = {o["name"]: o for o in data["objects"]}
    edges = {f"{names[e['tail']]} -> {names[e['head']]}": e for e in data["edges"]}
    red, orange = COLOURS[Severity.error], COLOURS[Severity.warning]
    for code, places in PINNED.items():
        for place in places:
            drawn = edges.get(place) or nodes[place]
            assert drawn["color"] == (orange if code == "rate" else red), place
            assert f"] {code}</B>" in drawn["label"], place
    assert edges["world -> rig"]["style"] == "dashed"
    assert edges["odom -> base_link"]["color"] not in (red, orange)
    assert edges["base_link -> arm"]["style"] == "dotted"


def test_without_dot_the_source_is_written_with_one_line_saying_how_to_get_graphviz(
    tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    empty = tmp_path / "bin"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    result = tfx("view-frames", "-b", SAMPLE_BAGS["mcap"], "-o", tmp_path / "frames.pdf")
    assert result.code == 1
    assert len(result.stderr.strip().splitlines()) == 1
    assert "dot" in result.stderr and "apt-get install graphviz" in result.stderr
    assert not (tmp_path / "frames.pdf").exists()
    source = (tmp_path / "frames.gv").read_text()
    assert source.startswith(f"// {SIGNATURE}")
    assert "\tmap -> odom [label=<Broadcaster: /tf<BR" in source
    again = tfx("view-frames", "-b", SAMPLE_BAGS["mcap"], "-o", tmp_path / "frames.pdf")
    assert again.code == 1  # its own .gv may be replaced
    piped = tfx("view-frames", "-b", SAMPLE_BAGS["mcap"], "-o", "-")
    assert piped.code == 1 and piped.stdout == "" and "apt-get install graphviz" in piped.stderr


def test_without_dot_a_foreign_gv_file_is_not_overwritten(
    tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "frames.gv").write_text("digraph mine {}\n")
    monkeypatch.setenv("PATH", str(tmp_path / "nothing"))
    result = tfx("view-frames", "-b", SAMPLE_BAGS["mcap"], "-o", tmp_path / "frames.pdf")
    assert result.code == 2
    assert "not overwriting" in result.stderr and len(result.stderr.strip().splitlines()) == 1
    assert (tmp_path / "frames.gv").read_text() == "digraph mine {}\n"


def test_default_output_is_frames_pdf_in_the_current_directory(
    tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    need("dot")
    monkeypatch.chdir(tmp_path)
    assert tfx("view-frames", "-b", SAMPLE_BAGS["db3"]).code == 0
    assert tfx("view-frames", "-b", SAMPLE_BAGS["db3"], "--format", "svg", "--rankdir", "LR", "--brief").code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frames.pdf", "frames.svg"]
    assert (tmp_path / "frames.pdf").read_bytes().startswith(b"%PDF")
    svg = (tmp_path / "frames.svg").read_text()
    assert "50.0 Hz" in svg and "Most recent transform" not in svg


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["-o", "x.png", "--format", "pdf"], "does not match"),
        (["-o", "."], "is a directory"),
        (["--rankdir", "XY"], "XY"),
    ],
)
def test_bad_arguments_are_one_line_and_exit_2(
    tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, args: list[str], says: str
) -> None:
    monkeypatch.chdir(tmp_path)
    result = tfx("view-frames", "-b", SAMPLE_BAGS["mcap"], *args)
    assert result.code == 2
    assert says in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_missing_bag_writes_nothing(tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = tfx("view-frames", "-b", tmp_path / "nope.bag")
    assert result.code == 2
    assert "nope.bag" in result.stderr and "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_rankdir_is_taken_in_either_case(tfx: Tfx) -> None:
    """Graphviz's rankdir is upper case; ``--rankdir lr`` means the same and is not refused for its case."""
    lower = tfx("view-frames", "-b", SAMPLE_BAGS["db3"], "--rankdir", "lr", "-f", "dot", "-o", "-")
    upper = tfx("view-frames", "-b", SAMPLE_BAGS["db3"], "--rankdir", "LR", "-f", "dot", "-o", "-")
    assert lower.code == 0 and "rankdir=LR" in lower.stdout and lower.stdout == upper.stdout


def test_notes_are_named_notes_and_decorate_no_edge(tfx: Tfx) -> None:
    """On the Nav2 TurtleBot 4 recording: the statics_early note is in the legend, as a note (the word wtf
    and the report use, not "info"), and its 29 static edges stay dashed blue, untagged; warnings still
    colour their edges."""
    from tests.corpus.fetch import shared_dir
    from tftools.render.graph import STATIC_INK

    bag = shared_dir() / "corpus" / "ros2_mcap_nav2_turtlebot4.mcap"
    if not bag.exists():
        pytest.skip(f"{bag.name} is not in {bag.parent} ($TFTOOLS_SHARED_DIR/corpus)")
    result = tfx("view-frames", "-b", bag, "-f", "dot", "-o", "-")
    assert result.code == 0 and result.stderr.endswith(" notes\n"), result.stderr
    dot = result.stdout
    assert "info" not in re.sub(r'tooltip="[^"]*"', "", dot) and re.search(
        r"Problems: \d+ warnings?( \(explaining \d+ more\))?, 3 notes", dot
    )
    edges = [line for line in dot.splitlines() if " -> " in line and "[label=" in line]
    static = [line for line in edges if "style=dashed" in line]
    assert len(static) == 29 and all(f'color="{STATIC_INK}"' in line for line in static)
    assert not any("statics_early" in line or f'color="{COLOURS[Severity.info]}"' in line for line in edges)
    assert any(f'color="{COLOURS[Severity.warning]}"' in line for line in edges)  # the gaps' rate warnings


def test_view_frames_runs_wtfs_checks_on_the_robots_description_and_counts_as_wtf(tfx: Tfx, tmp_path: Path) -> None:
    """Issue 39: on the CompRobo Neatos that record /robot_description, view-frames counted 1 error where wtf
    counted 2 (urdf_parent): it ran no check of the description. One list of checks, one count."""
    setup = robot_scenes.Setup(description=True, joint_states=("wheel_left_joint",))  # the right wheel never on tf
    bag = robot_scenes.robot_bag(tmp_path, "rover", setup, BagFormat.rosbag2_sqlite3)
    wtf = tfx("wtf", bag)
    summary = wtf.stdout.strip().splitlines()[-1].split(":")[0]  # "1 error, 0 warnings, 1 note"
    assert "urdf_missing" in wtf.stdout and summary.startswith("1 error")
    output = tmp_path / "rover.dot"
    drawn = tfx("view-frames", "-b", bag, "-o", output)
    assert drawn.code == wtf.code == 1, drawn.stderr
    said = drawn.stderr.strip().splitlines()[-1].split("transforms, ")[-1]
    assert said == ", ".join(part for part in summary.split(", ") if not part.startswith("0 ")), (said, summary)
    assert "urdf_missing" in output.read_text()


def test_an_edge_on_another_clock_says_its_delay_is_not_measurable_as_monitor_does(tfx: Tfx, tmp_path: Path) -> None:
    """A robot simulated from 100 s beside a device on the wall clock (the IAS0220 course's Gazebo robot and IMU):
    the simulated edge's label says "not measurable: another clock", as monitor's table; the device's says none,
    as its delay is measured (view-frames shows no delay figures)."""
    from tests.bags import device_beside_simulation_bag

    bag = device_beside_simulation_bag(tmp_path / "two_clocks")
    result = tfx("view-frames", "-b", bag, "--format", "dot", "-o", "-")
    labels = {m[0]: m[1] for m in re.findall(r"\t(\w+ -> \w+) \[label=<(.*?)> ", result.stdout)}
    assert "Delay: not measurable: another clock" in labels["odom -> base_link"], labels
    assert "Delay:" not in labels["imu_link -> range"], labels
    assert "not measurable: another clock" in tfx("monitor", "-b", bag).stdout
