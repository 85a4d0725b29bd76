"""Each command reads each recording once: its files opened once, read in one pass (transforms, clock
and sensor headers together), and of a remote one each byte fetched at most once, by ranged reads held
in memory (no temporary file but for a .db3, which SQLite opens by name)."""

from __future__ import annotations

import collections
import itertools
import json
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import fsspec
import pytest

from tests.cli.conftest import tfx  # noqa: F401 - a fixture
from tests.cli.test_filter import bags  # noqa: F401 - a fixture
from tftools.sources import user_files
from tftools.sources.bag.reader import BagReader
from tftools.sources.bag.rosbag2.database import Database
from tftools.sources.storage import remote
from tftools.sources.storage.source import FileSource

COMMANDS = {
    "wtf": ["wtf", "BAG"],
    "filter": ["filter", "-b", "BAG", "--target", "odom"],
    "report": ["report", "BAG", "-o", "OUT/report.html"],
    "frames": ["frames", "-b", "BAG"],
    "echo": ["echo", "odom", "base_link", "-b", "BAG"],
}


class Counted:
    """What the readers did: files opened (by name), passes over the recording, metadata.yaml files read,
    sqlite connections to .db3 files, ranges fetched from a remote one (each a request), temporary files
    and directories made."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.opened: collections.Counter[str] = collections.Counter()
        self.passes = 0
        self.metadata = 0
        self.connections = 0
        self.fetched: list[tuple[str, int, int]] = []
        self.temporary: list[str] = []
        opened, read, load, connected = FileSource.__init__, BagReader.read, user_files.load, Database.__init__
        remote_opened, fetch = remote.RemoteSource.__init__, remote.RemoteSource._fetch
        remote_load = remote.RemoteFiles.load_yaml

        def counted_open(source: FileSource, path: Path) -> None:
            self.opened[path.name] += 1
            opened(source, path)

        def counted_remote_open(source: remote.RemoteSource, fs: Any, url: str, path: str, size: int) -> None:
            if not path.endswith((".db3", ".yaml")):  # a .db3 is fetched whole, then opened as a local file
                self.opened[Path(path).name] += 1
            remote_opened(source, fs, url, path, size)

        def counted_connect(database: Database, path: Path, *, native: bool = True) -> None:
            self.connections += 1
            connected(database, path, native=native)

        def counted_read(reader: BagReader, *args: Any, **kwargs: Any) -> Any:
            self.passes += 1
            return read(reader, *args, **kwargs)

        def counted_load(path: Path) -> Any:
            self.metadata += 1
            return load(path)

        def counted_remote_load(files: remote.RemoteFiles, path: Path) -> Any:
            self.metadata += 1
            return remote_load(files, path)

        def counted_fetch(source: remote.RemoteSource, pieces: list[tuple[int, int]]) -> Any:
            self.fetched += [(source.path, start, end) for start, end in pieces]
            return fetch(source, pieces)

        def made(maker: Any) -> Any:
            def counted(*args: Any, **kwargs: Any) -> Any:
                if kwargs.get("dir") is None:  # in the system's temporary directory, not beside an output
                    self.temporary.append(maker.__name__)
                return maker(*args, **kwargs)

            return counted

        monkeypatch.setattr(FileSource, "__init__", counted_open)
        monkeypatch.setattr(remote.RemoteSource, "__init__", counted_remote_open)
        monkeypatch.setattr(BagReader, "read", counted_read)
        monkeypatch.setattr(Database, "__init__", counted_connect)
        monkeypatch.setattr(user_files, "load", counted_load)
        monkeypatch.setattr(remote.RemoteFiles, "load_yaml", counted_remote_load)
        monkeypatch.setattr(remote.RemoteSource, "_fetch", counted_fetch)
        for name in ("mkdtemp", "mkstemp", "NamedTemporaryFile", "TemporaryFile", "SpooledTemporaryFile"):
            monkeypatch.setattr(tempfile, name, made(getattr(tempfile, name)))


def _run(tfx: Any, command: str, bag: str, out: Path) -> None:  # noqa: F811
    args = [a.replace("BAG", bag).replace("OUT", str(out)) for a in COMMANDS[command]]
    done = tfx(*args)
    assert done.code in (0, 1), done.stderr


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap"])
@pytest.mark.parametrize("command", list(COMMANDS))
def test_each_command_reads_a_local_recording_once(
    tfx: Any,  # noqa: F811
    bags: dict[str, Path],  # noqa: F811
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    fmt: str,
    command: str,
) -> None:
    counted = Counted(monkeypatch)
    _run(tfx, command, str(bags[fmt]), tmp_path)
    files = [bags[fmt].name] if fmt == "ros1" else [p.name for p in bags[fmt].iterdir() if p.suffix != ".yaml"]
    assert counted.passes == 1
    assert dict(counted.opened) == dict.fromkeys(files, 1)
    assert counted.metadata == (0 if fmt == "ros1" else 1)
    assert counted.connections == (len(files) if fmt == "db3" else 0)  # one sqlite connection a .db3


@pytest.fixture
def bucket(bags: dict[str, Path]) -> Iterator[str]:  # noqa: F811
    """The sensor bags in fsspec's in-memory filesystem."""
    fs = fsspec.filesystem("memory")
    root = "/tftools-reads-once"
    fs.put(str(bags["ros1"]), f"{root}/robot.bag")
    fs.put(str(bags["db3"]), f"{root}/robot_db3", recursive=True)
    fs.put(str(bags["mcap"]), f"{root}/robot_mcap", recursive=True)
    yield f"memory://{root}"
    fs.rm(root, recursive=True)


