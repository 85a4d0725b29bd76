"""The commands other than ``wtf`` and ``monitor`` on the corpus, judged by each recording's bytes (read here
with rosbags, ``tests/corpus/data.py``): where findings are placed, what ``tfx filter`` says of recordings
without sensor data tied to tf, ``tfx echo --all`` of a static edge, and the report's facts."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path
from typing import Any, cast

import numpy as np
import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus import data
from tests.corpus.fetch import Recording
from tests.corpus.recordings import BY_ID, RECORDINGS, WITH_TF, Corpus
from tftools.core.time import NS_PER_S


def _span(contents: data.Contents) -> tuple[int, int]:
    """The times a finding may be at: the moving edges' stamps and the record times (ns). A static's stamp is
    not one: robot_state_publisher stamps its statics when it starts, hours before a recording may begin."""
    times = [contents.first_record, contents.last_record]
    times += [t for samples in contents.dynamic.values() for t in (min(samples.stamps), max(samples.stamps))]
    return min(times), max(times)


@pytest.mark.parametrize("recording", WITH_TF, ids=[r.id for r in WITH_TF])
def test_findings_are_placed_inside_the_recording(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Each finding's time (where the report's timelines zoom when it is clicked, and wtf's JSON ``first_time``)
    lies within the recording's stamps or record times: a real Create 3's 21 ``urdf_moved`` were placed 4.1 h
    before the recording, at their /tf_static message's stamp."""
    path = corpus(recording)
    result = tfx("wtf", path, "--format", "json")
    assert result.code in (0, 1), result.stderr
    low, high = _span(data.read_contents(path))
    for finding in json.loads(result.stdout)["bags"][0]["findings"]:
        for key in ("first_time", "last_time"):
            when = finding.get(key)
            if when:
                assert low - NS_PER_S <= when * NS_PER_S <= high + NS_PER_S, (finding["code"], key, when, low, high)


