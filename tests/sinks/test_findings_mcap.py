"""``tfx wtf BAG --mcap FILE``: the findings beside the recording, as Foxglove decodes them, on its times."""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from tests.bags import TfMessage, write_bag
from tests.cli.conftest import Tfx
from tftools.analysis.wtf.health import Level, check_name, edge_name
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START = 1_700_000_000 * NS_PER_S
IDENTITY = (0.0, 0.0, 0.0, 1.0)


@pytest.fixture(scope="module")
def stopping_bag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """map -> odom for 20 s at 10 Hz; odom -> base_link with it for the first 10 s only (stale)."""
    messages = []
    for i in range(200):
        at = START + i * NS_PER_S // 10
        transforms = [Transform((1.0, 0.0, 0.0), IDENTITY, at, "map", "odom")]
        if i < 100:
            transforms.append(Transform((i / 100, 0.0, 0.0), IDENTITY, at, "odom", "base_link"))
        messages.append(TfMessage("/tf", at + 1_000_000, transforms, "/robot"))
    return write_bag(tmp_path_factory.mktemp("bags") / "stopping.bag", messages)


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _messages(path: Path) -> list[tuple[str, str, int, Any]]:
    """(topic, schema, log time, decoded) of every message: protobuf by Foxglove's schemas as written in the
    file, ros1msg by the definition the file carries."""
    decoded = []
    store = get_typestore(Stores.EMPTY)
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        for schema, channel, message in reader.iter_messages():
            assert schema is not None
            if schema.encoding == "protobuf":
                decoder = DecoderFactory().decoder_for("protobuf", schema)
                assert decoder is not None
                value = decoder(message.data)
            else:
                assert schema.encoding == "ros1msg" and channel.message_encoding == "ros1"
                name = schema.name.replace("/", "/msg/", 1)
                if name not in store.types:
                    store.register(get_types_from_msg(schema.data.decode(), name))
                value = store.deserialize_ros1(message.data, name)
            decoded.append((channel.topic, schema.name, message.log_time, value))
    return decoded


def test_each_finding_is_a_foxglove_log_at_its_time_with_its_hint(tfx: Tfx, stopping_bag: Path, tmp_path: Path) -> None:
    out = tmp_path / "findings.mcap"
    before = _digest(stopping_bag)
    result = tfx("wtf", stopping_bag, "--mcap", out)
    assert result.code == 1, result.stderr  # the stale edge is an error
    assert "wrote" in result.stderr and str(out) in result.stderr
    assert _digest(stopping_bag) == before
    messages = _messages(out)
    logs = [m for m in messages if m[1] == "foxglove.Log"]
    [stale] = [log for _, _, _, log in logs if log.name == "tfx wtf: stale"]
    assert stale.level == stale.ERROR
    assert "odom -> base_link" in stale.message and "\nhint: " in stale.message
    begin, end = START + 1_000_000, START + 199 * NS_PER_S // 10 + 1_000_000
    assert all(begin <= at <= end for _, _, at, _ in messages)  # on the recording's own record times
    stale_at = next(at for _, _, at, log in logs if log.name == "tfx wtf: stale")
    assert stale_at == START + 99 * NS_PER_S // 10  # its last transform: when the edge stopped
    [frames] = [m for _, schema, _, m in messages if schema == "foxglove.FrameTransforms"]
    [edge] = frames.transforms
    assert (edge.parent_frame_id, edge.child_frame_id) == ("odom", "base_link")


