"""The version is written once, in pyproject.toml: ``tfx --version``, ``tftools.__version__`` and the
JSON outputs' ``version`` all read the installed distribution's."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import tftools

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def _declared() -> str:
    found = re.search(r'^version = "([^"]+)"$', PYPROJECT.read_text(), re.MULTILINE)
    assert found is not None, "pyproject.toml names no version"
    return found.group(1)


def test_the_version_is_pyprojects() -> None:
    assert tftools.version() == tftools.__version__ == _declared()


def test_tfx_version_prints_it() -> None:
    done = subprocess.run(
        [sys.executable, "-c", "from tftools.cli.app import main; main()", "--version"],
        capture_output=True,
        text=True,
    )
    assert (done.returncode, done.stdout) == (0, f"tfx {_declared()}\n")
