"""A recording without tf says which frames its data needs (issue 39): the frames its stamped topics name, the
topics whose poses a broadcaster could have turned into tf, in wtf's text and JSON and in the report; said only
where no transform is recorded anywhere (a recording with /tf read with another --topic is told to read /tf)."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

AUV = "ros2-auv-real-sbg-dvl-ping-sensors-no-tf-humble-2026-db3"
CRAZYFLIE = "ros2-crazyflie-real-vicon-flight-no-tf-jazzy-2025-mcap"
WALKER = "ros2-webots-walker-ranges-no-tf-2025-db3"
AGV = "ros1-agv-two-lasers-mounts-on-tf-and-tf-static-replayed-2018-bag"


def _no_tf(tfx: Tfx, *args: str | Path) -> dict[str, Any]:  # noqa: F811
    result = tfx("wtf", *args, "--format", "json")
    assert result.code == 1, result.stderr
    (bag,) = json.loads(result.stdout)["bags"]
    (finding,) = [f for f in bag["findings"] if f["code"] == "no_tf"]
    assert isinstance(finding, dict)
    return finding


def test_the_auvs_range_frame_is_named_and_its_vendor_topics_said_untold(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The AUV's /ping1d/range is stamped in range_link; its DVL's and SBG's topics are of driver types tfx has no
    definition of (a Humble sqlite3 bag stores none): their frames are said not told, not left out unsaid."""
    path = corpus(BY_ID[AUV])
    finding = _no_tf(tfx, path)
    assert finding["frames"] == ["range_link"] and finding["figures"] == {"/ping1d/range": "range_link"}
    assert "its data is stamped in range_link (/ping1d/range)" in finding["message"]
    assert "the frames of /dvl/data, /dvl/position, /sbg/imu_data are not told" in finding["message"]
    assert "a tree for its data must hold range_link" in finding["hint"]
    text = " ".join(tfx("wtf", path).stdout.split())
    assert "its data is stamped in range_link (/ping1d/range)" in text
    # view-frames (as every command that stops for want of tf) reads the headers again on its error's path
    drawn = tfx("view-frames", "-b", path, "-o", tmp_path / "auv.pdf")
    line = " ".join(drawn.stderr.split())
    assert drawn.code == 2 and "; its data is stamped in range_link (/ping1d/range);" in line, drawn.stderr
    assert line.endswith(finding["hint"]), (line, finding["hint"])
    page = tmp_path / "auv.html"
    tfx("report", "-b", path, "-o", page)
    assert "a tree for its data must hold range_link" in html.unescape(re.sub(r"<[^>]+>", " ", page.read_text()))


def test_the_crazyflies_mocap_poses_are_named_as_what_could_carry_its_tf(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The drone flies by a PoseStamped in vicon/world: a node broadcasting it as tf is what is missing."""
    finding = _no_tf(tfx, corpus(BY_ID[CRAZYFLIE]))
    pose = "/vicon/Group466CF/Group466CF/pose"
    assert finding["frames"] == ["vicon/world"] and finding["figures"] == {pose: "vicon/world"}
    assert f"its data is stamped in vicon/world (poses on {pose})" in finding["message"]
    assert f"the poses on {pose} as geometry_msgs/msg/PoseStamped become tf only through a node" in finding["hint"]
    assert "must hold" not in finding["hint"]  # a frame poses are given in is not a mount


def test_a_non_tf_topic_asked_for_names_the_frames_too(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """--topic /left_sensor (a Range) on the walker: not a transform type, and the frames of both ranges."""
    finding = _no_tf(tfx, corpus(BY_ID[WALKER]), "--topic", "/left_sensor")
    assert "/left_sensor: sensor_msgs/msg/Range (cdr) is not a transform message" in finding["message"]
    assert "its data is stamped in ds0 (/left_sensor), ds1 (/right_sensor)" in finding["message"]
    assert finding["frames"] == ["ds0", "ds1"]


def test_a_recording_with_tf_read_on_another_topic_is_told_to_read_tf_only(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The AGV's bag has /tf and /tf_static: --topic /scan is told to leave out --topic, no frames its data needs."""
    finding = _no_tf(tfx, corpus(BY_ID[AGV]), "--topic", "/scan")
    assert finding["hint"] == "/tf and /tf_static carry transforms: leave out --topic"
    assert "stamped in" not in finding["message"] and finding["frames"] == [] and finding["figures"] == {}


@pytest.mark.parametrize("name", [AUV, CRAZYFLIE, WALKER])
def test_every_other_command_names_the_data_frames_from_a_few_headers_per_topic(
    corpus: Corpus, monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    """Commands other than wtf read the headers again on their error's path (``no_transforms_data``): the first
    ``DATA_HEADERS`` of each topic, not every one (the AUV's /ping1d/range has 1,976, the Crazyflie's poses 754),
    and say what every header says (wtf's ``no_tf``)."""
    from tftools.analysis import reading
    from tftools.analysis.data_frames import data_frames
    from tftools.analysis.no_transforms import DATA_HEADERS, no_transforms_data
    from tftools.sources.errors import NoTransformsError
    from tftools.sources.recording import Recording as Read
    from tftools.sources.recording import read_recording

    path = corpus(BY_ID[name])
    with pytest.raises(NoTransformsError) as raised:
        read_recording([path])
    every = read_recording([path], headers=(), allow_empty=True)
    others = {t: kind for f in every.contents.files for t, kind in f.topics.items() if t not in every.contents.topics}
    read_again: list[Read] = []

    def kept(*args: Any, **kwargs: Any) -> Read:
        read_again.append(read_recording(*args, **kwargs))
        return read_again[-1]

    monkeypatch.setattr(reading, "read_recording", kept)
    assert no_transforms_data(raised.value) == data_frames(every.stamped.streams, others)
    (again,) = read_again
    assert [s.topic for s in again.stamped.streams] == [s.topic for s in every.stamped.streams]
    assert max(len(s) for s in again.stamped.streams) == DATA_HEADERS < max(len(s) for s in every.stamped.streams)
