"""The README a new user meets and the documentation site: the README short, its links and pictures
there, nothing in it that goes stale (issue numbers, test-time figures, performance figures), and the
pages under docs/ built by MkDocs with every warning an error."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = (REPO / "README.md").read_text(encoding="utf-8")


def test_the_readme_is_short_and_its_links_are_there() -> None:
    assert len(README.splitlines()) <= 220
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README)
    local = [link for link in links if "://" not in link]
    assert local and all((REPO / link).exists() for link in local), [k for k in local if not (REPO / k).exists()]
    pictures = [link for link in local if link.endswith(".png")]
    assert {"docs/pictures/wtf.png", "docs/pictures/monitor.png", "docs/pictures/view-frames.png"} <= set(pictures)
    assert all((REPO / p).stat().st_size < 400_000 for p in pictures)


def test_the_readme_says_nothing_that_goes_stale() -> None:
    assert not re.search(r"\bissues? \d+|#\d{2,}", README, flags=re.I)  # issue numbers
    assert not re.search(r"\d+ tests\b|\bs of CPU\b", README)  # test counts and times
    assert not re.search(r"\d\s*(µs|us|ns)\b", README)  # performance figures: docs/performance.md
    assert "pip install tftools " not in README.replace("`pip install tftools` does not find it", "")


def test_the_site_builds_without_a_warning(tmp_path: Path) -> None:
    if shutil.which("mkdocs", path=os.path.dirname(sys.executable)) is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI installs the dev extra, which has MkDocs")
        pytest.skip("MkDocs is not installed (pip install -e '.[dev]')")
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(tmp_path / "site")], cwd=REPO,
        capture_output=True, text=True,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "site" / "commands" / "index.html").is_file()
