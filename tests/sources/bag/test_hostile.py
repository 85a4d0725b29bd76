"""Hostile bag files (issue 14): bombs, looping links, lying metadata. Each is read within bounds,
or refused with tftools' own one-line error; never a traceback, a hang or a blow-up."""

from __future__ import annotations

import os
import shutil
import sqlite3
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import BinaryIO

import numpy as np
import pytest
import zstandard

from tests.bags import BagFormat, TfMessage, write_bag
from tests.sources.bag import hostile
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import T0
from tftools.core.errors import TfToolsError
from tftools.core.transform import Transform
from tftools.sources.bag import messages, rosbag2, unpack
from tftools.sources.bag.rosbag2.db3_salvage import salvage
from tftools.sources.bag.unpack import Budget
from tftools.sources.codecs.select import Wanted
from tftools.sources.errors import CorruptBagError, UnknownBagFormatError
from tftools.sources.storage.source import FileSource

MiB = 1 << 20
MEMORY_LIMIT = 1536 * MiB  # address space of a subprocess that reads a bomb
CODECS = ["bz2", "lz4", "zstd"]


def problems(path: Path) -> str:
    """The problem lines of the bag at ``path``, or its one-line error."""
    try:
        return " ".join(p for f in read_contents([path]).files for p in f.problems)
    except TfToolsError as e:
        assert "\n" not in str(e)
        return str(e)


# The codecs: at most the declared size, MAX_UNPACKED, the budget; the loss said.


@pytest.mark.parametrize("codec", CODECS)
def test_decompression_stops_at_the_declared_size(codec: str) -> None:
    bomb = hostile.compressed_zeros(codec, 8 * MiB)
    got = unpack.unpack(codec, bomb, 1000)
    assert len(got.data) == 1000
    assert got.loss == f"{codec} data decompresses past its declared size of 1000 bytes; read up to there"
    whole = unpack.unpack(codec, bomb, 8 * MiB)
    assert len(whole.data) == 8 * MiB and not whole.loss
    short = unpack.unpack(codec, bomb, 9 * MiB)
    assert len(short.data) == 8 * MiB and short.loss == f"{codec} data cut short: {8 * MiB} of {9 * MiB} bytes"


