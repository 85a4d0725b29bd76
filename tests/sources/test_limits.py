"""Hostile input, round two (issue 32): YAML of every use, special files, folders too large to search
and peers holding many half-sent messages are refused where they enter, with one line, at once."""

from __future__ import annotations

import os
import socket
import struct
import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from tftools.analysis.tree_file import TreeFileError, read_tree
from tftools.sources import user_files
from tftools.sources.errors import BagError
from tftools.sources.live.ros1 import tcpros
from tftools.sources.live.static_file import StaticFileError, read_static_transforms
from tftools.sources.storage import locations

READERS = [read_static_transforms, read_tree]


@pytest.fixture
def fifo(tmp_path: Path) -> Path:
    path = tmp_path / "f.yaml"
    os.mkfifo(path)
    return path


@pytest.mark.parametrize("read", READERS)
def test_a_fifo_or_a_device_is_refused_without_blocking(read: Callable[[Path], object], fifo: Path) -> None:
    for path, kind in ((fifo, "a FIFO"), (Path("/dev/zero"), "a device")):
        with pytest.raises((StaticFileError, TreeFileError)) as caught:
            read(path)  # a FIFO without a writer: opening it for reading would block for ever
        assert f"{kind} or socket" in str(caught.value) or f"{kind}, not a regular file" in str(caught.value)
        assert "no such file" not in str(caught.value)
        assert "save what it gives to a file" in caught.value.hint


@pytest.mark.parametrize("read", READERS)
def test_a_missing_file_and_a_folder_are_said_so(read: Callable[[Path], object], tmp_path: Path) -> None:
    with pytest.raises((StaticFileError, TreeFileError), match="no such file"):
        read(tmp_path / "missing.yaml")
    with pytest.raises((StaticFileError, TreeFileError), match="a folder, not a file"):
        read(tmp_path)


