"""Recording locations and remote files, without a server: globs and prefixes expanded, and fsspec's
in-memory filesystem read by ranged requests, only the ranges the readers ask fetched, each once."""

from __future__ import annotations

import http.server
import shutil
import threading
import time
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import ClassVar

import fsspec
import numpy as np
import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tests.sources.bag.reading import read_contents
from tftools.sources.errors import BagError, BagNotFoundError, RemoteError
from tftools.sources.storage import expand, is_url, recordings_in, remote
from tftools.sources.storage.remote import BATCH_BYTES, BLOCK_BYTES, RemoteFiles, RemoteSource


def test_urls_and_paths_told_apart() -> None:
    assert is_url("s3://bucket/a.bag") and is_url("https://host/a.mcap") and is_url("memory://x")
    assert not is_url("logs/a.bag") and not is_url("/abs/a.bag") and not is_url("C:/a.bag")


def test_recordings_in_a_listing() -> None:
    files = ["a.bag", "x/run_db3/metadata.yaml", "x/run_db3/run_0.db3", "x/b.mcap", "notes.txt", "y/c.db3"]
    assert recordings_in(files) == ["a.bag", "x/b.mcap", "x/run_db3", "y/c.db3"]
    assert recordings_in(["metadata.yaml", "bag_0.db3"]) == [""]  # the prefix is itself one bag


def test_local_prefix_and_quoted_glob_expand(tmp_path: Path) -> None:
    shutil.copy(SAMPLE_BAGS["ros1"], tmp_path / "a.bag")
    shutil.copytree(SAMPLE_BAGS["db3"], tmp_path / "deep" / "run_db3")
    (tmp_path / "readme.txt").write_text("not a bag")
    assert expand([f"{tmp_path}/"]) == [str(tmp_path / "a.bag"), str(tmp_path / "deep" / "run_db3")]
    assert expand([f"{tmp_path}/*.bag"]) == [str(tmp_path / "a.bag")]
    assert expand([f"{tmp_path}/deep/run_db3/"]) == [f"{tmp_path}/deep/run_db3/"]  # a bag itself, as given
    with pytest.raises(BagNotFoundError):
        expand([f"{tmp_path}/*.mcap"])


@pytest.fixture
def memory_bucket() -> Iterator[str]:
    """The sample bags in fsspec's in-memory filesystem."""
    fs = fsspec.filesystem("memory")
    root = "/tftools-test-bucket"
    fs.put(str(SAMPLE_BAGS["ros1"]), f"{root}/fleet/robot.bag")
    fs.put(str(SAMPLE_BAGS["db3"]), f"{root}/fleet/robot_db3", recursive=True)
    fs.put(str(SAMPLE_BAGS["mcap"]), f"{root}/fleet/robot_mcap", recursive=True)
    fs.pipe(f"{root}/fleet/broken.bag", b"#ROSBAG V2.0\n" + b"\xff" * 5000)
    yield f"memory://{root}"
    fs.rm(root, recursive=True)


def test_remote_recordings_read_as_the_local_ones(memory_bucket: str) -> None:
    found = expand([f"{memory_bucket}/fleet/"])
    names = ["broken.bag", "robot.bag", "robot_db3", "robot_mcap"]
    assert found == [f"{memory_bucket}/fleet/{name}" for name in names]
    for url, local in zip(found[1:], (SAMPLE_BAGS["ros1"], SAMPLE_BAGS["db3"], SAMPLE_BAGS["mcap"]), strict=True):
        remote, here = read_contents([url]), read_contents([local])
        assert remote.files[0].path == url and remote.files[0].format == here.files[0].format
        assert remote.transforms.record_time.tolist() == here.transforms.record_time.tolist()
        fetched = remote.files[0].fetched
        assert fetched is not None and 0 < fetched.received <= fetched.size and here.files[0].fetched is None
        assert fetched.whole == url.endswith("db3")