@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
@pytest.mark.parametrize("command", ["wtf", "report", "filter", "frames"])
def test_each_command_fetches_a_remote_recording_once(
    tfx: Any,  # noqa: F811
    bucket: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    command: str,
) -> None:
    """No byte of a remote recording is fetched twice (a .db3 is fetched whole: once, not once for the
    transforms and again for the sensor data), each file is opened once and read in one pass, and a
    ROS 1 bag or an MCAP file is read by ranged requests alone: no temporary file is made for it."""
    counted = Counted(monkeypatch)
    _run(tfx, command, f"{bucket}/{name}", tmp_path)
    assert counted.passes == 1 and counted.fetched
    assert counted.temporary == ([] if name != "robot_db3" else ["mkdtemp"])
    assert set(counted.opened.values()) == {1}
    assert counted.metadata == (0 if name == "robot.bag" else 1)
    by_file: dict[str, list[tuple[int, int]]] = {}
    for path, start, end in counted.fetched:
        by_file.setdefault(path, []).append((start, end))
    for ranges in by_file.values():
        ranges.sort()
        assert all(a[1] <= b[0] for a, b in itertools.pairwise(ranges)), "a byte fetched twice"


def test_a_remote_bag_directory_has_its_qos_checked(tfx: Any, bucket: str) -> None:  # noqa: F811
    """metadata.yaml's QoS comes with the bag read: a bag read by URL has /tf_static's durability
    checked, not skipped unsaid."""
    with BagReader([f"{bucket}/robot_db3"]) as reader:
        (qos,) = reader.read().qos.values()
    assert not qos.problem and "/tf_static" in qos.profiles


@pytest.mark.parametrize("command", ["wtf", "report"])
def test_the_robots_description_and_joint_states_come_with_the_same_pass(
    tfx: Any,  # noqa: F811
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    command: str,
) -> None:
    """A recording with /robot_description and /joint_states: wtf and report check the robot (its
    description's joints found, its joint states compared) from the one read of the transforms."""
    from tests.analysis.robot_scenes import Setup, robot_bag

    bag = robot_bag(tmp_path, "rover", Setup(description=True))
    counted = Counted(monkeypatch)
    args = (
        [command, str(bag), "--format", "json"] if command == "wtf" else [command, str(bag), "-o", f"{tmp_path}/r.html"]
    )
    done = tfx(*args)
    assert done.code in (0, 1), done.stderr
    assert counted.passes == 1 and dict(counted.opened) == {bag.name: 1}
    if command == "wtf":
        codes = {f["code"] for b in json.loads(done.stdout)["bags"] for f in b["findings"]}
        assert not {c for c in codes if c.startswith("urdf_") and c != "urdf_extra"}, codes