@pytest.mark.parametrize("read", READERS)
def test_a_file_larger_than_the_limit_is_not_read_whole(
    read: Callable[[Path], object], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(user_files, "MAX_BYTES", 1000)
    big = tmp_path / "big.yaml"
    big.write_bytes(b"#" * 5000)
    with pytest.raises((StaticFileError, TreeFileError), match="larger than"):
        read(big)


DEEP = {
    "flow": "a: " + "[" * 100_000,  # ruamel's scanner is quadratic in a flow's depth: seconds, refused at once
    "mapping-flow": "{a: " * 20_000,
    "block": "".join(" " * i + "- \n" for i in range(1500)),  # the composer recurses once per level
    "sequence": "- " * 3000,
}


@pytest.mark.parametrize("text", DEEP.values(), ids=DEEP)
@pytest.mark.parametrize("read", READERS)
def test_deep_yaml_is_refused_as_too_deep(read: Callable[[Path], object], text: str, tmp_path: Path) -> None:
    path = tmp_path / "deep.yaml"
    path.write_text(text)
    with pytest.raises((StaticFileError, TreeFileError), match=f"nested deeper than {user_files.MAX_DEPTH} levels"):
        read(path)


@pytest.mark.parametrize("text", [DEEP["flow"], DEEP["mapping-flow"]], ids=["flow", "mapping-flow"])
def test_deep_flow_is_refused_before_it_is_parsed(text: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """ruamel's scanner is quadratic in a flow's depth: reaching the recursion limit took 12 s."""

    def parse(*_: object) -> None:
        raise AssertionError("parsed")

    monkeypatch.setattr("ruamel.yaml.YAML.load", parse)
    with pytest.raises(user_files.UserFileError, match="nested deeper"):
        user_files.load_text(text)


LONG = {"lines": "- x\n" * 60_000, "flow": "[" + "x, " * 60_000 + "x]"}


@pytest.mark.parametrize("text", LONG.values(), ids=LONG)
@pytest.mark.parametrize("read", READERS)
def test_yaml_of_more_lines_and_items_than_tfx_parses_is_refused_before_it_is_parsed(
    read: Callable[[Path], object], text: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """ruamel parses ~10,000 lines or items a second: 200,000 listed files took 20 s."""

    def parse(*_: object) -> None:
        raise AssertionError("parsed")

    monkeypatch.setattr("ruamel.yaml.YAML.load", parse)
    path = tmp_path / "long.yaml"
    path.write_text(text)
    with pytest.raises((StaticFileError, TreeFileError), match="more than 50,000 lines and items"):
        read(path)


def test_yaml_just_within_the_lines_tfx_parses_is_read() -> None:
    text = "- x\n" * (user_files.MAX_ITEMS - 1)
    assert len(user_files.load_text(text)) == user_files.MAX_ITEMS - 1


def test_brackets_in_quotes_and_comments_do_not_count_as_nesting() -> None:
    text = "a: '[[[['\nb: \"{{{{\"  # [[[[[[[[\nc: [[1, 2], {d: [3]}]\n"
    assert user_files._flow_depth(text) == 3
    assert user_files.load_text(text) == {"a": "[[[[", "b": "{{{{", "c": [[1, 2], {"d": [3]}]}


def test_a_reused_anchor_is_read_without_a_library_warning(tmp_path: Path, recwarn: pytest.WarningsRecorder) -> None:
    path = tmp_path / "static.yaml"
    path.write_text(
        "- &a {frame_id: base_link, child_frame_id: laser, x: 1}\n- &a {frame_id: base_link, child_frame_id: cam}\n"
    )
    assert [t.child_frame_id for t in read_static_transforms(path)] == ["laser", "cam"]
    assert not [w for w in recwarn if "nchor" in str(w.message)]


def test_a_folder_holding_too_many_files_is_not_searched(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(locations, "MAX_FILES_BELOW", 50)
    for i in range(3):
        sub = tmp_path / f"d{i}"
        sub.mkdir()
        for j in range(30):
            (sub / f"{j}.txt").touch()
    with pytest.raises(BagError, match="holds more than 50 files below it") as caught:
        locations.expand_local(f"{tmp_path}/")
    assert "a folder closer to them" in caught.value.hint
    (tmp_path / "d0" / "run.bag").touch()
    monkeypatch.setattr(locations, "MAX_FILES_BELOW", 200)
    assert locations.expand_local(f"{tmp_path}/") == [str(tmp_path / "d0" / "run.bag")]


def test_half_sent_messages_are_bounded_over_all_peers(monkeypatch: pytest.MonkeyPatch) -> None:
    """64 peers each half-way through a 60 MiB message held 3.3 GB; all links together now hold at most
    ``MAX_IN_FLIGHT``: a message that would pass it is refused, and its room is given back when one ends."""
    monkeypatch.setattr(tcpros, "IN_FLIGHT", tcpros._InFlight(100))
    first, first_peer = socket.socketpair()
    second, second_peer = socket.socketpair()
    with first, first_peer, second, second_peer:
        first_peer.sendall(struct.pack("<I", 80) + b"x" * 40)  # half a message of 80 bytes
        got: list[bytes] = []
        reader = threading.Thread(target=lambda: got.append(tcpros.read_message(first)))
        reader.start()
        while tcpros.IN_FLIGHT.held != 80:
            time.sleep(0.01)
        second_peer.sendall(struct.pack("<I", 50) + b"y" * 50)
        with pytest.raises(tcpros.ProtocolError, match="above tfx's limit of 100 in all"):
            tcpros.read_message(second)
        first_peer.sendall(b"x" * 40)
        reader.join(10)
        assert got == [b"x" * 80] and tcpros.IN_FLIGHT.held == 0
    third, third_peer = socket.socketpair()  # the refused link is dropped; a new one is heard again
    with third, third_peer:
        third_peer.sendall(struct.pack("<I", 50) + b"z" * 50)
        assert tcpros.read_message(third) == b"z" * 50


@pytest.mark.slow
def test_a_silent_s3_endpoint_ends_within_the_listing_deadline(monkeypatch: pytest.MonkeyPatch) -> None:
    """An S3 endpoint that accepts connections and never answers (issue 32, H2): botocore's timeouts are
    per read and per attempt, and retried; the call as a whole has LISTING_DEADLINE."""
    pytest.importorskip("s3fs")
    from tftools.sources.errors import RemoteError
    from tftools.sources.storage import remote

    server = socket.create_server(("127.0.0.1", 0))
    held: list[socket.socket] = []
    threading.Thread(target=lambda: held.extend(iter(lambda: server.accept()[0], None)), daemon=True).start()
    monkeypatch.setattr(remote, "LISTING_DEADLINE", 2)
    monkeypatch.setenv("AWS_ENDPOINT_URL", f"http://127.0.0.1:{server.getsockname()[1]}")
    monkeypatch.setenv("AWS_ACCESS_KEY_ID", "x")
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "y")
    with server, pytest.raises(RemoteError, match="listing failed") as caught:
        remote.expand("s3://bucket/x.bag")
    assert "\n" not in str(caught.value) and held  # it did connect, and was held silent
