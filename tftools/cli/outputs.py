"""Where a command may write: never over, into or above its input, nor over a FIFO or device; a file already there
is replaced only with ``--force``, one rule for every command that writes a file (``check_replaceable``)."""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable, Sequence
from pathlib import Path

from tftools.cli.errors import UsageError
from tftools.sources.storage.locations import METADATA, is_url, only_bag_files


def protected(bags: Iterable[str | os.PathLike[str]]) -> list[Path]:
    """Every path an output must keep clear of, resolved: each local input, and the rosbag2 directory
    around an input given as one of its files (``-b bag/bag.db3`` or ``-b bag/metadata.yaml``).
    A URL is never written: outputs are local."""
    paths: list[Path] = []
    for bag in bags:
        if is_url(bag):
            continue
        path = Path(bag).resolve()
        paths.append(path)
        if path.name == METADATA or (path.parent / METADATA).is_file():
            paths.append(path.parent)
    return paths


def check_output(
    output: Path, bags: Sequence[str | os.PathLike[str]], *, option: str = "-o", file_name: str | None = None
) -> Path:
    """``output`` if writing it leaves every input in ``bags`` untouched: a ``UsageError`` when it is an
    input (or a link to one), lies inside a rosbag2 input directory, or is a folder holding an input;
    when its folder does not exist; or, for a ``file_name`` (the example in the hint), when it is a folder."""
    target = Path(output).resolve()
    for path in protected(bags):
        said = f"{option} {output}"
        if target == path or _same_file(target, path):
            raise UsageError(f"{said} is the input {path}", "tfx never writes over its input: name another output")
        if target.is_relative_to(path):
            raise UsageError(
                f"{said} is inside the input bag {path}", "tfx never writes into its input: name an output outside it"
            )
        if path.is_relative_to(target):
            raise UsageError(f"{said} holds the input {path}", "name a file for the output, away from the input")
    kind = _special(output)
    if kind:
        raise UsageError(f"{option} {output} is {kind}, not a regular file", _SPECIAL_HINT)
    folder = target.parent
    if not folder.is_dir():
        raise UsageError(
            f"{option} {output}: the folder {folder} does not exist", f"create it first: mkdir -p {folder}"
        )
    if file_name is not None and output.is_dir():
        raise UsageError(f"{option} {output} is a directory", f"give a file name, e.g. {option} {output / file_name}")
    return Path(output)


def check_replaceable(output: Path, force: bool, option: str = "-o") -> None:
    """An existing ``output`` is replaced only with ``force``, and only when it is a regular file or a bag
    directory (a folder of something else, a FIFO or a device is never replaced): the rule of every
    command that writes a file (``-o``, ``--plot``, ``--mcap``). Call after ``check_output``."""
    if not output.exists() and not output.is_symlink():
        return
    kind = _special(output)
    if kind:
        raise UsageError(f"{option} {output} is {kind}, not a regular file", _SPECIAL_HINT)
    if not force:
        raise UsageError(f"{option} {output} already exists", "name another output, or --force to replace it")
    if output.is_dir() and not output.is_symlink() and not only_bag_files(output):
        raise UsageError(
            f"{option} {output} is a folder that is not a bag; --force replaces only a file or a bag",
            f"name a file, e.g. {option} " + str(output / "with_static"),
        )


_SPECIAL_HINT = "name a file: tfx writes regular files, and --force replaces only a regular file"
_KINDS = ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))  # fmt: skip


def _special(output: Path) -> str:
    """What ``output`` (or what a link there points to) is when it exists and is neither a regular file
    nor a folder: a FIFO, a device or a socket, which writing would destroy or hang on; else ""."""
    try:
        mode = output.stat().st_mode
    except OSError:  # absent, or a dangling link: nothing there to destroy
        return ""
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return ""
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False
