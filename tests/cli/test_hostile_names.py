"""Names from files (frames, publishers, file names) never act on the terminal, the markup or the graph."""

from __future__ import annotations

import json
import os
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import graphviz
import pytest

import tftools.render.wtf
from tests.cli.conftest import HOSTILE_NAMES, HOSTILE_PUBLISHER, SAMPLE_BAGS, Tfx
from tftools.render.escape import printable

FORMATS = ("ros1", "db3", "mcap")
#: What must never reach a terminal: escape sequences, bell, carriage return, bidi override, emoji
#: made from ``:smile:``, rich markup applied (its text gone).
RAW = ("\x1b", "\x07", "\r", "\u202e", "\U0001f604")

TEXT_COMMANDS = {
    "frames": ("frames",),
    "frames-yaml": ("frames", "-f", "yaml"),
    "monitor": ("monitor",),
    "monitor-chain": ("monitor", "map", HOSTILE_NAMES[-1]),
    "wtf": ("wtf",),
    "echo": ("echo", "map", HOSTILE_NAMES[-1], "--at", "+1"),
    "echo-csv": ("echo", "map", HOSTILE_NAMES[-1], "--at", "+1", "-f", "csv"),
    "echo-missing": ("echo", "map", "missing", "--at", "+1"),
    "echo-failing": ("echo", HOSTILE_NAMES[0], "nowhere", "--at", "+1"),
}


def assert_safe(text: str) -> None:
    for raw in RAW:
        assert raw not in text, repr(raw)


def assert_one_line_errors(stderr: str) -> None:
    for line in stderr.splitlines():
        assert line.startswith(("tfx: error: ", "tfx: warning: ", "wrote ")), line[:200]
    assert "Traceback" not in stderr


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("name", list(TEXT_COMMANDS))
def test_text_output_shows_names_escaped(
    tfx: Tfx, hostile_bags: dict[str, Path], fmt: str, name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    # every hostile frame through the text renderer: the ROS 1 bag's one publisher of constant edges is one cause,
    # whose followers the text would cut at SHOWN_PER_CODE
    monkeypatch.setattr(tftools.render.wtf, "SHOWN_PER_CODE", len(HOSTILE_NAMES))
    args = TEXT_COMMANDS[name]
    result = tfx(*args, hostile_bags[fmt]) if args[0] == "wtf" else tfx(*args, "-b", hostile_bags[fmt])
    assert result.code in (0, 1, 2), result.stderr
    assert_safe(result.stdout + result.stderr)
    assert_one_line_errors(result.stderr)
    if name == "echo-missing":
        assert result.code == 2 and result.stderr.count("\n") == 1
        assert printable(HOSTILE_NAMES[1]) in result.stderr  # the close matches, escaped, on the one line
    if name in ("frames", "monitor", "wtf"):
        shown = result.stdout
        assert "[bold]markup[/bold]" in shown and ":smile:" in shown  # literally, not as markup or emoji
        assert "\\x1b[31mred\\x1b[0m" in shown and "line\\nbreak" in shown
        assert "tab\\there\\r\\x07\\u202eevil" in shown
    if name in ("frames", "monitor") and fmt == "ros1":  # ROS 2 bags do not record publishers
        assert printable(HOSTILE_PUBLISHER) in result.stdout


@pytest.mark.parametrize("fmt", FORMATS)
def test_json_keeps_the_exact_names(tfx: Tfx, hostile_bags: dict[str, Path], fmt: str) -> None:
    frames = json.loads(tfx("frames", "-b", hostile_bags[fmt], "-f", "json").stdout)
    assert {f["frame"] for f in frames["frames"]} == {"map", *HOSTILE_NAMES}
    monitor = json.loads(tfx("monitor", "-b", hostile_bags[fmt], "-f", "json").stdout)
    assert {e["child"] for e in monitor["edges"]} == set(HOSTILE_NAMES)
    wtf = json.loads(tfx("wtf", hostile_bags[fmt], "-f", "json").stdout)
    messages = " ".join(f["message"] for f in wtf["bags"][0]["findings"])
    assert HOSTILE_NAMES[0] in messages
    echo = tfx("echo", "map", HOSTILE_NAMES[1], "-b", hostile_bags[fmt], "--at", "+1", "-f", "json")
    assert json.loads(echo.stdout)["child_frame_id"] == HOSTILE_NAMES[1]


@pytest.mark.parametrize("fmt", FORMATS)
def test_junit_is_valid_xml(tfx: Tfx, hostile_bags: dict[str, Path], fmt: str) -> None:
    result = tfx("wtf", hostile_bags[fmt], "-f", "junit")
    root = ET.fromstring(result.stdout)  # XML 1.0 cannot hold control characters: they are escaped
    failures = " ".join(e.text or "" for e in root.iter("system-out"))
    assert_safe(result.stdout)
    assert "\\x1b[31mred" in failures or "\\x1b[31mred" in result.stdout


@pytest.mark.parametrize("fmt", FORMATS)
def test_graph_source_reads_back_with_every_frame(tfx: Tfx, hostile_bags: dict[str, Path], fmt: str) -> None:
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    result = tfx("view-frames", "-b", hostile_bags[fmt], "-f", "dot", "-o", "-")
    assert result.code in (0, 1), result.stderr
    assert_one_line_errors(result.stderr)
    data = json.loads(graphviz.Source(result.stdout).pipe(format="json0", quiet=True))
    labels = " ".join(o.get("label", "") for o in data["objects"])
    for name in HOSTILE_NAMES:
        shown = printable(name)[:50].replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
        assert shown.replace('"', "&quot;") in labels, name[:50]
    frames = [o for o in data["objects"] if "nodes" not in o and not o["name"].startswith("legend")]
    assert len(frames) == len(HOSTILE_NAMES) + 1
    assert len(data["edges"]) >= len(HOSTILE_NAMES)


@pytest.mark.parametrize("picture", ["pdf", "svg"])
def test_graph_is_drawn(tfx: Tfx, hostile_bags: dict[str, Path], tmp_path: Path, picture: str) -> None:
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    output = tmp_path / f"frames.{picture}"
    result = tfx("view-frames", "-b", hostile_bags["mcap"], "-o", output)
    assert result.code in (0, 1) and output.stat().st_size > 0, result.stderr
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("wrote ")


def test_a_file_name_with_escapes_and_bytes_that_are_not_utf8(tfx: Tfx, tmp_path: Path) -> None:
    name = os.fsdecode(b"run\x1b[2J\xff\n.bag")
    bag = tmp_path / name
    shutil.copy(SAMPLE_BAGS["ros1"], bag)
    for args in (("wtf", bag), ("frames", "-b", bag), ("echo", "map", "nope", "-b", bag)):
        result = tfx(*args)
        assert_safe(result.stdout + result.stderr)
        assert_one_line_errors(result.stderr)
    (tmp_path / "empty").mkdir()
    missing = tfx("frames", "-b", tmp_path / "empty" / name)
    assert missing.code == 2 and missing.stderr.count("\n") == 1 and "\\x1b[2J\\xff\\n.bag" in missing.stderr
