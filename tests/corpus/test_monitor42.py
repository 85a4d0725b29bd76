"""``tfx monitor``'s figures read against the bytes (issue 39, monitor42): a publisher's delay is of every
transform it sent, as its message count is, not of the ones tf2 stored alone."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from tests.bags import TfMessage, write_bag
from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

#: Gazebo's drone pose from /gazebo_connect at 1 kHz on 1 ms sim ticks: 2810 /tf messages (world -> drone/base_link
#: and world -> base_link, 1405 each) of 287 stamps each; tf2 stores the first of a stamp (574), refuses the others.
DRONE = "ros1-gazebo-drone-hover-pose-at-1-khz-on-sim-ticks-repeated-stamps-pfms-quiz5-2023-bag"


def _monitor(tfx: Tfx, path: Path) -> Any:  # noqa: F811
    result = tfx("monitor", "-b", path, "--format", "json")
    assert result.stdout.strip(), result.stderr
    return json.loads(result.stdout)


def _publisher(report: Any, name: str) -> Any:
    (found,) = [a for a in report["authorities"] if a["authority"] == name]
    return found


def test_a_publisher_s_delay_times_its_re_sent_transforms(tmp_path: Path, tfx: Tfx) -> None:  # noqa: F811
    """Ten stamps 0.1 s apart, each sent 1 ms after it and again 9 ms after it: ROS 1's tf2 stores the first of
    each (the edge's 10 samples, 1 ms late), the publisher sent 20 messages, 5 ms late on average (tf_monitor's
    "Node:" line times every one it hears); it said 1 ms, the stored ones' alone."""
    ms = NS_PER_S // 1000
    messages = []
    for i in range(10):
        stamp = 1_700_000_000 * NS_PER_S + i * 100 * ms
        sample = Transform((float(i), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "world", "drone")
        messages += [
            TfMessage("/tf", stamp + ms, [sample], "/pose"),
            TfMessage("/tf", stamp + 9 * ms, [sample], "/pose"),
        ]
    report = _monitor(tfx, write_bag(tmp_path / "resent.bag", messages))
    (edge,) = report["edges"]
    assert edge["count"] == 10
    assert edge["delay_mean_s"] == pytest.approx(0.001) and edge["delay_max_s"] == pytest.approx(0.001)
    publisher = _publisher(report, "/pose")
    assert publisher["messages"] == 20
    assert publisher["delay_mean_s"] == pytest.approx(0.005)
    assert publisher["delay_max_s"] == pytest.approx(0.009)


def test_gazebo_s_re_sent_drone_pose_is_timed_whole(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The real drone bag: /gazebo_connect's 2810 messages were 1.460 ms late on average (every transform's record
    time minus stamp, read off its 1 ms record clock: rosbags over the bytes gives 0.00146014), 26 ms at most;
    monitor said 1.1 ms, the 574 tf2 stored. The same replayed (``--play``); its edges keep their stored samples'
    figures."""
    report = _monitor(tfx, corpus(BY_ID[DRONE]))
    gazebo = _publisher(report, "/gazebo_connect")
    assert gazebo["messages"] == 2810
    assert gazebo["delay_mean_s"] == pytest.approx(0.0014601423, abs=1e-9)
    assert gazebo["delay_max_s"] == pytest.approx(0.026)
    edges = {e["child"]: e for e in report["edges"] if not e["static"]}
    assert {child: e["count"] for child, e in edges.items()} == {"drone/base_link": 287, "base_link": 287}
    assert all(e["delay_mean_s"] < 0.0012 for e in edges.values())
    played = tfx("monitor", "-b", corpus(BY_ID[DRONE]), "--play", "--rate", "10", "--format", "json").stdout
    replayed = _publisher(json.loads(played.strip().splitlines()[-1]), "/gazebo_connect")  # its last table: all of it
    assert (replayed["messages"], replayed["delay_mean_s"]) == (2810, gazebo["delay_mean_s"])
    text = tfx("monitor", "-b", corpus(BY_ID[DRONE])).stdout
    (row,) = [line for line in text.splitlines() if "/gazebo_connect " in line and "2810" in line]
    assert row.split()[1:5] == ["2810", "2020.86", "0.0015", "0.0260"]


#: Webots' e-puck (ROS 2, .db3): /tf from the diff-drive controller and the robot's own state publisher, /tf_static.
EPUCK = "ros2-webots-epuck-resends-2025-db3"


def test_a_ros2_bag_s_topics_are_not_shown_as_nodes(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The e-puck's rosbag2 names no publisher (its metadata.yaml gives topics and QoS only): monitor's "Node"
    column held /tf and /tf_static, read by a ROS 2 user as node names (monitor42's note). They are said as topics,
    with why, and the JSON says ``publishers_named: false``."""
    report = _monitor(tfx, corpus(BY_ID[EPUCK]))
    assert report["publishers_named"] is False
    assert {a["authority"] for a in report["authorities"]} == {"/tf", "/tf_static"}
    text = tfx("monitor", "-b", corpus(BY_ID[EPUCK])).stdout
    assert "The recording names no publisher (a ROS 2 bag records none" in " ".join(text.split())
    assert "Topic" in text and "Node" not in text
    assert _monitor(tfx, corpus(BY_ID[DRONE]))["publishers_named"] is True
