"""Property-based fuzzing of the bag readers (issue 14): mutated bags of every format, payloads
for every tf decoder, and metadata.yaml. Every outcome is transforms read or tftools' own one-line
error, in bounded time; never another exception.

A few examples per case by default (CI); ``TFTOOLS_FUZZ_EXAMPLES=2000`` runs them at length.
"""

from __future__ import annotations

import os
import struct
from datetime import timedelta
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.bags import BagFormat, TfMessage, write_bag
from tests.sources.bag import hostile
from tests.sources.bag.reading import read_contents
from tftools.core.errors import TfToolsError
from tftools.core.transform import Transform
from tftools.sources.bag.contents import RecordWindow
from tftools.sources.bag.messages import MessageSet
from tftools.sources.codecs.select import CODECS

EXAMPLES = int(os.environ.get("TFTOOLS_FUZZ_EXAMPLES", "25"))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=timedelta(seconds=10),  # a hang shows as a deadline exceeded
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
    derandomize=EXAMPLES <= 25,  # CI: the same examples every run
)
EXTREMES = [0, 1, 0x7F, 0x80, 0xFF, 0xFFFF, 0x7FFFFFFF, 0xFFFFFFFF, 1 << 32, 1 << 62, (1 << 63) - 1, (1 << 64) - 1]


def _transforms(n: int, t: int) -> list[Transform]:
    return [
        Transform((float(i), 0.5, -1.0), (0.0, 0.0, 0.0, 1.0), t, "map" if i == 0 else f"f{i - 1}", f"f{i}")
        for i in range(n)
    ]


def _messages() -> list[TfMessage]:
    return [TfMessage("/tf", 10**9 + k * 10**7, _transforms(3, 10**9 + k * 10**7), "/pub") for k in range(20)] + [
        TfMessage("/tf_static", 10**9, _transforms(2, 0), "/static")
    ]


@cache
def seed(kind: str) -> tuple[str, bytes]:
    """A small valid file of each kind the readers take, and its file name suffix."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        if kind == "ros1":
            return ".bag", write_bag(root / "a.bag", _messages(), BagFormat.ros1).read_bytes()
        if kind in ("ros1-bz2", "ros1-lz4"):
            from tests.sources.ros1_helpers import Msg, write_rosbags

            msgs = [
                Msg("/tf", "tf2", 10**9 + i * 10**7, "/p", [("map", "odom", 10**9 + i, [0.0] * 6 + [1.0])])
                for i in range(30)
            ]
            path = write_rosbags(root / "c.bag", msgs, kind.split("-")[1], chunk_threshold=600)
            return ".bag", path.read_bytes()
        if kind == "db3":
            bag = write_bag(root / "b", _messages(), BagFormat.rosbag2_sqlite3)
            return ".db3", next(bag.glob("*.db3")).read_bytes()
        if kind == "mcap":
            bag = write_bag(root / "m", _messages(), BagFormat.rosbag2_mcap)
            return ".mcap", next(bag.glob("*.mcap")).read_bytes()
        if kind == "mcap-zstd-bomb":
            return ".mcap", hostile.mcap_bomb("zstd", hostile.compressed_zeros("zstd", 1 << 20), 1 << 20)
        if kind == "ros1-bz2-bomb":
            return ".bag", hostile.ros1_bag([("bz2", hostile.compressed_zeros("bz2", 1 << 20), 1000)])
        if kind == "db3-loop":
            return ".db3", hostile.db3_looping_overflow(root / "l.db3", 3_900_000_000).read_bytes()
    raise AssertionError(kind)


KINDS = ["ros1", "ros1-bz2", "ros1-lz4", "db3", "mcap", "mcap-zstd-bomb", "ros1-bz2-bomb", "db3-loop"]


@st.composite
def mutations(draw: st.DrawFn, size: int) -> list[tuple[str, int, int]]:
    """Byte flips, extreme integers written over a length or offset, cuts and insertions."""
    ops = []
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from(["flip", "u32", "u64", "cut", "insert", "zero"]))
        at = draw(st.integers(0, max(0, size - 1)))
        value = draw(st.sampled_from(EXTREMES) | st.integers(0, 255))
        ops.append((kind, at, value))
    return ops


def mutated(data: bytes, ops: list[tuple[str, int, int]]) -> bytes:
    out = bytearray(data)
    for kind, at, value in ops:
        at = min(at, max(0, len(out) - 1))
        if kind == "flip" and out:
            out[at] ^= 1 << (value % 8)
        elif kind == "u32":
            out[at : at + 4] = struct.pack("<I", value & 0xFFFFFFFF)
        elif kind == "u64":
            out[at : at + 8] = struct.pack("<Q", value)
        elif kind == "cut":
            del out[at:]
        elif kind == "insert":
            out[at:at] = bytes([value & 0xFF]) * (1 + value % 64)
        elif kind == "zero":
            out[at : at + 1 + value % 4096] = bytes(len(out[at : at + 1 + value % 4096]))
    return bytes(out)


#: Whole files, and a window of record time amid the seeds' messages (and an empty one).
WINDOWS = [None, RecordWindow(10**9 + 5 * 10**7, 10**9 + 12 * 10**7), RecordWindow(10**9, 10**9)]


def read_anything(path: Path, window: RecordWindow | None = None) -> None:
    """Read ``path``: transforms, or tftools' own error in one line; anything else fails the test."""
    try:
        contents = read_contents([path], window=window)
    except TfToolsError as e:
        assert "\n" not in str(e), str(e)
        return
    for f in contents.files:
        assert all("\n" not in p for p in f.problems)
    contents.transforms  # noqa: B018 - every part put together


