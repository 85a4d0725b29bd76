"""Defects issue 39's corpus helpers left, each on the real recording that showed it (designed reproductions:
tests/sources/test_timeline.py, tests/analysis/test_causes.py, tests/analysis/test_wtf_clocks_and_words.py,
tests/analysis/test_jumps_back.py): a device's delays on the record clock beside a simulation on a coarse
/clock, two wheels one re-parenting, the clock hint where the trees are apart, and a ROS 1 frame kept static."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

DIFF_CONT = "ros2-ias0220-gazebo-diff-drive-beside-imu-device-2025-db3"
NO_CLOCK = "ros2-ias0220-gazebo-diff-drive-no-clock-2025-db3"
AGV = "ros1-agv-two-lasers-mounts-on-tf-and-tf-static-replayed-2018-bag"
COBOT = "ros2-logistic-cobot-pymoveit2-no-record-clock-2024-db3"
DEVICE = ("imu_link", "ultrasound_distance_sensor")


@pytest.mark.parametrize("recording_id", [DIFF_CONT, NO_CLOCK])
def test_the_devices_wall_clock_delays_are_measured_with_or_without_clock(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The device's samples are recorded 0.1-1 ms after their wall-clock stamps: monitor and report say so whether
    or not a /clock (ticking every 100 ms, the simulated robot's) was recorded beside them; the robot's delays
    stay unavailable under that /clock."""
    path = corpus(BY_ID[recording_id])
    report = json.loads(tfx("monitor", *DEVICE, "-b", path, "--format", "json").stdout)
    by_child = {e["child"]: e for e in report["edges"]}
    device = by_child[DEVICE[1]]
    assert 0.0 < device["delay_mean_s"] < 0.001 and 0.0 < device["delay_max_s"] <= 0.001, device
    assert report["chain"]["net_delay_mean_s"] is not None and report["chain"]["net_delay_max_s"] < 0.51, report[
        "chain"
    ]
    if recording_id == DIFF_CONT:
        assert by_child["base_footprint"]["delay_mean_s"] is None
        assert (
            "those of ultrasound_distance_sensor (stamped on the record clock) are measured"
            in report["delays_unavailable"]
        )


