"""A publisher's rate read whole and replayed is one figure, on the clock its messages arrived on (issue 39), on
small recordings shaped as the corpus' Husky (a simulation recorded without /clock) and Franka (a message logged
at time 0)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from tests.bags import BagFormat, TfMessage, write_bag
from tests.cli.conftest import Tfx
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

MS_NS = 1_000_000


def _reports(tfx: Tfx, bag: Path) -> list[Any]:
    whole = tfx("monitor", "-b", bag, "-f", "json")
    played = tfx("monitor", "-b", bag, "--play", "--rate", "500", "--window", "100", "-f", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    return [json.loads(whole.stdout), json.loads(played.stdout.splitlines()[-1])]


@pytest.mark.parametrize("fmt", [BagFormat.rosbag2_sqlite3, BagFormat.ros1])
def test_a_simulation_recorded_without_clock_rates_its_publisher_on_the_record_clock(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat
) -> None:
    """Odometry every 50 ms of simulated time from 10 s, the simulation at 0.25x real time: received every 200 ms
    of the recorder's wall clock, no /clock. Whole, the publisher was 20 msgs/s (by stamp), replayed 5: both are
    the 5 a listener counts (``ros2 bag play`` plays on the record clock), the edge's stamps 20 Hz."""
    wall, sim = 1_700_000_000 * NS_PER_S, 10 * NS_PER_S
    odometry = [Transform((0.01 * k, 0, 0), (0, 0, 0, 1), sim + k * 50 * MS_NS, "odom", "base_link") for k in range(41)]
    messages = [TfMessage("/tf", wall + k * 200 * MS_NS, [odom], "/gazebo") for k, odom in enumerate(odometry)]
    for report in _reports(tfx, write_bag(tmp_path / "sim", messages, fmt)):
        (publisher,) = (a for a in report["authorities"])
        assert publisher["messages"] == 41
        assert publisher["rate_hz"] == pytest.approx(5.0, rel=1e-6)
        (edge,) = report["edges"]
        assert edge["rate_hz"] == pytest.approx(20.0, rel=1e-6)


def test_a_message_logged_at_time_zero_is_counted_not_timed_whole_or_replayed(tfx: Tfx, tmp_path: Path) -> None:
    """An MCAP's first /tf message logged at 0 and stamped 0, four more logged and stamped 0.5 s apart: the replay
    played the first with the next and counted 5 messages over 1.5 s (2.67 msgs/s); as the whole read, 5 messages,
    the 4 timed over 1.5 s: 2.0."""
    wall = 1_748_331_282 * NS_PER_S

    def sent(at: int) -> TfMessage:
        return TfMessage("/tf", at, [Transform((0, 0, 0), (0, 0, 0, 1), at, "world", "base")])

    messages = [sent(0), *(sent(wall + k * 500 * MS_NS) for k in range(4))]
    bag = write_bag(tmp_path / "zero", messages, BagFormat.rosbag2_mcap)
    for report in _reports(tfx, bag):
        (publisher,) = (a for a in report["authorities"] if a["authority"] == "/tf")
        assert (publisher["messages"], publisher["rate_hz"]) == (5, pytest.approx(2.0, rel=1e-6))


@pytest.mark.parametrize("fmt", [BagFormat.rosbag2_sqlite3, BagFormat.ros1])
def test_a_window_of_a_simulation_recorded_without_clock_holds_one_set_whole_or_replayed(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat
) -> None:
    """The 0.25x simulation above, --start +0.5 --end +1.1: seconds into the replay, as ``ros2 bag play`` plays it
    (the record clock moved onto the stamps, its start at the first stamp: ``Timeline.replay_shift``), which plays
    odometries 3 to 5 then (+0.6, +0.8, +1.0). The whole read selected the edge's samples by stamp (10 to 22: 13)
    beside its publisher's 3 messages counted on the replay's clock; one axis now (``Timeline.arrival``): 3 samples
    and 3 messages, whole and replayed. The replay's start was the frames' median offset (3 s) before: odometries 18
    to 20, 3.6 s into the recording."""
    wall, sim = 1_700_000_000 * NS_PER_S, 10 * NS_PER_S
    odometry = [Transform((0.01 * k, 0, 0), (0, 0, 0, 1), sim + k * 50 * MS_NS, "odom", "base_link") for k in range(41)]
    messages = [TfMessage("/tf", wall + k * 200 * MS_NS, [odom], "/gazebo") for k, odom in enumerate(odometry)]
    bag = write_bag(tmp_path / "sim", messages, fmt)
    window = ("--start", "+0.5", "--end", "+1.1")
    whole = tfx("monitor", "-b", bag, *window, "-f", "json")
    played = tfx("monitor", "-b", bag, *window, "--play", "--rate", "500", "--window", "100", "-f", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    for report in (json.loads(whole.stdout), json.loads(played.stdout.splitlines()[-1])):
        (edge,) = report["edges"]
        (publisher,) = report["authorities"]
        assert (edge["count"], edge["first_stamp"], edge["last_stamp"]) == (3, 10.15, 10.25), edge
        assert publisher["messages"] == 3, publisher
