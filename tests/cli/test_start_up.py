"""Start-up imports only what is used: ``import tftools`` and ``tfx --version`` load no numpy, parser,
live stack or Graphviz, ``tfx frames -b`` loads no other subcommand nor live stack, and ``tfx --help`` and
``tfx COMMAND --help`` no numpy, analysis or reader."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tftools.cli.commands import SUBCOMMANDS

REPO = Path(__file__).resolve().parents[2]
#: Module prefixes no start-up needs.
HEAVY = ("numpy", "graphviz", "matplotlib", "typer", "rich", "tftools.sources.live", "tftools.core")
#: What ``tfx frames -b`` does not use.
NOT_FOR_FRAMES = (
    "graphviz",
    "matplotlib",
    "tftools.sources.live",
    "tftools.cli.live",
    "tftools.cli.echo",
    "tftools.cli.wtf",
    "tftools.cli.view_frames",
    "tftools.cli.static",
    "tftools.analysis.wtf",
    "rich.progress",  # drawn only on a terminal, for a large bag
    "rich._emoji_codes",  # the help's markup read with emoji codes replaced: 2 ms of every command's start-up
)


def modules_after(code: str) -> list[str]:
    """The modules loaded once ``code`` has run, in a fresh interpreter started in the repository."""
    listing = "import json, sys; print(json.dumps(sorted(sys.modules)))"
    script = f"try:\n    {code}\nexcept SystemExit:\n    pass\n{listing}"
    done = subprocess.run([sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=True)
    modules: list[str] = json.loads(done.stdout.strip().splitlines()[-1])
    return modules


def loaded(modules: list[str], prefixes: tuple[str, ...]) -> list[str]:
    return [m for m in modules if any(m == p or m.startswith(p + ".") for p in prefixes)]


def test_import_tftools_loads_nothing_heavy() -> None:
    modules = modules_after("import tftools")
    assert "tftools" in modules
    assert loaded(modules, HEAVY) == []


def test_public_names_still_load_on_use() -> None:
    modules = modules_after("import tftools; tftools.Buffer; tftools.read_recording")
    assert "tftools.core.buffer" in modules and "tftools.sources.recording" in modules


def test_tfx_version_loads_nothing_heavy() -> None:
    modules = modules_after("import sys; sys.argv = ['tfx', '--version']; from tftools.cli.app import main; main()")
    assert "tftools.cli.app" in modules
    assert loaded(modules, HEAVY) == []


def test_tfx_frames_loads_only_its_own_subcommand() -> None:
    bag = SAMPLE_BAGS["ros1"]
    code = f"import sys; sys.argv = ['tfx', 'frames', '-b', {str(bag)!r}]; from tftools.cli.app import main; main()"
    modules = modules_after(code)
    assert "tftools.cli.frames" in modules and "tftools.sources.recording" in modules
    assert loaded(modules, NOT_FOR_FRAMES) == []


def test_tfx_wtf_loads_dask_only_for_dask() -> None:
    bag = SAMPLE_BAGS["ros1"]
    argv = ["tfx", "wtf", str(bag), str(bag)]
    code = f"import sys; sys.argv = {argv!r}; from tftools.cli.app import main; main()"
    modules = modules_after(code)
    assert "tftools.analysis.fleet" in modules
    assert loaded(modules, ("dask", "distributed")) == []


@pytest.mark.parametrize("argv", [["wtf"], ["view-frames", "-f", "dot", "-o", "-"]])
def test_the_checks_on_a_sample_import_no_numpy_ma(argv: list[str]) -> None:
    """``np.unique``'s first call imports numpy.ma (~10 ms of CPU): the checks' distinct values on the sample bag's
    path (each edge's publishers, stamps and repeated stamps) are found without it."""
    command = ["tfx", *argv[:1], "-b", str(SAMPLE_BAGS["ros1"]), *argv[1:]]
    modules = modules_after(f"import sys; sys.argv = {command!r}; from tftools.cli.app import main; main()")
    assert "tftools.analysis.wtf" in modules
    assert loaded(modules, ("numpy.ma",)) == []


#: What no help needs: the arrays, the analyses, the readers, Graphviz.
NOT_FOR_HELP = ("numpy", "graphviz", "matplotlib", "tftools.analysis", "tftools.sources.bag", "tftools.sources.live")


def test_tfx_help_loads_no_subcommand_nor_numpy() -> None:
    modules = modules_after("import sys; sys.argv = ['tfx', '--help']; from tftools.cli.app import main; main()")
    assert "tftools.cli.commands" in modules
    assert loaded(modules, NOT_FOR_HELP) == []
    assert [m for m in modules if m.startswith("tftools.cli.") and m.removeprefix("tftools.cli.") in SUBCOMMANDS] == []


@pytest.mark.parametrize("name", SUBCOMMANDS)
def test_a_subcommands_help_loads_no_numpy(name: str) -> None:
    code = f"import sys; sys.argv = ['tfx', {name!r}, '--help']; from tftools.cli.app import main; main()"
    modules = modules_after(code)
    assert f"tftools.cli.{name.replace('-', '_')}" in modules
    assert loaded(modules, NOT_FOR_HELP) == []


def test_the_help_lists_every_subcommand_with_its_summary() -> None:
    done = subprocess.run([sys.executable, "-m", "tftools", "--help"], cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 0
    for name in SUBCOMMANDS:
        assert f" {name} " in done.stdout
    assert "Print the transform from SOURCE to TARGET" in done.stdout  # echo's, from its docstring


def test_the_defaults_the_help_shows_are_the_analyses_own() -> None:
    from dataclasses import asdict

    from tftools.analysis.expected import Tolerances
    from tftools.analysis.wtf import Thresholds
    from tftools.cli import defaults

    assert defaults.thresholds() == asdict(Thresholds())
    assert defaults.tolerances() == asdict(Tolerances())


def test_a_load_imports_no_frame_name_suggestions() -> None:
    """``difflib`` is for an unknown frame's error: a load that asks for no frame does without it."""
    modules = modules_after(f"import tftools; tftools.read_recording([{str(SAMPLE_BAGS['ros1'])!r}])")
    assert "tftools.sources.recording" in modules
    assert "difflib" not in modules


def blas_timeout_after(code: str, **env: str) -> str | None:
    """``OPENBLAS_THREAD_TIMEOUT`` once ``code`` has run in a fresh interpreter, ``env`` added and the variable
    otherwise unset."""
    environ = {k: v for k, v in os.environ.items() if k != "OPENBLAS_THREAD_TIMEOUT"} | env
    script = f"{code}\nimport json, os\nprint(json.dumps(os.environ.get('OPENBLAS_THREAD_TIMEOUT')))"
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=True, env=environ
    )
    found: str | None = json.loads(done.stdout.strip().splitlines()[-1])
    return found


def test_tfx_lets_numpys_blas_threads_sleep_when_idle_and_a_library_import_leaves_the_process_alone() -> None:
    """tfx sets it before numpy's import (OpenBLAS reads it when loaded), so that its threads do not spin on the core
    the read's threads want; a user's own value kept; ``import tftools`` in a user's script changes nothing."""
    sample = str(SAMPLE_BAGS["ros1"])
    tfx = f"import sys\nsys.argv = ['tfx', 'frames', '-b', {sample!r}]\nfrom tftools.cli import app\napp._run()"
    assert blas_timeout_after(tfx) == "4"
    assert blas_timeout_after(tfx, OPENBLAS_THREAD_TIMEOUT="20") == "20"
    assert blas_timeout_after("import tftools") is None
