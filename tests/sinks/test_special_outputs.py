"""An output is written only as a regular file: a FIFO or a device named as one is refused in one line (exit 2),
``--force`` or not, and is still what it was afterwards (issue 44: ``-o PIPE --force`` replaced a FIFO with a bag,
``-o /dev/null --force`` as root replaced /dev/null)."""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS, Result, Tfx, tfx  # noqa: F401 (the fixture)
from tftools.core.transform import Transform
from tftools.render.files import OutputError, write_atomically
from tftools.sinks.static_bag import add_static_transforms
from tftools.sources.errors import BagError

NULL = Path(os.devnull)
STATIC = ("static", "0", "0", "1", "0", "0", "0", "base_link", "extra")


@pytest.fixture
def fifo(tmp_path: Path) -> Path:
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


def _kind(path: Path) -> Callable[[int], bool]:
    mode = path.stat().st_mode
    return stat.S_ISFIFO if stat.S_ISFIFO(mode) else stat.S_ISCHR


def _refused(result: Result, special: Path) -> None:
    assert result.code == 2, result.stderr
    assert result.stderr.count("\n") == 1 and "not a regular file" in result.stderr, result.stderr
    assert str(special) in result.stderr


@pytest.mark.parametrize("force", [True, False])
@pytest.mark.parametrize("repair", [True, False])
def test_static_never_replaces_a_fifo_or_a_device(tfx: Tfx, fifo: Path, force: bool, repair: bool) -> None:  # noqa: F811
    for special in (fifo, NULL):
        kind = _kind(special)
        given = ("static", "--repair") if repair else STATIC
        _refused(tfx(*given, "-b", SAMPLE_BAGS["ros1"], "-o", special, *(["--force"] if force else [])), special)
        assert kind(special.stat().st_mode), f"{special} is no longer what it was"


@pytest.mark.parametrize("command", [("view-frames",), ("report",)])
def test_file_outputs_never_replace_a_fifo_or_a_device(tfx: Tfx, fifo: Path, command: tuple[str, ...]) -> None:  # noqa: F811
    for special in (fifo, NULL):
        kind = _kind(special)
        _refused(tfx(*command, "-b", SAMPLE_BAGS["db3"], "-o", special), special)
        assert kind(special.stat().st_mode)


def test_a_link_to_a_device_is_refused_too(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    link = tmp_path / "out.bag"
    link.symlink_to(NULL)
    _refused(tfx(*STATIC, "-b", SAMPLE_BAGS["ros1"], "-o", link, "--force"), link)
    assert link.is_symlink() and stat.S_ISCHR(NULL.stat().st_mode)


def test_the_library_never_replaces_a_fifo_or_a_device(fifo: Path) -> None:
    laser = Transform((0.1, 0.0, 0.2), (0.0, 0.0, 0.0, 1.0), 0, "base_link", "laser")
    for special in (fifo, NULL):
        kind = _kind(special)
        with pytest.raises(BagError, match="not a regular file"):
            add_static_transforms(SAMPLE_BAGS["ros1"], special, [laser], force=True)
        with pytest.raises(OutputError, match="not a regular file"):
            write_atomically(special, b"drawing")
        assert kind(special.stat().st_mode)


def test_force_still_replaces_an_earlier_output(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    out = tmp_path / "out.bag"
    out.write_bytes(b"an earlier output")
    done = tfx(*STATIC, "-b", SAMPLE_BAGS["ros1"], "-o", out, "--force")
    assert done.code == 0, done.stderr
    assert out.read_bytes().startswith(b"#ROSBAG V2.0")