def test_diagnostics_say_the_edge_healthy_then_stopped_once_a_second(
    tfx: Tfx, stopping_bag: Path, tmp_path: Path
) -> None:
    out = tmp_path / "findings.mcap"
    tfx("wtf", stopping_bag, "--mcap", out)
    arrays = [(at, m) for topic, _, at, m in _messages(out) if topic == "/diagnostics"]
    assert len(arrays) == 20  # one a second over the 19.9 s recording
    assert all(m.header.stamp.sec * NS_PER_S + m.header.stamp.nanosec == at for at, m in arrays)

    def levels(message: Any) -> dict[str, int]:
        return {s.name: s.level for s in message.status}

    early = levels(arrays[5][1])  # at +5 s: both edges moving
    assert early[edge_name("odom", "base_link")] == Level.OK and early[check_name("stale")] == Level.OK
    late = levels(arrays[-1][1])
    assert late[check_name("stale")] == Level.ERROR and late["tf: tree"] == Level.ERROR
    rate = {kv.key: kv.value for s in arrays[5][1].status if s.name == edge_name("map", "odom") for kv in s.values}
    assert rate["rate (Hz)"] == "10.000"


def test_an_existing_file_is_kept_without_force(tfx: Tfx, stopping_bag: Path, tmp_path: Path) -> None:
    out = tmp_path / "findings.mcap"
    out.write_bytes(b"mine")
    result = tfx("wtf", stopping_bag, "--mcap", out)
    assert result.code == 2 and "exists" in result.stderr and "--force" in result.stderr
    assert out.read_bytes() == b"mine"
    assert tfx("wtf", stopping_bag, "--mcap", out, "--force").code == 1
    assert out.read_bytes().startswith(b"\x89MCAP")


def test_the_recording_itself_is_never_written(tfx: Tfx, stopping_bag: Path) -> None:
    before = _digest(stopping_bag)
    result = tfx("wtf", stopping_bag, "--mcap", stopping_bag, "--force")
    assert result.code == 2 and "is the input" in result.stderr and "never writes over its input" in result.stderr
    assert _digest(stopping_bag) == before


def test_one_recording_at_a_time(tfx: Tfx, stopping_bag: Path, tmp_path: Path) -> None:
    other = tmp_path / "other.bag"
    other.write_bytes(stopping_bag.read_bytes())
    result = tfx("wtf", stopping_bag, other, "--mcap", tmp_path / "f.mcap")
    assert result.code == 2 and "one recording" in result.stderr
    assert not (tmp_path / "f.mcap").exists()


def test_report_writes_the_same_findings_beside_its_page(tfx: Tfx, stopping_bag: Path, tmp_path: Path) -> None:
    out, page = tmp_path / "findings.mcap", tmp_path / "report.html"
    result = tfx("report", stopping_bag, "-o", page, "--mcap", out)
    assert result.code == 1, result.stderr
    assert page.exists()
    names = {log.name for _, schema, _, log in _messages(out) if schema == "foxglove.Log"}
    assert "tfx wtf: stale" in names


def test_report_refuses_an_existing_mcap_before_writing_its_page(tfx: Tfx, stopping_bag: Path, tmp_path: Path) -> None:
    out, page = tmp_path / "findings.mcap", tmp_path / "report.html"
    out.write_bytes(b"mine")
    result = tfx("report", stopping_bag, "-o", page, "--mcap", out)
    assert result.code == 2 and "exists" in result.stderr
    assert not page.exists() and out.read_bytes() == b"mine"


def test_diagnostics_of_a_long_recording_are_bounded_in_number(
    tfx: Tfx, stopping_bag: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Once a second over the recording's record times: a recording whose record times spanned decades (a time
    from a damaged file) made a status a second from 1970 on, without end. Over ``MOST_STATUSES`` seconds they come
    less often, spread over the whole: here at most 5 over the 19.9 s recording, from its start to its end."""
    from tftools.sinks import findings_mcap

    monkeypatch.setattr(findings_mcap, "MOST_STATUSES", 5)
    out = tmp_path / "findings.mcap"
    tfx("wtf", stopping_bag, "--mcap", out)
    times = [at for topic, _, at, _ in _messages(out) if topic == "/diagnostics"]
    assert len(times) == 5 and times[0] == START + 1_000_000 and times[-1] >= START + 15 * NS_PER_S, times