@pytest.mark.parametrize("recording", WITH_TF, ids=[r.id for r in WITH_TF])
def test_filter_checks_a_topic_or_says_there_is_none_to_check(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``tfx filter -b BAG`` shows at least one topic, or, exactly where no topic's header names a frame (read
    with rosbags: ``data.framed_topics``), says there is no sensor data to check and the topics there are,
    and exits 0: a turtlesim bag whose only stamped topic is /rosout printed an empty table, then (until
    left40) a recording of tf alone (the Grand Tour's calibration, the ROS 2 talkers) exited 2 as if the
    command line were wrong, failing a CI that checks every recording."""
    path = corpus(recording)
    result = tfx("filter", "-b", path, "--format", "json")
    assert result.code in (0, 1), result.stderr
    report = json.loads(result.stdout)
    if report["unchecked"] is None:
        assert report["topics"], "an empty table"
        return
    assert result.code == 0 and not report["topics"] and not data.framed_topics(path)
    assert set(report["unchecked"]["topics"]) == data.read_contents(path).topics
    assert report["unchecked"]["note"].startswith("No sensor data to check: ")


def _one_valued_statics(contents: data.Contents) -> list[tuple[str, str]]:
    """Static edges sent with one value only, whose child has no other parent: what any tf2 answers alike."""
    parents: dict[str, int] = {}
    for _, child in contents.edges:
        parents[child] = parents.get(child, 0) + 1
    return [
        edge
        for edge, samples in contents.edges.items()
        if samples.static and parents[edge[1]] == 1 and len({tuple(v) for v in samples.values}) == 1
    ]


@pytest.mark.parametrize("recording", WITH_TF, ids=[r.id for r in WITH_TF])
def test_echo_all_of_a_static_edge_is_its_one_transform(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``tfx echo PARENT CHILD --all`` on a static edge prints its one transform, as the bytes hold it (a
    calibration bag of one /tf_static message printed nothing and exited 0)."""
    path = corpus(recording)
    statics = _one_valued_statics(data.read_contents(path))
    if not statics:
        pytest.skip("no static edge of one value")
    contents = data.read_contents(path)
    parent, child = statics[0]
    result = tfx("echo", parent, child, "-b", path, "--all", "--format", "json")
    assert result.code == 0, result.stdout + result.stderr
    (line,) = [json.loads(x) for x in result.stdout.splitlines()]
    value = contents.edges[parent, child].values[0]
    np.testing.assert_allclose(line["translation"], value[:3], atol=1e-9)
    q = np.asarray(line["rotation"]) * (1 if np.dot(line["rotation"], value[3:]) >= 0 else -1)
    np.testing.assert_allclose(q, value[3:], atol=1e-9)


WITHOUT_TF = [r for r in RECORDINGS if "no_tf" in r.meta["expected"]["errors"]]
REPORTED = WITH_TF + [r for r in WITHOUT_TF if r not in WITH_TF]


@pytest.mark.parametrize("recording", WITHOUT_TF, ids=[r.id for r in WITHOUT_TF])
def test_sensor_data_without_tf_has_no_target_frame(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A recording that holds no transform (its bytes: no tf edge) has no tree, so no frame to check its sensor
    data in: wtf's JSON said ``sensor_data.target: ""`` "the root of the largest tree" (the AUV's /ping1d/range,
    the Crazyflie's Vicon pose), a frame a script would take for one. It is null, with why, in -f json and
    -f jsonl alike (the line --resume reads back)."""
    path = corpus(recording)
    assert not data.read_contents(path).edges
    whole = json.loads(tfx("wtf", "-b", path, "-f", "json").stdout)["bags"][0]
    lines = [json.loads(x) for x in tfx("wtf", "-b", path, "-f", "jsonl").stdout.splitlines()]
    (line,) = [x for x in lines if x["type"] == "recording"]
    for said in (whole["sensor_data"], line["sensor_data"]):
        if said is not None:  # no topic with a header tied to tf: no sensor data said
            assert said["target"] is None and said["target_reason"] == "no transforms, so no tree to transform it into"


@pytest.mark.parametrize("recording", REPORTED, ids=[r.id for r in REPORTED])
def test_the_report_names_the_tf_topics_recorded(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The page's transforms fact says 'none on /tf_static' exactly where the recording holds no /tf_static
    message (it said 'on /tf, /tf_static' of every recording: the topics asked for). Of a recording the manifest
    finds no transform in (ros2_mcap_abitobot_no_tf, the Webots walker's ranges, ...), tfx report wrote nothing and
    exited 2 where tfx wtf gives its no_tf error and exits 1: it writes its page now, with what the recording holds
    (every topic, with its type) and wtf's no_tf finding, and exits as wtf does."""
    path = corpus(recording)
    page = tmp_path / "report.html"
    result = tfx("report", "-b", path, "-o", page)
    assert result.code in (0, 1), result.stderr
    text = html.unescape(page.read_text())
    (row,) = re.findall(r"<tr><th>Transforms</th><td>(.*?)</td></tr>", text, re.S)
    recorded = {topic.lstrip("/") for topic, _ in data.read_contents(path).messages}
    none = row.partition("none on ")[2].split(", ")  # "... ; none on /tf_static", or "none on /tf, /tf_static"
    assert ("/tf_static" in none) == ("tf_static" not in recorded), row
    if recording not in WITHOUT_TF:
        return
    assert result.code == recording.meta["expected"]["wtf_exit"] == 1, result.stderr
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    (no_tf,) = [f for f in bag["findings"] if f["code"] == "no_tf"]
    assert no_tf["message"] in text and no_tf["hint"] in text
    (held,) = re.findall(r"<tr><th>Holds</th><td>(.*?)</td></tr>", text, re.S)
    for topic in data.read_contents(path).topics:
        assert f"{topic} (" in held, (topic, held)  # each with its type
    assert "No transforms: no tree" in text and "<svg" not in text


@pytest.mark.parametrize("recording", WITHOUT_TF, ids=[r.id for r in WITHOUT_TF])
def test_every_command_says_how_to_record_tf_in_the_recordings_ros(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """'was /tf recorded?' came with no command, and a ROS 2 user needs ros2 bag record where a ROS 1 user
    needs rosbag record (ros2_mcap_abitobot_no_tf): wtf's no_tf hint and every other command's say the
    recording's, the same words."""
    path = corpus(recording)
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    (no_tf,) = [f for f in bag["findings"] if f["code"] == "no_tf"]
    if not no_tf["hint"].startswith("was /tf recorded?"):
        return  # its transforms are there, in a type tfx does not read: the hint says what to read instead
    record = "rosbag record" if recording.meta["format"] == "ros1" else "ros2 bag record"
    assert no_tf["hint"].startswith(f"was /tf recorded? record it with {record} /tf /tf_static"), no_tf["hint"]
    for command in ("frames", "monitor", "echo"):
        said = tfx(command, *(("a", "b") if command == "echo" else ()), "-b", path)
        # "message (hint)", or "message; hint" after a message that ends in parentheses (its data's frames)
        said_hint = " ".join(said.stderr.split()).removesuffix(")")
        assert said.code == 2 and said_hint.endswith(no_tf["hint"]), (command, said.stderr)


@pytest.mark.parametrize("recording", ["ros2-webots-epuck-resends-2025-db3", "ros2-coug-auv-replayed-2025-mcap"])
def test_a_copy_with_statics_opens_where_its_recording_opens(
    recording: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The Webots e-puck's .db3 (rosbag2 without definitions) holds webots_ros2_msgs/msg/StringStamped, a type no
    type store knows: ``tfx static -b -o`` gave it an empty definition with a hash of zeros, and rosbags' reader
    refused the whole copy ('hash mismatch'), as 39 of the corpus' 78 ROS 2 copies; the CougUV AUV's .mcap holds
    the definitions (its schemas) but no hashes, and its copies gave frost_interfaces/msg/DesiredHeading and the
    others a hash of zeros: refused too. The copies open, added and repaired, with every message there."""
    from mcap.reader import make_reader
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    source, added, repaired = corpus(BY_ID[recording]), tmp_path / "added", tmp_path / "repaired"
    result = tfx("static", "0.1", "0", "0.2", "0", "0", "0", "base_link", "zz_tag", "-b", source, "-o", added)
    assert result.code == 0, result.stderr
    # where nothing holds a definition (the e-puck's .db3, rosbag2 before Iron), one line says so
    undescribed = "webots_ros2_msgs/msg/StringStamped" if recording.startswith("ros2-webots") else None
    said = " ".join(result.stderr.split())
    assert ("the copy holds no definition of" in said) == bool(undescribed) and (undescribed or "") in said, said
    assert tfx("static", "--repair", "-b", source, "-o", repaired).code == 0
    with AnyReader([source], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as was:
        topics, count = {c.topic for c in was.connections}, sum(c.msgcount for c in was.connections)
        statics = sum(c.msgcount for c in was.connections if c.topic == "/tf_static")
    with AnyReader([added]) as now:
        assert {c.topic for c in now.connections} == topics
        assert sum(c.msgcount for c in now.connections) == count + 1
    with AnyReader([repaired]) as now:
        assert {c.topic for c in now.connections} == topics
        assert sum(c.msgcount for c in now.connections if c.topic != "/tf_static") == count - statics
    for mcap in (*added.glob("*.mcap"), *repaired.glob("*.mcap")):
        with mcap.open("rb") as f:
            assert sum(1 for _ in make_reader(f).iter_messages()) >= count


@pytest.mark.parametrize(
    "recording",
    ["ros2-webots-epuck-resends-2025-db3", "ros2-neato-real-lone-laser-beside-statics-20hz-allison-2022-db3"],
)
def test_a_copy_tells_its_publishers_apart_as_the_recording(
    recording: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The Webots e-puck's first /tf_static message and tfx's added one were recorded at one instant and read as one
    message: ``tfx wtf`` on ``tfx static ... -b -o``'s copy told a publisher of both, and another sending
    base_link -> base_footprint too (multiple_authorities), which the recording does not say; nor its repair. The
    real Neato's repair repeated the driver's lone laser before robot_state_publisher's 10 transforms (the latest
    of each, in the order of the latest), which read as one broadcaster adding transforms: dynamic_on_static where
    the recording gives static_conflict; it repeats the recording's sequence, 10, laser, 10."""
    source = corpus(BY_ID[recording])
    added, repaired = tmp_path / "added", tmp_path / "repaired"
    assert tfx("static", "0.1", "0", "0.2", "0", "0", "0", "base_link", "zz_tag", "-b", source, "-o", added).code == 0
    assert tfx("static", "--repair", "-b", source, "-o", repaired).code == 0
    was = {f["code"] for f in json.loads(tfx("wtf", "--format", "json", source).stdout)["bags"][0]["findings"]}
    for copy in (added, repaired):
        said = tfx("wtf", "--format", "json", copy)
        assert {f["code"] for f in json.loads(said.stdout)["bags"][0]["findings"]} == was, said.stdout


def test_the_repaired_create3_s_publishers_are_said_to_repeat_what_they_repeated(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The real Create 3's repair re-sends the merged static transforms every 5 s: read with rosbags, its
    /tf_static holds one message of 23 transforms (the second description's) and then messages of 35, which
    wtf tells to be the same publisher's; static_conflict said that publisher came "(the same 10 times)". It
    says how many more it sent and what they held; the recording itself sends each message once."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    source, repaired = corpus(BY_ID["ros2-create3-real-two-urdfs-2022-db3"]), tmp_path / "repaired"
    assert tfx("static", "--repair", "-b", source, "-o", repaired).code == 0
    with AnyReader([repaired], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        statics = [c for c in reader.connections if c.topic == "/tf_static"]
        sizes = [
            len(cast(Any, reader.deserialize(raw, c.msgtype)).transforms) for c, _, raw in reader.messages(statics)
        ]
    resent = sizes.count(35)
    assert sizes.count(23) == 1 and resent >= 2
    for bag, said in (
        (repaired, f"(+5.3 s) ({resent} more messages with up to 35 transforms), which"),
        (source, "(+5.3 s), which"),
    ):
        found = json.loads(tfx("wtf", "-b", bag, "-f", "json").stdout)["bags"][0]["findings"]
        (conflict,) = [f for f in found if f["code"] == "static_conflict"]
        assert f"publisher 2: 23 transforms at 1663967376.153 {said}" in conflict["message"], conflict["message"]


def test_filter_says_wtf_s_words_of_data_in_map(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """CyberShip Voyager's MCAP: mocap4r2's /markers and /voyager/rigid_bodies in 'map', the ship under 'world', no
    odom. wtf's sensor_frame hint says 'map' is not localization's here; `tfx filter` said "publish its frame's
    transform, or fix the frame_id". Both say it in the same words (``targets.world_frame_unpublished``)."""
    source = corpus(BY_ID["ros2-cybership-voyager-mocap-basin-2025-mcap"])
    found = json.loads(tfx("wtf", "--format", "json", source).stdout)["bags"][0]["findings"]
    (unknown,) = [f for f in found if f["code"] == "sensor_frame" and "'map'" in f["message"]]
    words = unknown["hint"].split(": every tf lookup")[0]
    assert "with no odom frame 'map' is not localization's (REP 105) here" in words, words
    said = " ".join(tfx("filter", "-b", source).stdout.split())
    assert said.count(f"no timeout can ({words})") == 2 and "fix the frame_id" not in said, said
