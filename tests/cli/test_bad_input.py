"""The README's promise on bad input, tested: a one-line error that says what to do, never a traceback."""

from __future__ import annotations

import random
import shutil
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS, Tfx

COMMANDS = {
    "frames": ("frames", "-b", "BAG"),
    "frames-json": ("frames", "-b", "BAG", "-f", "json"),
    "echo": ("echo", "map", "base_link", "-b", "BAG"),
    "echo-csv": ("echo", "map", "gripper", "-b", "BAG", "-f", "csv", "--at", "+1"),
    "monitor": ("monitor", "-b", "BAG"),
    "monitor-play": ("monitor", "-b", "BAG", "--play", "--rate", "1000", "-f", "json"),
    "echo-play": ("echo", "map", "base_link", "-b", "BAG", "--play", "--start", "-0.2", "-r", "10"),
    "view-frames": ("view-frames", "-b", "BAG", "-f", "dot", "-o", "-"),
    "wtf": ("wtf", "BAG"),
    "filter": ("filter", "-b", "BAG"),
    "filter-json": ("filter", "-b", "BAG", "--queue", "2", "-f", "json"),
    "wtf-b": ("wtf", "-b", "BAG", "-f", "junit"),
    "static": ("static", "0", "0", "1", "0", "0", "0", "base_link", "extra", "-b", "BAG", "-o", "OUT"),
    "report": ("report", "-b", "BAG", "-o", "OUT"),
    "diff": ("diff", "BAG", "BAG", "-f", "json"),
    "wtf-init": ("wtf", "--init", "BAG"),
    "echo-static": ("echo", "map", "gripper", "-b", "BAG", "-f", "static"),
}


def hostile_inputs(folder: Path) -> dict[str, Path]:
    """Inputs a new user or a broken disk produces: nothing, not a bag, empty, noise, truncated bags."""
    rng = random.Random(14)
    made: dict[str, Path] = {"missing": folder / "missing.bag"}
    (folder / "not_a_bag").mkdir()
    (folder / "not_a_bag" / "notes.txt").write_text("hello\n")
    made["not-a-bag-folder"] = folder / "not_a_bag"
    (folder / "empty_folder").mkdir()
    made["empty-folder"] = folder / "empty_folder"
    for suffix in (".bag", ".db3", ".mcap"):
        empty = folder / f"empty{suffix}"
        empty.touch()
        made[f"empty{suffix}"] = empty
        noise = folder / f"noise{suffix}"
        noise.write_bytes(rng.randbytes(50_000))
        made[f"noise{suffix}"] = noise
    ros1 = folder / "truncated.bag"
    ros1.write_bytes(SAMPLE_BAGS["ros1"].read_bytes()[:300_000])
    made["truncated.bag"] = ros1
    for key in ("db3", "mcap"):
        copy = folder / f"truncated_{key}"
        shutil.copytree(SAMPLE_BAGS[key], copy)
        data = next(p for p in copy.iterdir() if p.suffix == f".{key}")
        data.write_bytes(data.read_bytes()[: data.stat().st_size // 2])
        made[f"truncated-{key}"] = copy
        bare = folder / f"truncated_bare.{key}"
        shutil.copy(data, bare)
        made[f"truncated-bare.{key}"] = bare
    metadata = folder / "bad_metadata"
    shutil.copytree(SAMPLE_BAGS["mcap"], metadata)
    (metadata / "metadata.yaml").write_text("rosbag2_bagfile_information: [unclosed\n")
    made["bad-metadata"] = metadata
    return made


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return hostile_inputs(tmp_path_factory.mktemp("hostile_inputs"))


UNUSABLE = {
    "missing",
    "not-a-bag-folder",
    "empty-folder",
    *(f"{k}.{s}" for k in ("empty", "noise") for s in ("bag", "db3", "mcap")),
}
INPUTS = sorted([*UNUSABLE, "truncated.bag", "truncated-db3", "truncated-mcap", "truncated-bare.db3",
                 "truncated-bare.mcap", "bad-metadata"])  # fmt: skip


def check_stderr(stderr: str, code: int) -> None:
    assert "Traceback" not in stderr and "internal error" not in stderr, stderr
    lines = stderr.splitlines()
    for line in lines:
        assert line.startswith(("tfx: error: ", "tfx: warning: ", "wrote ")), line
    errors = [line for line in lines if line.startswith("tfx: error: ")]
    assert len(errors) == (1 if code == 2 else 0), stderr


def _nesting(line: str) -> int:
    """How deep the line's parentheses go."""
    depth = deepest = 0
    for character in line:
        depth += {"(": 1, ")": -1}.get(character, 0)
        deepest = max(deepest, depth)
    return deepest


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("name", INPUTS)
def test_bad_input_is_one_line(tfx: Tfx, inputs: dict[str, Path], tmp_path: Path, name: str, command: str) -> None:
    args = [{"BAG": str(inputs[name]), "OUT": str(tmp_path / "out")}.get(a, a) for a in COMMANDS[command]]
    result = tfx(*args)
    check_stderr(result.stderr, result.code)
    errors = [line for line in result.stderr.splitlines() if line.startswith("tfx: error: ")]
    if command != "static":  # static -b's copy errors are being reworked with --repair: they quote a library's
        assert all(_nesting(line) <= 1 for line in errors), f"parentheses inside parentheses: {errors}"
    if name in UNUSABLE:
        assert result.code == 2, result.stdout[-500:] + result.stderr
        assert result.stdout == "" or command == "wtf-b"  # JUnit says it too
    else:  # what can still be read is used; what cannot is said
        assert result.code in (0, 1, 2), result.stderr


@pytest.mark.parametrize(
    "args",
    [
        ("echo", "map", "nowhere", "-b", SAMPLE_BAGS["ros1"]),
        ("echo", "nowhere", "map", "-b", SAMPLE_BAGS["db3"], "--at", "+1"),
        ("monitor", "map", "nowhere", "-b", SAMPLE_BAGS["mcap"]),
        ("echo", "map", "base_link", "-b", SAMPLE_BAGS["mcap"], "--at", "nan"),
        ("echo", "map", "base_link", "-b", SAMPLE_BAGS["mcap"], "--start", "nan"),
        ("monitor", "-b", SAMPLE_BAGS["ros1"], "--end", "nan"),
        ("wtf", SAMPLE_BAGS["ros1"], "--delay", "nan"),
        ("diff", SAMPLE_BAGS["ros1"], SAMPLE_BAGS["db3"], "--tolerance-mm", "nan"),
        ("echo", "map", "base_link", "-b", SAMPLE_BAGS["ros1"], "--topic", "/nothing"),
    ],
)
def test_bad_arguments_on_a_good_bag(tfx: Tfx, args: tuple[str, ...]) -> None:
    result = tfx(*args)
    assert result.code == 2 and result.stdout == ""
    check_stderr(result.stderr, result.code)


def test_a_fleet_with_bad_bags_runs_and_says_which(tfx: Tfx, inputs: dict[str, Path]) -> None:
    result = tfx("wtf", SAMPLE_BAGS["ros1"], inputs["noise.bag"], inputs["missing"], inputs["truncated-mcap"])
    assert result.code == 1
    check_stderr(result.stderr, result.code)
    assert "internal error" not in result.stdout and "2 unusable" in result.stdout
