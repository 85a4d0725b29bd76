"""Every command leaves its inputs byte for byte unchanged, whatever its flags (the listing of a bag
directory and each file's bytes and modification time, before and after)."""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS, Tfx

STATIC = ("static", "0", "0", "1", "0", "0", "0", "base_link", "extra")
FRAME = "base_link"

#: (name, arguments): ``BAG`` stands for the copied input, ``OUT`` for a fresh path beside it, ``INSIDE`` for
#: a path inside the input (or beside it, for a single file), ``HOLDER`` for the folder holding it.
CASES = {
    "frames": ("frames", "-b", "BAG"),
    "frames-json": ("frames", "-b", "BAG", "-f", "json"),
    "frames-yaml": ("frames", "-b", "BAG", "-f", "yaml"),
    "echo": ("echo", "map", FRAME, "-b", "BAG"),
    "echo-csv-range": ("echo", "map", FRAME, "-b", "BAG", "-f", "csv", "--start", "+1", "--end", "+3", "-r", "5"),
    "echo-all-json": ("echo", "map", FRAME, "-b", "BAG", "--all", "-f", "json"),
    "echo-at": ("echo", "map", "gripper", "-b", "BAG", "--at", "-1", "--matrix"),
    "echo-play": ("echo", "map", FRAME, "-b", "BAG", "--play", "--start", "-0.3", "--rate", "10"),
    "echo-bad-time": ("echo", "map", FRAME, "-b", "BAG", "--end", "1e12"),
    "monitor": ("monitor", "-b", "BAG"),
    "monitor-chain-json": ("monitor", "map", "gripper", "-b", "BAG", "-f", "json", "--start", "+2"),
    "monitor-play": ("monitor", "-b", "BAG", "--play", "--start", "-1", "--rate", "4", "--duration", "0.3"),
    "wtf": ("wtf", "BAG"),
    "filter-nothing-to-check": ("filter", "-b", "BAG"),  # the sample robot has no sensor data: said, exit 0
    "filter-tf-json-bad": ("filter", "/tf", "-b", "BAG", "--queue", "2", "-f", "json"),
    "wtf-b-json": ("wtf", "-b", "BAG", "-f", "json", "--strict"),
    "wtf-junit": ("wtf", "BAG", "-f", "junit", "--jobs", "2", "BAG"),
    "view-frames-dot": ("view-frames", "-b", "BAG", "-f", "dot", "-o", "-"),
    "view-frames-out": ("view-frames", "-b", "BAG", "-o", "OUT.gv"),
    "view-frames-onto-input": ("view-frames", "-b", "BAG", "-o", "BAG"),
    "view-frames-inside": ("view-frames", "-b", "BAG", "-o", "INSIDE"),
    "view-frames-holder": ("view-frames", "-b", "BAG", "-o", "HOLDER"),
    "static-copy": (*STATIC, "-b", "BAG", "-o", "OUT"),
    "static-onto-input": (*STATIC, "-b", "BAG", "-o", "BAG", "--force"),
    "static-inside": (*STATIC, "-b", "BAG", "-o", "INSIDE", "--force"),
    "static-holder": (*STATIC, "-b", "BAG", "-o", "HOLDER", "--force"),
    "static-metadata": (*STATIC, "-b", "BAG", "-o", "METADATA", "--force"),
    "report": ("report", "-b", "BAG", "-o", "OUT.html"),
    "report-fleet": ("report", "BAG", "BAG", "-o", "OUT.html"),
    "report-onto-input": ("report", "-b", "BAG", "-o", "BAG"),
    "report-inside": ("report", "BAG", "-o", "INSIDE"),
    "echo-plot": ("echo", "map", FRAME, "-b", "BAG", "--plot", "OUT.svg"),
    "monitor-plot-play": ("monitor", "-b", "BAG", "--play", "--start", "-1", "--rate", "4", "--plot", "OUT.png"),
    "echo-plot-onto-input": ("echo", "map", FRAME, "-b", "BAG", "--plot", "BAG"),
    "diff-json": ("diff", "BAG", "BAG", "-f", "json", "--tolerance-mm", "2"),
    "wtf-init": ("wtf", "--init", "BAG"),
    "echo-static": ("echo", "map", "gripper", "-b", "BAG", "-f", "static"),
    "echo-urdf-at": ("echo", "map", "gripper", "-b", "BAG", "-f", "urdf", "--at", "+2"),
}

#: The cases that must be refused (exit 2, one line); every other one runs (exit 0 or 1).
REFUSED = {name for name in CASES if any(word in name for word in ("onto", "inside", "holder", "metadata", "bad"))}


def fingerprint(path: Path) -> dict[str, tuple[str, int]]:
    """Each file under ``path`` (or ``path`` itself): its SHA-256 and modification time; folders listed too."""
    paths = [path, *sorted(path.rglob("*"))] if path.is_dir() else [path]
    result = {}
    for p in paths:
        stat = p.stat()
        digest = hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else "folder"
        result[str(p.relative_to(path.parent))] = (digest, stat.st_mtime_ns)
    return result


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
@pytest.mark.parametrize("case", list(CASES))
def test_inputs_unchanged(tfx: Tfx, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str, case: str) -> None:
    holder = tmp_path / "recordings"
    holder.mkdir()
    sample = SAMPLE_BAGS[fmt]
    bag = holder / sample.name
    (shutil.copytree if sample.is_dir() else shutil.copy2)(sample, bag)
    names = {
        "BAG": str(bag),
        "OUT": str(tmp_path / f"out{'.bag' if fmt == 'ros1' else ''}"),
        "OUT.gv": str(tmp_path / "out.gv"),
        "OUT.html": str(tmp_path / "out.html"),
        "OUT.svg": str(tmp_path / "out.svg"),
        "OUT.png": str(tmp_path / "out.png"),
        "INSIDE": str(bag / "inside" if bag.is_dir() else bag.with_suffix(".bag.d") / "x"),
        "HOLDER": str(holder),
        "METADATA": str(bag / "metadata.yaml" if bag.is_dir() else bag),
    }
    args = [names.get(a, a) for a in CASES[case]]
    before = fingerprint(bag)
    listing = sorted(p.name for p in holder.iterdir())
    monkeypatch.chdir(tmp_path)
    result = tfx(*args)
    assert "Traceback" not in result.stderr
    if case in REFUSED:
        assert result.code == 2 and result.stderr.startswith("tfx: error: "), result.stderr
    else:
        assert result.code in (0, 1), result.stderr
    assert fingerprint(bag) == before
    assert sorted(p.name for p in holder.iterdir()) == listing