@pytest.mark.parametrize(
    ("name", "damage"),
    [("ros1", "cut"), ("ros1", "middle"), ("ros1", "index"), ("mcap", "cut"), ("mcap", "middle")],
)
def test_a_damaged_remote_file_reads_as_its_local_copy(tmp_path: Path, name: str, damage: str) -> None:
    """Damaged files are read without their index (scanned, resynchronised after damage) through
    ranged reads alone, as their local copies are: the same messages and problems, each byte fetched once."""
    source = SAMPLE_BAGS[name] if name == "ros1" else next(SAMPLE_BAGS[name].glob("*.mcap"))
    data = bytearray(source.read_bytes())
    if damage == "cut":
        data = data[: len(data) * 6 // 10]
    elif damage == "middle":
        data[len(data) // 3 : len(data) // 3 + 3000] = b"\xff" * 3000
    else:  # the index records at the end
        data[-2000:] = b"\xff" * 2000
    local = tmp_path / f"damaged{source.suffix}"
    local.write_bytes(bytes(data))
    fs = fsspec.filesystem("memory")
    fs.pipe(f"/tftools-damaged/{local.name}", bytes(data))
    try:
        here, there = read_contents([local]), read_contents([f"memory:///tftools-damaged/{local.name}"])
    finally:
        fs.rm("/tftools-damaged", recursive=True)
    assert there.transforms.record_time.tolist() == here.transforms.record_time.tolist()
    assert here.files[0].problems and [p.replace("damaged", "x") for p in there.files[0].problems] == [
        p.replace("damaged", "x") for p in here.files[0].problems
    ]
    fetched = there.files[0].fetched
    assert fetched is not None and fetched.received <= fetched.size == len(data)


def test_missing_remote_recording_is_said_of_its_url(memory_bucket: str) -> None:
    with pytest.raises(BagNotFoundError, match=r"nothing\.bag"):
        expand([f"{memory_bucket}/nothing.bag"])
    with pytest.raises(BagNotFoundError):
        read_contents([f"{memory_bucket}/nothing.bag"])


def test_a_failed_read_is_said_of_its_url_once(memory_bucket: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A read the server fails, after the file was opened, names the URL as given (which holds the
    filesystem's path: not replaced in it again) and stays a ``RemoteError``."""
    url = f"{memory_bucket}/fleet/robot.bag"
    fs = fsspec.filesystem("memory")
    served = fs.cat_ranges

    def failing_past_the_first_block(paths: list[str], starts: list[int], ends: list[int], **kwargs: object) -> object:
        if min(starts) < BLOCK_BYTES:
            return served(paths, starts, ends, **kwargs)
        return [ConnectionResetError("reset")] * len(paths)

    monkeypatch.setattr(
        type(fs), "cat_ranges", lambda self, *args, **kwargs: failing_past_the_first_block(*args, **kwargs)
    )
    with pytest.raises(RemoteError) as raised:
        read_contents([url])
    message = str(raised.value)
    assert message.startswith(f"{url}: reading bytes ") and message.count("memory:/") == 1 and "reset" in message


def test_a_read_dropped_once_is_asked_again(memory_bucket: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A server under load drops a request now and then: the piece is asked once more, and the bag reads
    as its local copy."""
    url = f"{memory_bucket}/fleet/robot.bag"
    fs = fsspec.filesystem("memory")
    served = fs.cat_ranges
    dropped: list[int] = []

    def dropping_each_piece_once(paths: list[str], starts: list[int], ends: list[int], **kwargs: object) -> object:
        replies = served(paths, starts, ends, **kwargs)
        fresh = [i for i, start in enumerate(starts) if start not in dropped]
        dropped.extend(starts[i] for i in fresh)
        return [ConnectionResetError("reset") if i in fresh else reply for i, reply in enumerate(replies)]

    monkeypatch.setattr(type(fs), "cat_ranges", lambda self, *args, **kwargs: dropping_each_piece_once(*args, **kwargs))
    there, here = read_contents([url]), read_contents([SAMPLE_BAGS["ros1"]])
    assert dropped and len(there.transforms) == len(here.transforms) > 0
    assert np.array_equal(there.transforms.stamp, here.transforms.stamp)


def test_a_remote_file_fetches_each_range_once(memory_bucket: str) -> None:
    """A small read fetches the block after it (the next record headers are near); what was fetched
    is kept, and read again without a request."""
    expected = SAMPLE_BAGS["ros1"].read_bytes()
    with RemoteFiles(f"{memory_bucket}/fleet/robot.bag") as files, files.open(files.root) as source:
        assert isinstance(source, RemoteSource) and source.size == len(expected)
        assert source.read(0, 13) == expected[:13] and source.fetched == BLOCK_BYTES and source.requests == 1
        assert source.read(100, 200) == expected[100:200] and source.requests == 1  # in the block
        far = source.size - 1000
        assert source.read(far - 10, far + 500) == expected[far - 10 : far + 500]
        assert source.fetched == BLOCK_BYTES + 1000 + 10  # the block after it reaches the end
        assert source.read(far, far + 100) == expected[far : far + 100] and source.requests == 2


def test_planned_ranges_are_fetched_together_as_they_are_reached(memory_bucket: str) -> None:
    """Ranges a reader says it will read (``ahead``) are fetched in one call when the first is read
    (ranges closer than the gap as one request), and what is read into place is not kept."""
    expected = SAMPLE_BAGS["ros1"].read_bytes()
    with RemoteFiles(f"{memory_bucket}/fleet/robot.bag") as files, files.open(files.root) as source:
        assert isinstance(source, RemoteSource)
        starts, ends = np.array([300_000, 1000, 200_000], np.int64), np.array([300_100, 1100, 200_100], np.int64)
        data, where, whole = source.read_ranges(starts, ends)
        assert whole.all() and source.requests == 3 and source.fetched == 300
        for start, end, at in zip(starts.tolist(), ends.tolist(), where.tolist(), strict=True):
            assert data[at : at + end - start].tobytes() == expected[start:end]
        source.ahead(np.array([400_000, 400_500], np.int64), np.array([400_100, 400_600], np.int64))
        assert source.read(400_500, 400_600) == expected[400_500:400_600]
        assert source.requests == 4 and source.fetched == 300 + 600  # one request, what lies between too
        assert source.read(400_000, 400_100) == expected[400_000:400_100] and source.requests == 4


def test_what_is_kept_is_bounded(memory_bucket: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A file read through in order (no index: every record) keeps at most ``CACHE_BYTES`` of it, and
    asks ``BATCH_BYTES`` at a time."""
    monkeypatch.setattr(remote, "CACHE_BYTES", 64 << 10)
    monkeypatch.setattr(remote, "BATCH_BYTES", 32 << 10)
    expected = SAMPLE_BAGS["ros1"].read_bytes()
    with RemoteFiles(f"{memory_bucket}/fleet/robot.bag") as files, files.open(files.root) as source:
        assert isinstance(source, RemoteSource)
        buffer = source.buffer()
        source.ahead(np.zeros(1, np.int64), np.full(1, source.size, np.int64))
        most = 0
        for start in range(0, source.size, 1000):
            assert buffer[start : start + 100] == expected[start : start + 100]
            most = max(most, source._kept)
        assert most <= 64 << 10 and source.fetched == source.size
        assert source.requests == -(-source.size // (32 << 10))
    assert BATCH_BYTES == 64 << 20


def test_a_reply_longer_than_asked_is_refused() -> None:
    class Lying:
        def cat_ranges(self, paths: list[str], starts: list[int], ends: list[int], on_error: str) -> list[bytes]:
            return [b"x" * (e - s + 1) for s, e in zip(starts, ends, strict=True)]

    source = RemoteSource(Lying(), "memory://lying.bag", "/lying.bag", 1000)
    with pytest.raises(RemoteError, match="sent 11 bytes for 10 asked"):
        source.read_ranges(np.zeros(1, np.int64), np.full(1, 10, np.int64))


class _HostileHandler(http.server.BaseHTTPRequestHandler):
    """A server for hostile replies: a gzip-encoded body (``gzip``) or one trickled a byte at a time."""

    encodings: ClassVar[list[str]] = []
    trickle: ClassVar[bool] = False
    body: ClassVar[bytes] = b""

    def do_HEAD(self) -> None:
        self.send_response(200)
        self.send_header("Content-Length", str(1 << 20))
        self.end_headers()

    def do_GET(self) -> None:
        type(self).encodings.append(self.headers.get("Accept-Encoding", ""))
        self.send_response(206)
        self.send_header("Content-Range", f"bytes 0-{(1 << 20) - 1}/{1 << 20}")
        if self.trickle:  # 40 bytes in 4 s: a whole reply, each byte well within the read timeout
            self.send_header("Content-Length", "40")
            self.end_headers()
            for _ in range(40):
                self.wfile.write(b"x")
                self.wfile.flush()
                time.sleep(0.1)
            return
        self.send_header("Content-Encoding", "gzip")
        self.send_header("Content-Length", str(len(self.body)))
        self.end_headers()
        self.wfile.write(self.body)

    def log_message(self, *args: object) -> None:
        pass


@pytest.fixture
def hostile_server() -> Iterator[str]:
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _HostileHandler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()


def test_a_gzip_encoded_reply_is_not_inflated(hostile_server: str) -> None:
    """A server answering with ``Content-Encoding: gzip`` (here 16 MiB of zeros in 16 KiB): the body is
    taken as sent, never inflated in memory (issue 32 M5): the bag is unreadable, not a memory bomb."""
    squeeze = zlib.compressobj(9, zlib.DEFLATED, 31)
    _HostileHandler.body = squeeze.compress(bytes(16 << 20)) + squeeze.flush()
    _HostileHandler.trickle = False
    _HostileHandler.encodings.clear()
    with pytest.raises(BagError) as caught:
        read_contents([f"{hostile_server}/bomb.bag"])
    assert "sent" not in str(caught.value)  # not inflated past the bytes asked for
    assert _HostileHandler.encodings and set(_HostileHandler.encodings) == {"identity"}


def test_a_trickling_server_meets_the_deadline(hostile_server: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A server sending a byte at a time, each within the read timeout, still meets the request's
    overall deadline (issue 32 H2)."""
    monkeypatch.setattr(remote, "REQUEST_DEADLINE", 1)
    _HostileHandler.trickle = True
    with pytest.raises(RemoteError, match="failed"):  # without the deadline: read, and not a bag
        read_contents([f"{hostile_server}/slow.bag"])