def test_a_replay_shows_the_devices_delays_as_the_whole_recording_does(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """--play moves record times onto /clock, whose 0.1 s ticks cannot time the device: its delays were
    "unavailable" in the replay while the whole-recording monitor measured them (0.3 ms mean). Over a window
    holding all of it, the replay's last table shows the whole recording's figures, the chain's too."""
    path = corpus(BY_ID[DIFF_CONT])
    whole = json.loads(tfx("monitor", *DEVICE, "-b", path, "--format", "json").stdout)
    replayed = tfx("monitor", *DEVICE, "-b", path, "--play", "--rate", "50", "--window", "100", "--format", "json")
    last = json.loads(replayed.stdout.splitlines()[-1])
    (device,) = [e for e in last["edges"] if e["child"] == DEVICE[1]]
    (measured,) = [e for e in whole["edges"] if e["child"] == DEVICE[1]]
    figures = ("count", "delay_mean_s", "delay_max_s")
    assert [device[k] for k in figures] == [measured[k] for k in figures] and 0 < device["delay_mean_s"] < 0.001
    assert last["chain"]["net_delay_mean_s"] == whole["chain"]["net_delay_mean_s"] is not None, last["chain"]


def test_a_window_counts_on_the_clock_of_the_frames_asked_about(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """--start/--end with the device's chain count on its own wall-clock stamps (+10 to +20 s after its first,
    1761904738.875: 93 of its samples, as the bytes hold); without frames, on the simulation's tf span, each edge
    windowed by when its transforms arrived on /clock (the device's: 88 arrived in +10 to +20 s of /clock)."""
    path = corpus(BY_ID[DIFF_CONT])
    window = ("--start", "+10", "--end", "+20", "--format", "json")
    chain = json.loads(tfx("monitor", *DEVICE, "-b", path, *window).stdout)
    every = json.loads(tfx("monitor", "-b", path, *window).stdout)
    assert [e["count"] for e in chain["edges"] if e["child"] == DEVICE[1]] == [93], chain["edges"]
    assert [e["count"] for e in every["edges"] if e["child"] == DEVICE[1]] == [88], every["edges"]
    echoed = tfx("echo", *DEVICE, "-b", path, "--start", "+10", "--end", "+11").stdout
    assert echoed.startswith("At time 1761904748.875"), echoed[:80]


def test_the_report_draws_the_devices_delay(corpus: Corpus, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    page = tmp_path / "diff_cont.html"
    tfx("report", corpus(BY_ID[DIFF_CONT]), "-o", page)
    text = page.read_text()
    (about,) = re.findall(r"ultrasound_distance_sensor</b><small>([^<]*)", text)
    assert re.search(r"delay 0\.\d ms \(max [01]\.\d\)", about), about


def test_the_two_wheels_are_one_re_parenting_and_the_clock_hint_says_the_trees_are_apart(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """gazebo_ros' diff_drive plugin publishes both wheels under base_footprint (base_link in the URDF): one
    finding naming both, neither explaining the other. The device's tree on the wall clock is apart from the
    robot's on /clock: no lookup combines them, and the clock hint says so instead of lookups failing."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[DIFF_CONT]), "--format", "json").stdout)["bags"]
    (parent,) = [f for f in bag["findings"] if f["code"] == "urdf_parent"]
    assert set(parent["frames"]) == {"base_footprint", "left_wheel", "right_wheel", "base_link"}, parent
    assert "left_wheel" in parent["message"] and "right_wheel" in parent["message"]
    assert (parent["key"], parent["cause"]) == ("", ""), parent  # explains nothing, follows from nothing
    (clock,) = [f for f in bag["findings"] if f["code"] == "clock" and f["severity"] == "error"]
    assert "lookups within each tree work" in clock["hint"] and "fail with extrapolation" not in clock["hint"]
    # a device stamping wall-clock time beside the simulation on purpose: said as observed, not "use_sim_time"
    assert "arriving 0.3 ms after their stamps by the record clock" in clock["message"], clock["message"]
    assert "a tree of their own: a device on the wall clock beside the simulation" in clock["message"]
    assert "set use_sim_time true for it too" not in clock["hint"] and "put both on one clock" in clock["hint"]


def test_the_simulation_without_its_clock_is_not_said_to_count_from_boot(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The no-/clock sibling: the device's stamps keep time with the record clock, so they are the reference, and
    the simulated robot (1418.3-1499.9 s) was said to be on "a clock counting from boot" and told it "runs with
    use_sim_time while nothing publishes /clock" (then it would stamp 0, not 82 s of advancing time). The bytes
    hold no /clock and nothing else that tells a simulation's time from a clock since boot: wtf, the report's
    page and view-frames' legend say so, and what to do for each (record /clock; stamp with the node's clock)."""
    path = corpus(BY_ID[NO_CLOCK])
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    (clock,) = [f for f in bag["findings"] if f["code"] == "clock"]
    assert clock["frames"][:2] == ["odom", "base_footprint"], clock
    said = "on a clock counting from zero (a simulation's time or time since boot: no /clock was recorded to tell"
    assert said in clock["message"] and "1459.1 s" in clock["message"], clock["message"]
    assert "which ultrasound_distance_sensor follows" in clock["message"], clock["message"]
    assert "record /clock with them (ros2 bag record /clock ...)" in clock["hint"], clock["hint"]
    assert "nothing publishes /clock" not in clock["hint"] and "lookups within each tree work" in clock["hint"]
    page = tmp_path / "report.html"
    tfx("report", "-b", path, "-o", page)
    assert "counting from boot" not in page.read_text() and said.replace("'", "&#x27;") in page.read_text()


def test_a_ros1_frame_kept_static_has_no_order_to_its_stamps(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """front_laser_link came first on /tf_static: ROS 1's tf2 keeps it static and each /tf sample replaces its
    value for every time, so its one stamp 0.1 s back changes no lookup (no TF_OLD_DATA either). The depth
    camera's optical frame, a dynamic frame, keeps its warning."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[AGV]), "--format", "json").stdout)["bags"]
    backwards = [f for f in bag["findings"] if f["code"] == "time_backwards"]
    assert [f["frames"][1] for f in backwards] == ["camera_floor_depth_optical_frame"], backwards


def test_monitor_of_the_simulated_chain_says_its_own_span_and_why_it_has_no_delay(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``monitor odom base_footprint`` headed its table with the device's wall-clock span ("78.305 s from
    1761903969.970") though odom -> base_footprint is stamped 1418.277-1499.945 s (no /clock recorded), and showed
    "-" for its delays with no word why: arrival (the record clock) minus a stamp on another clock is no delay.
    Whole and replayed, text and JSON, it says so now; the device's delays stay measured."""
    path = corpus(BY_ID[NO_CLOCK])
    text = tfx("monitor", "odom", "base_footprint", "-b", path).stdout
    header = text.splitlines()[0]
    assert header.endswith(
        ": odom to base_footprint on a clock of its own, its tf stamped over 81.668 s from 1418.277 to 1499.945"
    )
    why = (
        "those of base_footprint cannot be measured: stamped on another clock than the record clock, which timed "
        "their arrival"
    )
    assert f"delays: {why}" in text and "not measurable: another clock" in text, text
    whole = json.loads(tfx("monitor", "odom", "base_footprint", "-b", path, "--format", "json").stdout)
    replayed = tfx("monitor", "odom", "base_footprint", "-b", path, "--play", "--rate", "50", "--format", "json")
    last = json.loads(replayed.stdout.splitlines()[-1])
    for report in (whole, last):
        assert report["delays_other_clock"].startswith(why) and report["delays_unavailable"] is None, report
        (edge,) = report["chain"]["edges"]
        assert edge["delay_mean_s"] is None and edge["delay_unmeasurable"] == "not measurable: another clock", edge
    played = tfx("monitor", "odom", "base_footprint", "-b", path, "--play", "--rate", "50").stdout
    last = played[played.rindex("time ") :].splitlines()
    assert last[1] == "odom to base_footprint stamped up to 1499.945, on a clock of its own", last[:3]
    assert f"delays: {why}" in last[2], last[:3]
    windowed = tfx("monitor", "odom", "base_footprint", "-b", path, "--start", "+10", "--end", "+20").stdout
    assert windowed.splitlines()[0].endswith(
        "on a clock of its own, its tf stamped over 10.000 s from 1428.277 to 1438.277"
    )
    device = json.loads(tfx("monitor", *DEVICE, "-b", path, "--format", "json").stdout)
    assert device["delays_other_clock"] is None and device["chain"]["edges"][0]["delay_unmeasurable"] is None


def test_detections_on_one_clock_without_a_record_clock_are_aged_from_one_end(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The coBot's obj_6 (6 sightings, the last at 1731467426.909) and obj_12 (newest 1731467426.680), both on
    epoch time, were each aged from its own clock group's newest stamp: both '0.000 s old'. One clock, one end."""
    dot = tfx("view-frames", "-b", corpus(BY_ID[COBOT]), "--format", "dot", "-o", "-").stdout
    labels = dict(re.findall(r"\t(base_link -> obj_\d+) \[label=<(.*?)> ", dot))
    assert "1731467426.909 (0.000 s old)" in labels["base_link -> obj_6"], labels["base_link -> obj_6"]
    assert "1731467426.680 (0.230 s old)" in labels["base_link -> obj_12"], labels["base_link -> obj_12"]
    assert "1731467414.092 (12.817 s old)" in labels["base_link -> obj_2"], labels["base_link -> obj_2"]


def test_plus_s_counts_on_the_clock_view_frames_ages_detections_on(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The coBot's obj_6, seen only from 1731467419.682 s, is on the detections' clock (wtf's one "epoch time"
    group, view-frames' one end) but ``+S`` of its chain counted from its own first stamp: ``echo base_link obj_6
    --at +1`` answered at 1731467420.682, obj_12's at 1731467402.668, one "+1" 18 s apart on one clock. Now both
    count from the detections' first stamp: obj_6 was not seen yet, said as tf2 says it, with where it was."""
    path = corpus(BY_ID[COBOT])
    seen = tfx("echo", "base_link", "obj_12", "-b", path, "--at", "+1")
    assert seen.code == 0 and seen.stdout.startswith("At time 1731467402.668\n"), seen.stdout[:200]
    unseen = tfx("echo", "base_link", "obj_6", "-b", path, "--at", "+1")
    assert unseen.code != 0 and "Lookup would require extrapolation into the past" in unseen.stdout + unseen.stderr
    assert "--at +18.014 to +25.241 look it up there" in unseen.stdout + unseen.stderr
    later = tfx("echo", "base_link", "obj_6", "-b", path, "--at", "+18.1")
    assert later.code == 0 and later.stdout.startswith("At time 1731467419.768"), later.stdout[:200]
    header = tfx("monitor", "base_link", "obj_6", "-b", path).stdout.splitlines()[0]
    assert header.endswith(
        ": base_link to obj_6 on a clock of its own, its tf stamped over 25.241 s from 1731467401.668 to 1731467426.909"
    )


def test_two_time_bases_without_a_record_clock_are_said_as_seen(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The coBot's record times are 0-74 ns (a script's writer): no clock. Its box detections are stamped on epoch
    time (1731467401-1731467427 s), the arm and the eBot from zero (46-74 s), in trees apart. The finding said
    "two clocks in one tree" and told the detector to "set use_sim_time true for it too": the bytes hold two time
    bases and nothing telling which clock each publisher keeps. Said so, with how to tell them apart."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[COBOT]), "--format", "json").stdout)["bags"]
    (clock,) = [f for f in bag["findings"] if f["code"] == "clock" and f["severity"] == "error"]
    assert set(clock["frames"]) == {"base_link", "obj_2", "obj_3", "obj_6", "obj_12"}, clock
    assert "stamped around 1731467408.0 s (epoch time) while" in clock["message"], clock["message"]
    assert "are stamped around 53.2 s (counting from zero): two time bases" in clock["message"], clock["message"]
    assert "no record clock to tell which clock each keeps" in clock["message"] and "one tree" not in clock["message"]
    assert "set use_sim_time true for it too" not in clock["hint"], clock["hint"]
    assert "record with ros2 bag record, which stores when each message arrived, and /clock" in clock["hint"]
    assert "lookups within each tree work" in clock["hint"], clock["hint"]