@pytest.mark.parametrize("codec", CODECS)
def test_decompression_stops_at_the_absolute_limit_and_the_budget(codec: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(unpack, "MAX_UNPACKED", 2 * MiB)
    bomb = hostile.compressed_zeros(codec, 8 * MiB)
    got = unpack.unpack(codec, bomb, 8 * MiB)
    assert len(got.data) == 2 * MiB and "tftools' limit of 2 MiB a piece" in got.loss
    monkeypatch.setattr(unpack, "MAX_UNPACKED", 256 * MiB)
    monkeypatch.setattr(unpack, "MIN_BUDGET", 3 * MiB)
    budget = unpack.Budget(0)  # 3 MiB for the file's pieces in all
    first, second = (unpack.unpack(codec, bomb, 8 * MiB, budget) for _ in range(2))
    assert (len(first.data), len(second.data)) == (3 * MiB, 0)
    assert "the file's budget of 3 MiB" in first.loss


@pytest.mark.parametrize("codec", CODECS)
def test_damaged_stream_gives_its_start(codec: str) -> None:
    bomb = hostile.compressed_zeros(codec, 4 * MiB)
    got = unpack.unpack(codec, bomb[: len(bomb) // 2] + b"\xff" * 64, 4 * MiB)
    assert got.loss and len(got.data) < 4 * MiB


# Each format's bomb, read.


@pytest.mark.parametrize("codec", ["bz2", "lz4"])
def test_ros1_chunk_bomb_is_cut_at_its_declared_size(tmp_path: Path, codec: str) -> None:
    bag = tmp_path / "bomb.bag"
    bag.write_bytes(hostile.ros1_bag([(codec, hostile.compressed_zeros(codec, 16 * MiB), 1000)] * 3))
    assert "decompresses past its declared size of 1000 bytes" in problems(bag)


@pytest.mark.parametrize("summary", [True, False])
def test_mcap_chunk_bomb_is_cut_and_lost(tmp_path: Path, summary: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(unpack, "MAX_UNPACKED", 4 * MiB)
    path = tmp_path / "bomb.mcap"
    path.write_bytes(hostile.mcap_bomb("zstd", hostile.compressed_zeros("zstd", 16 * MiB), 1 << 40, summary=summary))
    found = problems(path)
    assert ("tftools' limit of 4 MiB a piece" if summary else "1 chunks are damaged") in found


def test_message_compressed_db3_bomb_loses_that_message(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(unpack, "MAX_UNPACKED", 4 * MiB)
    bag = hostile.db3(tmp_path / "bomb.db3", [hostile.compressed_zeros("zstd", 16 * MiB)])
    from tftools.sources.bag.messages import MessageSet
    from tftools.sources.bag.rosbag2 import db3

    with FileSource(bag) as source:
        scan = db3.Db3File(bag, source).scan(Wanted(("/tf",)), lambda _a, _b: None, MessageSet())
    _, _, _, lost = scan.messages.decode()
    assert lost and "could not be decompressed" in lost[0] and "4 MiB a piece" in lost[0]


def test_file_compressed_rosbag2_bomb_writes_no_more_than_its_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(unpack, "MIN_BUDGET", 2 * MiB)
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "bag_0.db3.zstd").write_bytes(hostile.compressed_zeros("zstd", 32 * MiB))
    (bag / "metadata.yaml").write_text(
        "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
        "  relative_file_paths: [bag_0.db3.zstd]\n  compression_mode: FILE\n"
    )
    written: list[int] = []
    real = unpack.zstd_file

    def measured(source: BinaryIO, target: Path, budget: Budget) -> str:
        loss = real(source, target, budget)
        written.append(target.stat().st_size)
        return loss

    monkeypatch.setattr(rosbag2, "zstd_file", measured)
    with pytest.raises(CorruptBagError, match="not an SQLite database"):
        read_contents([bag])
    assert written and written[0] <= max(2 * MiB, unpack.MAX_RATIO * (bag / "bag_0.db3.zstd").stat().st_size)


def test_file_compressed_rosbag2_stops_short_of_a_full_disk(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "plain"
    source = tmp_path / "bomb.zstd"
    source.write_bytes(hostile.compressed_zeros("zstd", 8 * MiB))
    free = shutil.disk_usage(tmp_path).free
    monkeypatch.setattr(unpack, "FREE_SPACE_MARGIN", free - MiB)  # as if only 1 MiB were free
    with source.open("rb") as f:
        loss = unpack.zstd_file(f, target, unpack.Budget(1 << 30))
    assert target.stat().st_size <= MiB and "free in" in loss


def _run_limited(code: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    """``code`` run in a fresh Python limited to ``MEMORY_LIMIT`` of address space."""
    prelude = f"import resource; resource.setrlimit(resource.RLIMIT_AS, ({MEMORY_LIMIT}, {MEMORY_LIMIT}))\n"
    return subprocess.run(
        [sys.executable, "-c", prelude + textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=Path(__file__).parents[3],
    )


@pytest.mark.slow
@pytest.mark.parametrize("summary", [True, False])
def test_mcap_gigabyte_bomb_reads_within_memory_and_time(tmp_path: Path, summary: bool) -> None:
    """A 1 GiB zstd chunk that says so: cut at the budget, well within 1.5 GB and a few seconds."""
    path = tmp_path / "bomb.mcap"
    path.write_bytes(hostile.mcap_bomb("zstd", hostile.compressed_zeros("zstd", 1 << 30), 1 << 30, summary=summary))
    done = _run_limited(
        f"""
        from tests.sources.bag.reading import read_contents
        print(read_contents([{str(path)!r}]).files[0].problems)
        """,
        timeout=20,
    )
    assert done.returncode == 0, done.stderr
    assert ("the file's budget of 64 MiB" if summary else "1 chunks are damaged") in done.stdout


# Links and lengths checked against the file.


def test_db3_overflow_chain_looping_on_itself(tmp_path: Path) -> None:
    """64 KiB pages, a message declaring 3.9 GB whose overflow page links to itself: refused at once."""
    bag = hostile.db3_looping_overflow(tmp_path / "loop.db3", 3_900_000_000)
    done = _run_limited(
        f"""
        from tftools.core.errors import TfToolsError
        from tests.sources.bag.reading import read_contents
        try:
            read_contents([{str(bag)!r}])
        except TfToolsError as e:
            print("refused:", e)
        """,
        timeout=20,
    )
    assert done.returncode == 0, done.stderr
    assert "refused:" in done.stdout and "corrupt" in done.stdout


def test_db3_salvage_reads_no_more_overflow_pages_than_the_file_holds() -> None:
    """200 records claiming one 20-page overflow chain in a 44-page file: read until 44 overflow
    pages have been read, not 4,000; the others lost."""
    (one,) = salvage(hostile.db3_shared_overflow(1, 20), {1}).rows
    image = hostile.db3_shared_overflow(200, 20)
    found = salvage(image, {1})
    pages = len(image) // 512
    assert len(found.rows) == pages // 20 and found.lost == 200 - pages // 20
    assert all(payload == one[2] for _, _, payload in found.rows)


@pytest.mark.parametrize("declared", [150_000, 3_900_000_000])
def test_db3_salvage_of_an_overflow_chain_looping_on_itself(tmp_path: Path, declared: int) -> None:
    """A chain that loops within the file's size is lost; a payload larger than the file is no record."""
    data = hostile.db3_looping_overflow(tmp_path / "loop.db3", declared).read_bytes()
    assert declared > len(data) or declared < len(data) // 2
    found = salvage(data, {1})
    assert (found.rows, found.lost) == ([], 0 if declared > len(data) else 1)


def test_db3_rows_of_the_wrong_types(tmp_path: Path) -> None:
    """sqlite keeps any value in any column: NULL, bytes or numbers for text, text for integers."""
    from tests.sources.ros2_helpers import Tf, tf_cdr

    bag = hostile.db3(tmp_path / "odd.db3", [tf_cdr([Tf("map", "odom", 7)])])
    db = sqlite3.connect(bag)
    db.execute("INSERT INTO topics VALUES (2, NULL, X'ff2f7466', 3, '')")
    db.execute("INSERT INTO messages VALUES (5, 'x', 9, X'00')")
    db.execute("INSERT INTO messages VALUES (2, 1, 'soon', X'00')")
    db.execute("INSERT INTO messages VALUES (3, 1, 9, 'text, not a blob')")
    db.execute("INSERT INTO messages VALUES (4, 1, NULL, NULL)")
    db.commit()
    db.close()
    contents = read_contents([bag])
    assert sum(f.transform_count for f in contents.files) == 1


def test_prefetch_of_ranges_a_damaged_index_gives(tmp_path: Path) -> None:
    path = tmp_path / "f"
    path.write_bytes(b"x" * 100)
    with FileSource(path) as source:
        source.ahead(np.array([-5, 50, 1 << 62, 10], np.int64), np.array([10, 20, (1 << 63) - 1, 10], np.int64))
        source.ahead(np.array([1 << 63], np.uint64), np.array([(1 << 64) - 1], np.uint64))


# metadata.yaml


def _bag_with_metadata(tmp_path: Path, text: str) -> Path:
    from tests.sources.ros2_helpers import Msg, Tf, write_rosbag2

    bag = write_rosbag2(tmp_path / "bag", [Msg("/tf", 5, (Tf("map", "odom", 5),))])
    (bag / "metadata.yaml").write_text(text)
    return bag


def _problems(bag: Path) -> list[str]:
    return [p for f in read_contents([bag]).files for p in f.problems]


def test_metadata_billion_laughs(tmp_path: Path) -> None:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]" for i in range(1, 10)]
    bag = _bag_with_metadata(tmp_path, "\n".join(lines) + "\nrosbag2_bagfile_information: *a9\n")
    done = _run_limited(
        f"""
        from tests.sources.bag.reading import read_contents
        print([p for f in read_contents([{str(bag)!r}]).files for p in f.problems])
        """,
        timeout=20,
    )
    assert "aliases expand to more than" in done.stdout, done.stderr


def test_metadata_deep_nesting(tmp_path: Path) -> None:
    bag = _bag_with_metadata(tmp_path, "[" * 100_000 + "]" * 100_000)
    assert any("nested deeper than" in p for p in _problems(bag))


def test_metadata_too_large(tmp_path: Path) -> None:
    bag = _bag_with_metadata(tmp_path, "# " + "x" * (5 * MiB))
    assert any("larger than" in p for p in _problems(bag))


@pytest.mark.parametrize(
    "name", ["../outside.db3", "/etc/passwd", "a/../../b.db3", "x" * 5000 + ".db3", "\x1b[31mred\n.db3"]
)
def test_metadata_file_names(tmp_path: Path, name: str) -> None:
    bag = _bag_with_metadata(tmp_path, "")
    found = sorted(p.name for p in bag.glob("*.db3"))
    listed = ", ".join(f'"{n}"' for n in [name.replace("\x1b", "\\e").replace("\n", "\\n"), *found])
    (bag / "metadata.yaml").write_text(f"rosbag2_bagfile_information:\n  relative_file_paths: [{listed}]\n")
    contents = read_contents([bag])
    assert sum(f.transform_count for f in contents.files) == 1
    problems = " ".join(p for f in contents.files for p in f.problems)
    assert "\x1b" not in problems and "\n" not in problems
    assert ("outside the bag directory" in problems) == (".." in name or name.startswith("/"))


# wtf: a reader's bug is an internal error, not "could not be read".


def test_wtf_names_a_reader_crash_an_internal_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from tftools.analysis import reading
    from tftools.analysis.wtf.fleet import check_fleet

    def crash(*_args: object, **_kwargs: object) -> None:
        raise ValueError("boom")

    monkeypatch.setattr(reading, "read_recording", crash)
    (report,) = check_fleet([[str(tmp_path / "x.bag")]])
    assert report.error is not None
    assert "internal error of tftools" in report.error.message and "ValueError: boom" in report.error.message


# Special files and empty messages


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_empty_tf_messages_are_read_as_none(tmp_path: Path, fmt: BagFormat, monkeypatch: pytest.MonkeyPatch) -> None:
    """5,000 /tf messages holding an empty TFMessage, then one transform, decoded a few at a time (as
    hundreds of thousands are): no error, one transform."""
    monkeypatch.setattr(messages, "_GROUP_BYTES", 256)
    one = Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), T0 + 5000, "map", "odom")
    written = [TfMessage("/tf", T0 + i, ()) for i in range(5000)] + [TfMessage("/tf", T0 + 5000, (one,))]
    contents = read_contents([write_bag(tmp_path / "empty", written, fmt)])
    assert len(contents.transforms) == 1 and contents.problems == []


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_is_refused_not_waited_on(tmp_path: Path) -> None:
    """A FIFO (``tfx frames -b <(zcat x.bag.gz)``) would block forever when opened: refused unopened."""
    fifo = tmp_path / "f.bag"
    os.mkfifo(fifo)
    with pytest.raises(UnknownBagFormatError, match="not a regular file"):
        read_contents([fifo])
    bag = tmp_path / "bag"
    bag.mkdir()
    os.mkfifo(bag / "bag.db3")  # a ROS 2 bag's file that is a FIFO
    with pytest.raises(CorruptBagError, match="not a regular file"):
        read_contents([bag])


def test_one_zstd_bomb_does_not_use_up_a_message_compressed_bag(tmp_path: Path) -> None:
    """One message of a bag compressed message by message is a bomb that does not state its size: it
    alone is lost, the 799 /tf messages after it are read (issue 32 U4)."""
    from tests.sources.ros2_helpers import Msg, Tf, write_rosbag2

    written = [Msg("/tf", T0 + i, (Tf("map", "odom", i),)) for i in range(800)]
    bag = write_rosbag2(tmp_path / "bag", written, compression="message")
    db = sqlite3.connect(bag / "bag.db3")
    (first,) = db.execute("SELECT min(id) FROM messages").fetchone()
    db.execute("UPDATE messages SET data = ? WHERE id = ?", (hostile.compressed_zeros("zstd", 1 << 30), first))
    db.commit()
    db.close()
    contents = read_contents([bag])
    assert len(contents.transforms) == 799
    (line,) = contents.problems
    assert line.startswith("/tf: 1 of 800 messages could not be decompressed") and "share of the file's budget" in line


@pytest.mark.parametrize("mode", ["message", "file"])
def test_a_compressed_bag_is_copied_within_the_budget(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, mode: str
) -> None:
    """``tfx static -b IN -o OUT`` (and ``--repair``) read the bag through tftools' reader, whose zstd
    decompression is budgeted (issue 32 M2), and copy it compressed as it was. A healthy compressed bag is
    copied with the statics added; one with a bomb is refused in one line, and no copy is left."""
    from tests.sources.ros2_helpers import Msg, Tf, write_rosbag2
    from tftools.sinks.static_bag import add_static_transforms
    from tftools.sources.errors import BagError

    static = Transform((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0), 0, "base", "laser")
    written = [Msg("/tf", T0 + i, (Tf("map", "odom", i),)) for i in range(50)]
    healthy = write_rosbag2(tmp_path / "healthy", written, compression=mode)
    copy = add_static_transforms(healthy, tmp_path / "copy", [static])
    assert len(read_contents([copy]).transforms) == 51
    assert (any(copy.glob("*.zstd")), "compression_mode: message" in (copy / "metadata.yaml").read_text()) == (
        mode == "file",
        mode == "message",
    )
    monkeypatch.setattr(unpack, "MAX_UNPACKED", 4 << 20)
    monkeypatch.setattr(unpack, "MIN_BUDGET", 8 << 20)
    bomb = write_rosbag2(tmp_path / "bomb", [*written, Msg("/big", T0 + 60, ())], compression=mode)
    if mode == "message":
        db = sqlite3.connect(bomb / "bomb.db3")
        db.execute("UPDATE messages SET data = ? WHERE id = (SELECT max(id) FROM messages)",
                   (hostile.compressed_zeros("zstd", 64 << 20),))  # fmt: skip
        db.commit()
        db.close()
    else:
        (compressed,) = bomb.glob("*.zstd")  # the database, then 64 MiB of zeros sqlite would not mind
        plain = zstandard.ZstdDecompressor().stream_reader(compressed.read_bytes()).read()
        z = zstandard.ZstdCompressor().compressobj()
        compressed.write_bytes(z.compress(plain) + b"".join(z.compress(bytes(1 << 20)) for _ in range(64)) + z.flush())
    with pytest.raises(BagError, match=r"cannot be copied whole: .*(past|budget)"):
        add_static_transforms(bomb, tmp_path / "bomb_copy", [static])
    assert not (tmp_path / "bomb_copy").exists()
