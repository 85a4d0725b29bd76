"""The wheel scripts/build_wheels.sh builds installs where no compiler is found, and its ``tfx`` answers
as the checkout's does on sample_bags/.

``TFTOOLS_WHEEL=dist/tftools-...whl`` tests that wheel (it must be for this interpreter); without it the
test builds one (an sdist, then the wheel from it: minutes of compiling)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SAMPLES = REPO / "sample_bags"
COMPILERS = ("cc", "c++", "gcc", "g++", "clang", "clang++")
#: Every command that needs no live system, run by both the installed wheel and the checkout, each in a
#: folder of its own: their outputs, and the files they write, must be the same.
COMMANDS = [
    ["frames", "-b", str(SAMPLES / "robot.bag")],
    ["frames", "-b", str(SAMPLES / "robot_db3"), "--format", "yaml"],
    ["wtf", str(SAMPLES / "robot.bag"), str(SAMPLES / "robot_db3"), str(SAMPLES / "robot_mcap")],
    ["echo", "map", "gripper", "-b", str(SAMPLES / "robot_mcap"), "--at", "+5"],
    ["echo", "map", "gripper", "-b", str(SAMPLES / "robot_db3"), "--at", "+5", "--format", "json"],
    ["monitor", "map", "gripper", "-b", str(SAMPLES / "robot.bag")],
    ["view-frames", "-b", str(SAMPLES / "robot_mcap"), "-o", "tree.gv"],
    ["report", str(SAMPLES / "robot.bag"), "-o", "report.html"],
    ["diff", str(SAMPLES / "robot.bag"), str(SAMPLES / "robot_db3")],
    ["static", "0.1", "0", "0.2", "0", "0", "0", "base_link", "sonar", "-b", str(SAMPLES / "robot.bag"), "-o", "x.bag"],
]


def _wheel(tmp_path: Path) -> Path:
    given = os.environ.get("TFTOOLS_WHEEL")
    if given:
        return Path(given).resolve()
    dist = tmp_path / "dist"
    env = {**os.environ, "TFTOOLS_DIST": str(dist)}
    subprocess.run(["bash", "scripts/build_wheels.sh", sys.executable], cwd=REPO, env=env, check=True)
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    (wheel,) = dist.glob(f"tftools-*-{tag}-{tag}-manylinux*.whl")
    return wheel


def _run(argv: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True, timeout=600)


@pytest.mark.slow
def test_the_wheel_installs_without_a_compiler_and_answers_as_the_checkout(tmp_path: Path) -> None:
    wheel = _wheel(tmp_path)
    target = tmp_path / "venv"
    venv.create(target, with_pip=True, symlinks=True)
    bin_dir = target / "bin"
    # On PATH only the venv and Graphviz's dot (which view-frames and report run): no compiler to be
    # found; and pip may take binaries only.
    tools = tmp_path / "tools"
    tools.mkdir()
    dot = shutil.which("dot")
    if dot is not None:
        (tools / "dot").symlink_to(dot)
    path = f"{bin_dir}:{tools}"
    assert [c for c in COMPILERS if shutil.which(c, path=path)] == []
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "CC", "CXX")}
    env.update(PATH=path, CC="/nonexistent/cc", CXX="/nonexistent/c++", PIP_ONLY_BINARY=":all:")
    installed = _run([str(bin_dir / "python"), "-m", "pip", "install", "-q", str(wheel)], env, tmp_path)
    assert installed.returncode == 0, installed.stderr

    where = _run([str(bin_dir / "python"), "-c", "import tftools.core._kernels as k; print(k.__file__)"], env, tmp_path)
    assert where.returncode == 0 and where.stdout.startswith(str(target)), where
    version = _run([str(bin_dir / "tfx"), "--version"], env, tmp_path)
    expected = _run([sys.executable, "-c", "from tftools import version; print(version())"], dict(os.environ), REPO)
    assert version.stdout == f"tfx {expected.stdout}", (version, expected)

    checkout = [sys.executable, "-c", "from tftools.cli.app import main; main()"]
    for i, command in enumerate(COMMANDS):
        ours, theirs = tmp_path / f"wheel{i}", tmp_path / f"checkout{i}"
        ours.mkdir()
        theirs.mkdir()
        got = _run([str(bin_dir / "tfx"), *command], env, ours)
        want = _run([*checkout, *command], dict(os.environ), theirs)
        assert (got.returncode, got.stdout, got.stderr) == (want.returncode, want.stdout, want.stderr), command
        written = sorted(p.name for p in theirs.iterdir())
        assert got.returncode == 0 and (got.stdout.strip() or written), (command, got.stderr)
        assert sorted(p.name for p in ours.iterdir()) == written
        differ = [name for name in written if (ours / name).read_bytes() != (theirs / name).read_bytes()]
        assert differ == [], (command, differ)
