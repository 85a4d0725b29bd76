"""Recording locations and remote copies, without a server: globs and prefixes expanded, and
fsspec's in-memory filesystem read through sparse copies, only the ranges the readers ask fetched."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from pathlib import Path

import fsspec
import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tftools.sources.bag import read_bag
from tftools.sources.errors import BagNotFoundError
from tftools.sources.storage import expand, is_url, recordings_in
from tftools.sources.storage.remote import GAP_BYTES, RemoteCopy, local_view


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
        remote, here = read_bag([url]), read_bag([local])
        assert remote.files[0].path == url and remote.files[0].format == here.files[0].format
        assert remote.transforms.record_time.tolist() == here.transforms.record_time.tolist()
        fetched = remote.files[0].fetched
        assert fetched is not None and 0 < fetched.received <= fetched.size and here.files[0].fetched is None
        assert fetched.whole == url.endswith("db3")


def test_missing_remote_recording_is_said_of_its_url(memory_bucket: str) -> None:
    with pytest.raises(BagNotFoundError, match=r"nothing\.bag"):
        expand([f"{memory_bucket}/nothing.bag"])
    with pytest.raises(BagNotFoundError):
        read_bag([f"{memory_bucket}/nothing.bag"])


def test_a_copy_fetches_each_range_once(memory_bucket: str) -> None:
    url = f"{memory_bucket}/fleet/robot.bag"
    with local_view(url) as view:
        (copy,) = view.copies
        assert copy.fetched == GAP_BYTES  # its header, to recognise it
        far = copy.size - 1000
        copy.fill([far - 10, far], [far + 10, far + 500])
        assert copy.fetched == GAP_BYTES + 510
        copy.fill([far], [far + 100])  # already here
        assert copy.fetched == GAP_BYTES + 510
        assert view.path.read_bytes()[far - 10 : far + 500] == SAMPLE_BAGS["ros1"].read_bytes()[far - 10 : far + 500]


def test_a_reply_longer_than_asked_is_refused(memory_bucket: str, tmp_path: Path) -> None:
    class Lying:
        def cat_ranges(self, paths: list[str], starts: list[int], ends: list[int], on_error: str) -> list[bytes]:
            return [b"x" * (e - s + 1) for s, e in zip(starts, ends, strict=True)]

    fd = (tmp_path / "copy").open("wb").fileno()
    copy = RemoteCopy(Lying(), "memory://lying.bag", "/lying.bag", 1000, fd, tmp_path / "copy")  # type: ignore[arg-type]
    with pytest.raises(Exception, match="sent 11 bytes for 10 asked"):
        copy.fill([0], [10])
