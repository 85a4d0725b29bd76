"""Damaged copies of the corpus's real recordings, made where a test asks (never in the corpus)."""

from __future__ import annotations

import random
import shutil
from pathlib import Path
from typing import Any

import pytest

from tests.corpus.fetch import shared_dir
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import batch_rows

TOPICS = ("/tf", "/tf_static")


def copied(name: str, into: Path) -> Path:
    """A copy in ``into`` of the corpus recording ``name`` (a file or a bag directory, links followed)."""
    original = shared_dir() / "corpus" / name
    if not original.exists():
        pytest.skip(f"{name} is not in {original.parent}")
    target = into / original.name
    if original.is_dir():
        shutil.copytree(original, target)
    else:
        shutil.copyfile(original, target)
    for path in [target, *target.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    return target


def overwritten(path: Path, share: float, seed: int = 43, length: int = 16) -> None:
    """``length`` bytes from ``share`` of the file overwritten with seeded noise."""
    data = bytearray(path.read_bytes())
    start = int(len(data) * share)
    rng = random.Random(seed)
    data[start : start + length] = bytes(rng.randrange(256) for _ in range(length))
    path.write_bytes(bytes(data))


def zeroed_pages(db3: Path, share: float, length: int = 1 << 16) -> None:
    """``length`` bytes of whole pages zeroed from ``share`` of a .db3 (its pages are 4 KiB)."""
    data = bytearray(db3.read_bytes())
    at = int(len(data) * share) // 4096 * 4096
    data[at : at + length] = bytes(length)
    db3.write_bytes(bytes(data))


def cut(path: Path, size: int) -> None:
    with path.open("r+b") as f:
        f.truncate(size)


def rows(path: Path) -> tuple[list[tuple[Any, ...]], list[str]]:
    contents = read_contents([path], TOPICS)
    return batch_rows(contents.transforms), contents.problems