@pytest.mark.parametrize("window", WINDOWS, ids=str)
@pytest.mark.parametrize("kind", KINDS)
def test_mutated_bags(kind: str, window: RecordWindow | None, tmp_path_factory: pytest.TempPathFactory) -> None:
    suffix, data = seed(kind)
    where = tmp_path_factory.mktemp("fuzz")

    @FUZZ
    @given(mutations(len(data)))
    def check(ops: list[tuple[str, int, int]]) -> None:
        path = where / f"bag{suffix}"
        path.write_bytes(mutated(data, ops))
        read_anything(path, window)

    check()


@pytest.mark.parametrize("window", WINDOWS, ids=str)
@pytest.mark.parametrize("kind", ["ros1", "db3", "mcap"])
def test_bags_cut_at_every_boundary(kind: str, window: RecordWindow | None, tmp_path: Path) -> None:
    """The seed cut short at every 97th byte (a cut through each kind of record)."""
    suffix, data = seed(kind)
    path = tmp_path / f"bag{suffix}"
    for end in range(0, len(data), 97 if EXAMPLES <= 25 else 1):
        path.write_bytes(data[:end])
        read_anything(path, window)


@pytest.mark.parametrize("key", list(CODECS), ids=lambda key: f"{key[0]}-{key[1]}")
def test_tf_decoders_on_any_payload(key: tuple[str, str]) -> None:
    codec = CODECS[key]

    @FUZZ
    @given(st.lists(st.binary(max_size=600), min_size=1, max_size=8))
    def check(payloads: list[bytes]) -> None:
        messages = MessageSet()
        channel = messages.channel("/tf", codec)
        messages.add(channel, np.arange(len(payloads)), np.arange(len(payloads)), payloads)
        _, _, _, problems = messages.decode()
        assert all("\n" not in p for p in problems)

    check()


YAML_PIECES = [
    "rosbag2_bagfile_information:",
    "  relative_file_paths: [a.db3]",
    "  storage_identifier: sqlite3",
    "  compression_mode: FILE",
    "&a [*a]",
    "*b",
    "[[[[",
    "{",
    "!!python/object:os.system",
    "- \x00",
    "  files: *x",
    "x: &x [1, 2]",
    "  relative_file_paths: ['../x', '/etc/passwd']",
]


def test_metadata_yaml(tmp_path: Path) -> None:
    from tftools.sources.bag import rosbag2
    from tftools.sources.storage.source import LocalFiles

    @FUZZ
    @given(st.lists(st.sampled_from(YAML_PIECES) | st.text(max_size=40), max_size=12))
    def check(lines: list[str]) -> None:
        (tmp_path / "metadata.yaml").write_text("\n".join(lines), "utf-8", "surrogatepass")
        problems: list[str] = []
        rosbag2._metadata(tmp_path / "metadata.yaml", LocalFiles(tmp_path), problems)
        assert all("\n" not in p for p in problems)

    check()


# Mutants the fuzzing found, kept as regressions: (seed, mutations, what it raised before its fix).
FOUND = [
    ("mcap", [("u64", 2210, 127), ("insert", 5195, 116), ("insert", 5173, 2147483647), ("insert", 8935, 65535)]),
    ("mcap-zstd-bomb", [("flip", 410, 0)]),  # MemoryError: a chunk index's length read as is
    ("mcap-zstd-bomb", [("u32", 382, (1 << 63) - 1)]),
    ("mcap-zstd-bomb", [("flip", 380, 127)]),  # ValueError: a chunk offset past what seek takes
    # OverflowError: a chunk info's position past the file, prefetched
    ("ros1-bz2", [("u32", 6819, 1 << 32), ("flip", 8291, 0x7FFFFFFF), ("u64", 3782, (1 << 64) - 1)]),
    ("ros1-bz2-bomb", [("flip", 39, 0)]),  # ValueError: an index without chunk infos, prefetched
]


@pytest.mark.parametrize("window", WINDOWS, ids=str)
@pytest.mark.parametrize(("kind", "ops"), FOUND)
def test_mutants_found(kind: str, ops: list[tuple[str, int, int]], window: RecordWindow | None, tmp_path: Path) -> None:
    suffix, data = seed(kind)
    path = tmp_path / f"bag{suffix}"
    path.write_bytes(mutated(data, ops))
    read_anything(path, window)
