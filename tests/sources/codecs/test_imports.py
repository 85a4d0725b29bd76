"""A load imports only the codecs of the encodings its recording holds: a .bag ``ros1``'s, a .db3 and a ROS 2
MCAP ``cdr``'s, none of them json's, protobuf's (and their ``template``, ``parsed``) or the whole-message
``robot`` decoders (imported when a read takes topics whole); no YAML library for rosbag2's metadata; and no
numpy.ma, which ``np.unique``'s first call imports (~9 ms of a process's first load)."""

from __future__ import annotations

import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tests.cli.test_start_up import loaded, modules_after
from tftools.sources.codecs.select import CLOCK_CODECS, CODECS, Wanted, WholeCodec, select

PACKAGE = "tftools.sources.codecs"
#: What no ROS recording's transforms need.
NOT_ROS = tuple(f"{PACKAGE}.{name}" for name in ("json", "protobuf", "template", "parsed", "robot"))


def load(bag: str) -> list[str]:
    return modules_after(f"import tftools; tftools.read_recording([{bag!r}])")


def test_a_bag_imports_only_ros1_codecs() -> None:
    modules = load(str(SAMPLE_BAGS["ros1"]))
    assert f"{PACKAGE}.ros1" in modules
    assert loaded(modules, (*NOT_ROS, f"{PACKAGE}.cdr")) == []
    assert loaded(modules, ("bz2", "lzma")) == []  # its chunks are not compressed
    assert loaded(modules, ("numpy.ma",)) == []  # np.unique's first call imports it: none on the read


@pytest.mark.parametrize("kind", ["db3", "mcap"])
def test_a_ros2_recording_imports_no_numpy_ma(kind: str) -> None:
    assert loaded(load(str(SAMPLE_BAGS[kind])), ("numpy.ma",)) == []


@pytest.mark.parametrize("kind", ["db3", "mcap"])
def test_a_ros2_recording_imports_only_cdr_codecs(kind: str) -> None:
    modules = load(str(SAMPLE_BAGS[kind]))
    assert f"{PACKAGE}.cdr" in modules
    assert loaded(modules, (*NOT_ROS, f"{PACKAGE}.ros1")) == []
    assert loaded(modules, ("ruamel",)) == []  # its metadata.yaml, in the block YAML rosbag2 writes
    assert loaded(modules, ("tempfile",)) == []  # its files are not compressed whole


def test_the_robot_decoders_are_selected_for_topics_read_whole() -> None:
    from tftools.sources.codecs.robot import WHOLE_DECODERS

    for (type_name, encoding), decoder in WHOLE_DECODERS.items():
        codec, unread = select("/joint_states", type_name, encoding, Wanted(whole=("/joint_states",)))
        assert isinstance(codec, WholeCodec) and codec.decode is decoder and unread is None


def test_each_codec_decodes_with_its_modules_decoder() -> None:
    from tftools.sources.codecs import cdr, json, protobuf, ros1

    modules = {"cdr": cdr, "json": json, "protobuf": protobuf, "ros1": ros1}
    for (_, encoding), codec in CODECS.items():
        assert codec.decode is getattr(modules[encoding], codec.decoder.split(".")[1])
    for (_, encoding), clock in CLOCK_CODECS.items():
        assert clock.decode is modules[encoding].decode_clocks
