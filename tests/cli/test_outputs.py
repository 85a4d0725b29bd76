"""Output paths: never the input, inside it or above it; a file already there replaced only with --force, and
only a regular file, by every command that writes one; a missing folder, a read-only folder or a full disk is
one line and leaves no half-written file."""

from __future__ import annotations

import errno
import os
import shutil
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS, Result, Tfx

STATIC = ("static", "0", "0", "1", "0", "0", "0", "base_link", "extra")


@pytest.fixture
def bags(tmp_path: Path) -> dict[str, Path]:
    """Copies of the sample bags in ``tmp_path/in``."""
    folder = tmp_path / "in"
    folder.mkdir()
    copies = {}
    for key, path in SAMPLE_BAGS.items():
        copy = folder / path.name
        (shutil.copytree if path.is_dir() else shutil.copy)(path, copy)
        copies[key] = copy
    return copies


def snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() if p.is_file() else b"/" for p in sorted(folder.rglob("*"))}


def refused(result: Result, *words: str) -> None:
    assert result.code == 2, result.stderr
    assert result.stderr.startswith("tfx: error: ") and result.stderr.count("\n") == 1, result.stderr
    for word in words:
        assert word in result.stderr


def test_view_frames_never_writes_over_or_into_its_input(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    before = snapshot(tmp_path / "in")
    db3 = bags["db3"]
    cases = [
        (bags["ros1"], bags["ros1"], "is the input"),
        (db3, db3, "is the input"),
        (db3, db3 / "metadata.yaml", "inside the input"),
        (db3, db3 / "new.pdf", "inside the input"),
        (db3 / "robot_db3.db3", db3 / "metadata.yaml", "inside the input"),
        (db3 / "robot_db3.db3", db3 / "robot_db3.db3", "is the input"),
        (bags["ros1"], tmp_path / "in", "holds the input"),
        (bags["mcap"], tmp_path, "holds the input"),
    ]
    for bag, output, words in cases:
        refused(tfx("view-frames", "-b", bag, "-o", output), words)
    link = tmp_path / "link.pdf"
    link.symlink_to(bags["ros1"])
    refused(tfx("view-frames", "-b", bags["ros1"], "-o", link), "is the input")
    hard = tmp_path / "hard.pdf"
    os.link(bags["ros1"], hard)
    refused(tfx("view-frames", "-b", bags["ros1"], "-o", hard), "is the input")
    assert snapshot(tmp_path / "in") == before


def test_view_frames_default_output_inside_a_bag_is_refused(
    tfx: Tfx, bags: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(bags["db3"])
    refused(tfx("view-frames", "-b", "."), "the default output", "inside the input")


def test_static_never_deletes_or_replaces_its_input(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    before = snapshot(tmp_path / "in")
    db3 = bags["db3"]
    cases = [
        (bags["ros1"], bags["ros1"], "is the input"),
        (db3, db3, "is the input"),
        (db3, tmp_path / "in", "holds the input"),
        (db3, tmp_path, "holds the input"),
        (db3, db3 / "metadata.yaml", "inside the input"),
        (db3, db3 / "robot_db3.db3", "inside the input"),
        (db3, db3 / "copy", "inside the input"),
        (db3 / "robot_db3.db3", db3, "holds the input"),
        (db3 / "metadata.yaml", db3 / "robot_db3.db3", "inside the input"),
        (bags["ros1"], Path("/"), "holds the input"),
    ]
    for bag, output, words in cases:
        for force in ((), ("--force",)):
            refused(tfx(*STATIC, "-b", bag, "-o", output, *force), words)
    assert snapshot(tmp_path / "in") == before


def test_force_replaces_an_earlier_output_only(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    out = tmp_path / "out.bag"
    assert tfx(*STATIC, "-b", bags["ros1"], "-o", out).code == 0
    refused(tfx(*STATIC, "-b", bags["ros1"], "-o", out), "already exists", "--force")
    assert tfx(*STATIC, "-b", bags["ros1"], "-o", out, "--force").code == 0
    out2 = tmp_path / "out_db3"
    assert tfx(*STATIC, "-b", bags["db3"], "-o", out2).code == 0
    assert tfx(*STATIC, "-b", bags["mcap"], "-o", out2, "--force").code == 0  # an earlier bag directory
    documents = tmp_path / "documents"
    documents.mkdir()
    (documents / "thesis.tex").write_text("precious")
    refused(tfx(*STATIC, "-b", bags["db3"], "-o", documents, "--force"), "not a bag")
    assert (documents / "thesis.tex").read_text() == "precious"


#: Every command that writes a file, and its option naming it (OUT: where the file goes).
WRITERS = {
    "view-frames": ("view-frames", "-o", "OUT.gv"),
    "report": ("report", "-o", "OUT.html"),
    "report --mcap": ("report", "-o", "page.html", "--mcap", "OUT.mcap"),
    "wtf --mcap": ("wtf", "--mcap", "OUT.mcap"),
    "echo --plot": ("echo", "base_link", "odom", "--plot", "OUT.png"),
    "monitor --plot": ("monitor", "--plot", "OUT.png"),
    "static": (*STATIC, "-o", "OUT.bag"),
}


def _writing(command: str, bag: Path, folder: Path) -> tuple[list[str], Path]:
    """``command``'s arguments writing into ``folder``, and the file it writes."""
    arguments = [str(folder / a) if a.startswith(("OUT.", "page.")) else a for a in WRITERS[command]]
    (output,) = [Path(a) for a in arguments if a.startswith(str(folder / "OUT."))]
    return [*arguments, "-b", str(bag)], output


@pytest.mark.parametrize("command", WRITERS)
def test_every_writer_replaces_a_file_only_with_force(
    tfx: Tfx, bags: dict[str, Path], tmp_path: Path, command: str
) -> None:
    arguments, output = _writing(command, bags["ros1"], tmp_path)
    output.write_text("someone's notes")
    (tmp_path / "page.html").unlink(missing_ok=True)
    refused(tfx(*arguments), f"{output} already exists", "--force to replace it")
    assert output.read_text() == "someone's notes"
    assert tfx(*arguments, "--force").code in (0, 1)
    assert output.read_bytes() != b"someone's notes"


@pytest.mark.parametrize("command", WRITERS)
def test_no_writer_replaces_a_fifo_even_with_force(
    tfx: Tfx, bags: dict[str, Path], tmp_path: Path, command: str
) -> None:
    arguments, output = _writing(command, bags["ros1"], tmp_path)
    os.mkfifo(output)
    refused(tfx(*arguments, "--force"), f"{output} is a FIFO, not a regular file")
    assert output.is_fifo()


def test_view_frames_redraws_its_default_output_but_a_named_one_only_with_force(
    tfx: Tfx, bags: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """As ROS's view_frames: running it again redraws frames.pdf (here frames.gv); a file named with -o is
    replaced only with --force, and the default is never a FIFO."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "frames.gv").write_text("an earlier drawing")
    assert tfx("view-frames", "-b", bags["ros1"], "-f", "dot").code == 0
    assert "digraph frames" in (tmp_path / "frames.gv").read_text()
    assert tfx("view-frames", "-b", bags["ros1"], "-o", "tree.gv").code == 0
    refused(tfx("view-frames", "-b", bags["ros1"], "-o", "tree.gv"), "-o tree.gv already exists")
    assert tfx("view-frames", "-b", bags["ros1"], "-o", "tree.gv", "--force").code == 0
    (tmp_path / "frames.gv").unlink()
    os.mkfifo(tmp_path / "frames.gv")
    refused(tfx("view-frames", "-b", bags["ros1"], "-f", "dot"), "frames.gv is a FIFO, not a regular file")


@pytest.mark.parametrize("command", ["view-frames", "static"])
def test_a_missing_folder_is_one_line(tfx: Tfx, bags: dict[str, Path], tmp_path: Path, command: str) -> None:
    output = tmp_path / "missing" / "out.bag"
    args = ("view-frames",) if command == "view-frames" else STATIC
    refused(tfx(*args, "-b", bags["ros1"], "-o", output), "does not exist", "mkdir -p")
    assert not output.parent.exists()


@pytest.mark.parametrize(
    ("code", "words"),
    [(errno.ENOSPC, "the disk is full"), (errno.EACCES, "no permission"), (errno.EROFS, "read-only")],
)
def test_a_full_or_read_only_disk_leaves_nothing_half_written(
    tfx: Tfx, bags: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch, code: int, words: str
) -> None:
    output = tmp_path / "out" / "frames.gv"
    output.parent.mkdir()
    real_fdopen = os.fdopen

    class Failing:
        def __init__(self, handle: int, mode: str) -> None:
            self.file = real_fdopen(handle, mode)

        def __enter__(self) -> Failing:
            return self

        def __exit__(self, *exc: object) -> None:
            self.file.close()

        def fileno(self) -> int:
            return self.file.fileno()

        def write(self, data: bytes) -> int:
            self.file.write(data[: len(data) // 2])  # half of it reached the disk, then it was full
            raise OSError(code, os.strerror(code))

        def flush(self) -> None:
            self.file.flush()

    monkeypatch.setattr(os, "fdopen", Failing)
    result = tfx("view-frames", "-b", bags["ros1"], "-o", output)
    refused(result, f"cannot write {output}", words)
    assert list(output.parent.iterdir()) == []  # neither the output nor its temporary file


def test_an_earlier_output_survives_a_failed_write(
    tfx: Tfx, bags: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    output = tmp_path / "frames.gv"
    assert tfx("view-frames", "-b", bags["ros1"], "-o", output).code == 0
    earlier = output.read_bytes()

    def full(*args: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", full)
    refused(tfx("view-frames", "-b", bags["mcap"], "-o", output, "--force"), "the disk is full")
    assert output.read_bytes() == earlier
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frames.gv", "in"]


def test_written_files_get_the_usual_permissions(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    output = tmp_path / "frames.gv"
    assert tfx("view-frames", "-b", bags["ros1"], "-o", output).code == 0
    mask = os.umask(0)
    os.umask(mask)
    assert output.stat().st_mode & 0o777 == 0o666 & ~mask


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_folder_is_one_line(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    folder = tmp_path / "locked"
    folder.mkdir(mode=0o500)
    refused(tfx("view-frames", "-b", bags["ros1"], "-o", folder / "frames.gv"), "no permission")


@pytest.fixture
def tiny_disk(tmp_path: Path) -> Iterator[Path]:
    """A 16 KiB tmpfs (needs root and a mount namespace that allows it; skipped otherwise)."""
    import subprocess

    folder = tmp_path / "tiny"
    folder.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", str(folder)], capture_output=True, check=False
    )
    if os.geteuid() != 0 or mounted.returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    yield folder
    subprocess.run(["umount", str(folder)], check=False)


@pytest.mark.parametrize("command", ["view-frames", "static"])
def test_a_really_full_disk(tfx: Tfx, bags: dict[str, Path], tiny_disk: Path, command: str) -> None:
    args = ("view-frames",) if command == "view-frames" else STATIC
    output = tiny_disk / ("frames.pdf" if command == "view-frames" else "out.bag")
    result = tfx(*args, "-b", bags["ros1"], "-o", output)
    assert result.code == 2 and result.stderr.count("\n") == 1 and "No space left" in result.stderr
    assert list(tiny_disk.iterdir()) == []
