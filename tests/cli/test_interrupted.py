"""Ctrl-C (SIGINT) stops tfx with one line, ``tfx: interrupted``, and exit code 130, whenever it comes:
while Python imports tfx's modules at start-up or while the command runs."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tests.cli.test_start_up import modules_after

REPO = Path(__file__).resolve().parents[2]

#: tfx run as its entry point does, SIGINT delivered the moment a given module starts to import (a
#: terminal's Ctrl-C, without guessing at timing); SIGINT handled as in a shell's foreground job.
INTERRUPT_AT_IMPORT = """
import os, signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)
class Interrupt:
    def find_spec(self, name, path=None, target=None):
        if name == {module!r}:
            os.kill(os.getpid(), signal.SIGINT)
        return None
sys.meta_path.insert(0, Interrupt())
sys.argv = {argv!r}
from tftools.cli.app import main
main()
"""

FRAMES = ["tfx", "frames", "-b", str(SAMPLE_BAGS["ros1"])]


@pytest.mark.parametrize(
    "module",
    [
        "typer",  # the parser, before any command
        "numpy",  # the first heavy import
        "tftools.analysis.frames",  # the subcommand's own modules
        "tftools.sources.bag.ros1",  # reading the bag: the command runs
    ],
)
def test_ctrl_c_is_one_line_and_130(module: str) -> None:
    script = INTERRUPT_AT_IMPORT.format(module=module, argv=FRAMES)
    done = subprocess.run([sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=False)
    assert done.returncode == 130, done.stderr
    assert done.stderr == "tfx: interrupted\n"
    assert done.stdout == ""


def test_the_trigger_is_reached() -> None:
    """The modules above are all imported by ``tfx frames`` (else the test above would prove nothing)."""
    modules = modules_after(f"import sys; sys.argv = {FRAMES!r}; from tftools.cli.app import main; main()")
    for module in ("typer", "numpy", "tftools.analysis.frames", "tftools.sources.bag.ros1"):
        assert module in modules
