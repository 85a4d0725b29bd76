"""Figures derived from times (delays, spans, durations, +S, rhythms of arrival) on one timeline with one
origin: plausible, or unavailable with the reason. Real recordings where the corpus has one, else written."""

from __future__ import annotations

import dataclasses
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from tests.bags import BagFormat, ClockMessage, TfMessage, write_bag
from tests.cli.conftest import Tfx
from tests.corpus.fetch import shared_dir
from tftools.analysis.edges import TimeWindow
from tftools.analysis.frames import frame_tree
from tftools.analysis.monitor import MonitorQuery, MonitorReport, monitor, monitor_buffer, monitor_stream, played_window
from tftools.analysis.report import recording_facts
from tftools.analysis.report import report as recording_report
from tftools.analysis.report.poses import frame_poses
from tftools.analysis.times import Offset
from tftools.analysis.wtf.fleet import check
from tftools.core.batch import BatchBuilder, take_rows
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.graph import recording_legend
from tftools.render.report import recording_section
from tftools.render.scene3d import scene_html
from tftools.sources.contents import RecordingContents, SourceInfo, StampedMessages, StampedRead
from tftools.sources.recording import read_recording, recording_of
from tftools.sources.stream import stream_recording
from tftools.sources.timeline import record_grid

S = NS_PER_S
MS = NS_PER_S // 1000
WALL = 1_695_944_000 * S  # a wall-clock time (September 2023)


def corpus(name: str) -> Path:
    path = shared_dir() / "corpus" / name
    if not path.exists():
        pytest.skip(f"corpus recording {name} is not placed in {path.parent}")
    return path


def moving(parent: str, child: str, stamp: int, x: float = 0.0) -> Transform:
    return Transform((x, 0, 0), (0, 0, 0, 1), stamp, parent, child)


# --- delays on a /clock that ticks coarsely ------------------------------------------------------------


def gazebo(tmp_path: Path, clock_hz: float) -> Path:
    """A simulation recorded on wall time: /clock at ``clock_hz`` (sim time from 100 s), odom -> base at
    30 Hz stamped with the simulation's own time, received 2 ms after (all on the record clock)."""
    period = round(S / clock_hz)
    clock = [ClockMessage(WALL + k * period + MS // 2, 100 * S + k * period) for k in range(round(10 * clock_hz))]
    tf = [
        TfMessage("/tf", WALL + i * S // 30 + 2 * MS, [moving("odom", "base", 100 * S + i * S // 30, i)])
        for i in range(300)
    ]
    return write_bag(tmp_path / f"gazebo_{clock_hz:g}hz", tf, BagFormat.rosbag2_sqlite3, clock)


def test_a_10_hz_clock_gives_no_delay_but_says_why(tmp_path: Path, tfx: Tfx) -> None:
    """Arrivals mapped to the last /clock tick before them lag by up to 100 ms: mean delays of -0.05 s
    were shown. Now none, and the reason, in text and JSON."""
    bag = gazebo(tmp_path, 10)
    recording = read_recording([bag])
    report = monitor_buffer(recording.buffer, window=TimeWindow(timeline=recording.timeline))
    (base,) = [e for e in report.edges if e.child == "base"]
    assert math.isnan(base.delay_mean) and math.isnan(base.delay_max)
    assert "ticks every 0.100 s of sim time (10.0 Hz of record time)" in report.delays_unavailable
    shown = json.loads(tfx("monitor", "-b", bag, "-f", "json").stdout)
    assert shown["edges"][0]["delay_mean_s"] is None and shown["authorities"][0]["delay_max_s"] is None
    assert "/clock, which ticks every 0.100 s" in shown["delays_unavailable"]
    text = tfx("monitor", "-b", bag).stdout
    assert "delays unavailable: ROS time at arrival is read off /clock, which ticks every 0.100 s" in text
    played = [
        json.loads(line)
        for line in tfx("monitor", "-b", bag, "--play", "--rate", "50", "-f", "json").stdout.splitlines()
    ]
    assert played and all(e["delay_mean_s"] is None for r in played for e in r["edges"])  # a replay too
    codes = {f.code for f in check(recording).findings}
    assert not codes & {"delay", "future"}


def test_a_clock_slower_than_real_time_says_its_step_and_its_rate_on_their_own_axes(tmp_path: Path) -> None:
    """Gazebo below real time (the TurtleBot 3 circle MCAP: /clock steps 0.095 s of sim time, 9.8 times a second of
    wall time): "ticks every 0.095 s (11 Hz)" read the step as a rate. Here 0.05 s of sim time at 10 Hz."""
    clock = [ClockMessage(WALL + k * S // 10 + MS // 2, 100 * S + k * S // 20) for k in range(100)]
    tf = [
        TfMessage("/tf", WALL + i * S // 10 + 2 * MS, [moving("odom", "base", 100 * S + i * S // 20, i)])
        for i in range(100)
    ]
    recording = read_recording([write_bag(tmp_path / "slow", tf, BagFormat.rosbag2_sqlite3, clock)])
    said = recording.timeline.delays_unavailable
    assert "/clock, which ticks every 0.050 s of sim time (10.0 Hz of record time)" in said, said


def test_a_fine_clock_measures_delays_never_below_zero(tmp_path: Path) -> None:
    """/clock at 1 kHz: the 2 ms delays are measured; a reading a tick behind the stamp is no negative delay."""
    recording = read_recording([gazebo(tmp_path, 1000)])
    report = monitor_buffer(recording.buffer, window=TimeWindow(timeline=recording.timeline))
    (base,) = [e for e in report.edges if e.child == "base"]
    assert report.delays_unavailable == ""
    assert 0.001 <= seconds(base.delay_mean) <= 0.0025 and seconds(base.delay_max) <= 0.003
    history = recording.buffer.history("base")
    assert history is not None
    delays = recording.timeline.delays("base", history.stamps, history.record_times, history.flags)
    assert len(delays) == 300 and delays.min() >= 0
    chain = monitor_buffer(recording.buffer, "odom", "base", TimeWindow(timeline=recording.timeline)).chain
    assert chain is not None and 0 <= seconds(chain.delay_mean) <= seconds(chain.delay_max) < 0.04


def test_the_gazebo_corpus_recording_shows_no_impossible_delay(tfx: Tfx) -> None:
    """The TurtleBot 3 in Gazebo (ros2_walker): /clock at 10 Hz, received on wall time."""
    bag = corpus("ros2_db3_tb3_gazebo_walker")
    shown = json.loads(tfx("monitor", "-b", bag, "-f", "json").stdout)
    figures = [e[k] for e in shown["edges"] + shown["authorities"] for k in ("delay_mean_s", "delay_max_s")]
    assert figures and all(f is None for f in figures)
    assert "ticks every 0.100 s of sim time (9.7 Hz of record time)" in shown["delays_unavailable"]
    wtf = tfx("wtf", bag)
    assert wtf.code == 0 and "delays shorter than that cannot be measured" in wtf.stdout
    assert not re.search(r"\b(delay|future)\b:", wtf.stdout)


# --- spans: one clock, plausible --------------------------------------------------------------------


def two_clocks(tmp_path: Path, root: str | None = None) -> Path:
    """On a topic named ``tf``: an arm stamped on simulated time (from 1900 s) and detections stamped on
    wall time, all received on wall time, for 20 s; in two trees, or both under ``root`` (the real UR5's)."""
    messages = []
    for i in range(200):
        record = WALL + i * S // 10
        arm = moving(root or "arm_base", "arm_link", 1900 * S + i * S // 10, i)
        seen = moving(root or "camera", "object", record - 5 * MS, i)
        messages.append(TfMessage("tf", record, [arm, seen]))
    return write_bag(tmp_path / "two_clocks.bag", messages)


def test_a_span_over_two_clocks_is_the_reference_clocks(tmp_path: Path, tfx: Tfx) -> None:
    """'1695944406.454 s from 1907.175 to 1695946313.629': a span from the simulated stamps to the wall ones."""
    bag = two_clocks(tmp_path)
    recording = read_recording([bag], topics=["tf"])
    timeline = recording.timeline
    assert timeline.off_reference == {"arm_link"}
    assert (timeline.tf_start, timeline.tf_end) == (WALL - 5 * MS, WALL + 199 * S // 10 - 5 * MS)
    header = tfx("monitor", "-b", bag, "--topic", "tf").stdout.splitlines()[0]
    assert header.endswith(
        f": tf stamped over 19.900 s from {(WALL - 5 * MS) / S:.3f} to {(WALL + 19895 * MS) / S:.3f}"
    )
    facts = dict(recording_facts(recording))
    assert "(19.900 s)" in facts["tf stamps"]
    at = tfx("echo", "arm_base", "arm_link", "-b", bag, "--topic", "tf", "--at", "1905")  # its own clock's times
    assert at.code == 0 and at.stdout.startswith("At time 1905.000\n- Translation: [50.000,")
    (clock,) = [f for f in check(recording).findings if f.code == "clock"]  # the arm is still told of
    assert "arm_base -> arm_link" in clock.message and "stamped around 1910.0 s" in clock.message
    assert not re.search(r"[+-]\d{6,}\.\d s", "\n".join(f.message for f in check(recording).findings))


def test_the_report_s_facts_name_the_frames_on_another_clock_and_their_span(tmp_path: Path) -> None:
    """The real UR5 (two clocks): the page said 'tf stamps on the record clock' and a span of the detections
    only, while its findings said the arm's 6 edges are on another clock; the facts now name them, with their
    stamps' span on their own clock."""
    bag = two_clocks(tmp_path)
    clocks = dict(recording_facts(read_recording([bag], topics=["tf"])))["Clocks"]
    assert clocks.startswith("tf stamps on the record clock; but arm_link is stamped on another clock")
    assert f"{1900:.3f} to {1900 + 19.9:.3f} (not in the tf stamps' span)" in clocks
    # The transforms on the topic the file names, and none on /tf_static (it said 'on /tf, /tf_static').
    assert dict(recording_facts(read_recording([bag])))["Transforms"] == (
        "400 in 200 messages on tf; none on /tf_static"
    )


def test_view_frames_says_why_ages_count_from_the_newest_stamp_once(tmp_path: Path) -> None:
    """A simulation recorded without /clock (the Nav2 TurtleBot 4 MCAP): the legend gave the clock finding's
    whole sentence as the reason ages count from the newest stamp, then listed that finding again."""
    messages = [
        TfMessage("/tf", WALL + i * S // 10, [moving("odom", "base_link", 100 * S + i * S // 10, i)]) for i in range(50)
    ]
    recording = read_recording([write_bag(tmp_path / "sim_no_clock.bag", messages)])
    (clock,) = [f for f in check(recording).findings if f.code == "clock"]
    (ages,) = [line for line in recording_legend(recording) if line.startswith("Ages")]
    assert ages == "Ages from the newest tf stamp (104.900): the recording does not tell ROS time at its end"
    assert recording.timeline.reason not in ages and "no /clock was recorded" in clock.message


def test_the_report_s_3d_view_places_an_arm_on_its_own_clock(tmp_path: Path) -> None:
    """The real UR5: base_link's arm on simulated time (1907-1914 s), its detections on wall time. The 3D view
    looked every frame up at wall times: the arm was never placed, and nothing said so. Now at the same times
    into its own stamps (as echo's +S counts), and the page says which frames are placed so."""
    recording = read_recording([two_clocks(tmp_path, root="base_link")])
    timeline = recording.timeline
    poses = frame_poses(recording.buffer, frame_tree(recording), timeline.tf_start, timeline.tf_end, timeline=timeline)
    assert poses is not None and poses.fixed == "base_link" and poses.own_clock == ("arm_link",)
    arm, seen = poses.frames.index("arm_link"), poses.frames.index("object")
    assert poses.valid[arm].all() and poses.valid[seen].all()
    # 5 s into the detections is 5 s into the arm's stamps: x = 50 there (``moving`` puts x at i).
    k = int(np.argmin(np.abs(poses.times - (timeline.tf_start + 5 * S))))
    into = (int(poses.times[k]) - timeline.tf_start) / S
    assert poses.translations[arm, k, 0] == pytest.approx(10 * into, abs=1e-6)
    assert "placed as far into their own stamps as the slider is into the recording's: arm_link." in scene_html(poses)
    # The report's view spans the tf data: at its last time too every frame is placed (its end was past the data).
    drawn = recording_report(recording).poses
    assert drawn is not None and drawn.valid[1:].all() and drawn.times[-1] == timeline.tf_end


def test_monitor_start_counts_on_the_clock_of_the_chain_asked_about(tmp_path: Path, tfx: Tfx) -> None:
    """Issue 39: ``tfx monitor`` counted ``+S`` on the record clock's tf (the detections') while ``tfx echo --at``
    counted it on the chain's own: an arm on simulated time recorded from 3 s before the first detection was
    monitored from 1904 s for ``--start +1``. Now from 1901 s, a second into its own stamps."""
    messages = []
    for i in range(200):
        record = WALL + i * S // 10
        transforms = [moving("arm_base", "arm_link", 1900 * S + i * S // 10, i)]
        if i >= 30:  # the detections begin 3 s into the recording
            transforms.append(moving("camera", "object", record - 5 * MS, i))
        messages.append(TfMessage("tf", record, transforms))
    bag = write_bag(tmp_path / "late_detections.bag", messages)
    recording = read_recording([bag], topics=["tf"])
    assert recording.timeline.tf_start == WALL + 3 * S - 5 * MS  # the record clock's tf: the detections'
    query = MonitorQuery(target="arm_base", source="arm_link", start=Offset(1), end=Offset(-1, from_end=True))
    report = monitor(recording, query)
    arm = next(e for e in report.edges if e.key == ("arm_base", "arm_link"))
    assert (arm.first_stamp, arm.last_stamp, arm.count) == (1901 * S, 19189 * S // 10, 180)
    printed = json.loads(
        tfx("monitor", "arm_base", "arm_link", "-b", bag, "--topic", "tf", "--start", "+1", "-f", "json").stdout
    )
    [edge] = [e for e in printed["edges"] if e["child"] == "arm_link"]
    assert edge["first_stamp"] == 1901.0 and edge["count"] == 190
    whole = json.loads(tfx("monitor", "-b", bag, "--topic", "tf", "--start", "+1", "-f", "json").stdout)
    [edge] = [e for e in whole["edges"] if e["child"] == "arm_link"]  # no chain asked: the record clock's tf
    assert edge["first_stamp"] == 1904.0


def late_detections(tmp_path: Path) -> Path:
    """``two_clocks``' arm on simulated time (1900 s on, received at its stamp's tenth of a second into the
    recording), its detections on wall time beginning 3 s into it."""
    messages = []
    for i in range(200):
        record = WALL + i * S // 10
        transforms = [moving("arm_base", "arm_link", 1900 * S + i * S // 10, i)]
        if i >= 30:
            transforms.append(moving("camera", "object", record - 5 * MS, i))
        messages.append(TfMessage("tf", record, transforms))
    return write_bag(tmp_path / "late_detections.bag", messages)


def test_a_replay_starts_on_the_clock_of_the_chain_asked_about(tmp_path: Path, tfx: Tfx) -> None:
    """Issue 39 item 4 for ``--play``: a replay counted ``+S`` on the record clock's tf (the detections', 3 s
    in) whatever the frames; now from the arrival of the arm's first transform stamped at its own first
    stamp + 1 s (1901 s, received 1 s into the recording), to that of its last stamped 1 s before its end."""
    stream = stream_recording([late_detections(tmp_path)], topics=["tf"])
    assert stream.timeline.tf_start == WALL + 3 * S - 5 * MS
    assert stream.moving_chain("arm_base", "arm_link") == ["arm_link"]
    query = MonitorQuery(target="arm_base", source="arm_link", start=Offset(1), end=Offset(-1, from_end=True))
    assert played_window(stream, query) == (WALL + S, WALL + 189 * S // 10)
    assert played_window(stream, MonitorQuery(start=Offset(1))) == (WALL + 4 * S - 5 * MS, None)  # no chain
    printed = tfx("monitor", "arm_base", "arm_link", "-b", tmp_path / "late_detections.bag", "--topic", "tf",
                  "--start", "+1", "--play", "--rate", "100", "--window", "30", "-f", "json")  # fmt: skip
    assert printed.code == 0, printed.stderr
    [edge] = [e for e in json.loads(printed.stdout.splitlines()[-1])["edges"] if e["child"] == "arm_link"]
    assert (edge["first_stamp"], edge["count"]) == (1901.0, 190)  # as the whole read counts them


def test_a_long_replay_starts_between_the_arrivals_its_first_pass_kept(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A frame's arrivals are thinned past ``SAMPLES_PER_FRAME`` while they are read and to ``PLAYED_ARRIVALS``
    for the replay: a stamp between two kept ones plays when its neighbours' arrivals say, never after the
    next transform stamped from it."""
    monkeypatch.setattr("tftools.sources.stream.SAMPLES_PER_FRAME", 64)
    monkeypatch.setattr("tftools.sources.stream.PLAYED_ARRIVALS", 16)
    stream = stream_recording([late_detections(tmp_path)], topics=["tf"])
    stamps, played = stream.arrivals["arm_link"]
    assert len(stamps) == 16
    thinned = int(np.setdiff1d(1900 * S + np.arange(200) * S // 10, stamps)[5])
    arrival = WALL + (thinned - 1900 * S)  # the arm is received at its stamp's distance from 1900 s
    assert stream.replay_time(thinned, ["arm_link"]) == arrival
    assert stream.replay_time(thinned + 50 * MS, ["arm_link"]) == arrival + 50 * MS  # before the next one's
    assert stream.replay_time(thinned + 50 * MS, ["arm_link"], last=True) == arrival + 50 * MS
    assert stream.replay_time(2000 * S, ["arm_link"]) == played[-1] + 1  # none stamped from it: after the last
    assert stream.replay_time(0, ["arm_link"], last=True) == WALL - 1  # none stamped up to it: before the first


def test_monitor_start_on_a_real_chain_on_simulated_time(tfx: Tfx) -> None:
    """ros2_db3_ur5_topic_tf_two_clocks: the UR5 arm on simulated time (1907.175 to 1914.325 s) beside ArUco
    detections on wall time, the arm recorded from 0.57 s before the first detection. ``--start +1`` between
    base_link and wrist_3_link is 1908.175 s, as ``tfx echo --at +1`` asks (it monitored from 1908.575 s)."""
    bag = corpus("ros2_db3_ur5_topic_tf_two_clocks")
    recording = read_recording([bag], topics=["tf"])
    first, last = recording.timeline.span_of(["wrist_3_link"])
    assert (first, last) == (1907175 * MS, 1914325 * MS)
    report = monitor(recording, MonitorQuery(target="base_link", source="wrist_3_link", start=Offset(1)))
    assert report.chain is not None and len(report.chain.edges) == 6
    assert {(e.first_stamp, e.last_stamp, e.count) for e in report.chain.edges} == {(first + S, last, 124)}
    printed = tfx("monitor", "base_link", "wrist_3_link", "-b", bag, "--topic", "tf", "--start", "+1", "-f", "json")
    arm = [e for e in json.loads(printed.stdout)["edges"] if e["child"] in report.chain.frames]
    assert len(arm) == 6 and {(e["first_stamp"], e["count"]) for e in arm} == {(1908.175, 124)}
    at = tfx("echo", "base_link", "wrist_3_link", "-b", bag, "--topic", "tf", "--at", "+1", "-f", "json")
    assert json.loads(at.stdout)["time"] == 1908.175  # echo and monitor count +1 alike


def test_a_replay_of_a_real_chain_on_simulated_time_starts_on_its_clock(tfx: Tfx) -> None:
    """ros2_db3_ur5_topic_tf_two_clocks with ``--play``: ``--start +1`` between base_link and wrist_3_link
    replayed from 1908.575 s of the arm (116 samples per joint: +1 counted on the detections' wall clock);
    now from 1908.175 s, 124 samples, as the whole read."""
    bag = corpus("ros2_db3_ur5_topic_tf_two_clocks")
    played = tfx("monitor", "base_link", "wrist_3_link", "-b", bag, "--topic", "tf", "--start", "+1", "--end", "-1",
                 "--play", "--rate", "50", "-f", "json")  # fmt: skip
    assert played.code == 0, played.stderr
    whole = tfx("monitor", "base_link", "wrist_3_link", "-b", bag, "--topic", "tf", "--start", "+1", "--end", "-1",
                "-f", "json")  # fmt: skip
    chain = json.loads(whole.stdout)["chain"]["frames"]
    seen = [
        {
            (e["child"], e["first_stamp"], e["last_stamp"], e["count"])
            for e in json.loads(out)["edges"]
            if e["child"] in chain
        }
        for out in (played.stdout.splitlines()[-1], whole.stdout)
    ]
    assert seen[0] == seen[1] and {e[1:] for e in seen[0]} == {(1908.175, 1913.325, 104)}


def test_the_timelines_tf_span_follows_its_clock_threshold(tmp_path: Path) -> None:
    """``Timeline.within`` chooses the frames on the reference again, and their span with them."""
    timeline = read_recording([two_clocks(tmp_path)], topics=["tf"]).timeline
    wide = timeline.within(2 * 10**9 * S)  # a clock threshold wider than the two clocks' distance: one clock
    assert wide.off_reference == frozenset() and wide.tf_start == 1900 * S
    assert timeline.within(10 * S).tf_start == WALL - 5 * MS


# --- times counted from zero -------------------------------------------------------------------------


def test_a_json_mcap_whose_first_messages_have_no_log_time_spans_its_known_times(tfx: Tfx) -> None:
    """The Foxglove JSON MCAP (Labelbox's Franka): messages logged at time 0 made its span 1748331284.3 s."""
    bag = corpus("json_mcap_lbx_franka.mcap")
    recording = read_recording([bag])
    assert recording.start > 1_700_000_000 * S and recording.end - recording.start < 5 * S
    header = tfx("wtf", bag).stdout.splitlines()[0]
    assert header.startswith(f"{bag}  mcap, 1.5 s recorded, 12 transforms")
    assert not re.search(r"[+-]\d{6,}\.\d s", tfx("wtf", bag).stdout)  # stamps 0 get no offset from 1748331282 s


def test_the_report_counts_every_time_from_the_one_origin(tmp_path: Path) -> None:
    """The page's axis started at the first sensor message while findings counted from the first tf stamp:
    '+45.5 s' in a finding's header and '+40.8 s' in its text. Now both from the tf's first stamp."""
    messages = [
        TfMessage("/tf", WALL + i * S // 10 + MS, [moving("odom", "base", WALL + i * S // 10, i)]) for i in range(300)
    ]
    messages += [
        TfMessage("/tf", WALL + (100 + i) * S // 10 + MS, [moving("base", "arm", WALL + (100 + i) * S // 10)])
        for i in range(50)
    ]
    messages.sort(key=lambda m: m.record_time)
    recording = read_recording([write_bag(tmp_path / "stale.bag", messages)])
    times = WALL - 5 * S + np.arange(0, 350) * S // 10  # a scan from 5 s before tf to its end
    scan = StampedMessages("/scan", "sensor_msgs/msg/LaserScan", times, times, np.zeros(350, np.int32), ["base"])
    recording.contents.stamped = StampedRead([scan])  # as read with its headers
    report = recording_report(recording)
    assert report.origin == recording.timeline.origin == WALL and report.bins.start < WALL - 4 * S
    (stale,) = [f for f in report.findings if f.code == "stale"]
    said = re.search(r"stopped at [\d.]+ \(([+-][\d.]+) s\)", stale.message)
    assert said is not None
    section = recording_section(0, report).html
    shown = re.search(r'<span class="when">([+-][\d.]+) s to [+-][\d.]+ s</span>', section)
    assert shown is not None and float(shown.group(1)) == pytest.approx(float(said.group(1)), abs=0.05)
    embedded = re.search(r'class="report-data">(.*?)</script>', section)
    assert embedded is not None
    data = json.loads(embedded.group(1))
    assert data["axis"]["start"] == pytest.approx((report.bins.start - WALL) / S)
    assert data["findings"][0]["from"] == pytest.approx(float(said.group(1)), abs=0.05)


# --- arrivals read off a ticking clock: rosbag play --clock --------------------------------------------


def heard_on_a_clock(step: int, record_step: int) -> RecordingContents:
    """What a live listener on use_sim_time hears of a replay whose /clock ticks every ``step``: each
    transform received 0 to 2 ms after its stamp, at the last tick before (a tick is 1 ms after the
    stamps' grid). odom -> base at a steady 100 Hz; map -> odom at about 20 Hz, truly irregular."""
    rng = np.random.default_rng(7)
    base = WALL + np.arange(1000) * 10 * MS
    odom = WALL + np.cumsum(rng.choice([20, 50, 100], 120)) * MS
    rows = [(t, "odom", "base") for t in base.tolist()] + [(t, "map", "odom") for t in odom.tolist()]
    rows.sort()
    builder = BatchBuilder()
    ticks = WALL + MS + np.arange(2000) * step
    arrivals = np.array([t for t, _, _ in rows]) + rng.integers(0, 2 * MS, len(rows))
    received = ticks[np.searchsorted(ticks, arrivals, side="right") - 1]
    for (stamp, parent, child), record in zip(rows, received.tolist(), strict=True):
        builder.add(parent, child, stamp, (0, 0, 0), (0, 0, 0, 1), record_time=record, authority="/replayed")
    heard = builder.take()
    info = SourceInfo("a replay", "ros1-live", int(received.min()), int(received.max()), len(heard))
    return RecordingContents([heard], [info], ("/tf", "/tf_static"))


def test_arrivals_read_off_a_10_ms_clock_raise_no_false_rate_warning() -> None:
    """tfx wtf beside rosbag play --clock gave 'rate' warnings for steady edges: the rhythm of arrivals
    read off /clock's 10 ms steps (a 100 Hz edge's intervals read 0, 10 or 20 ms). Knowing the step,
    only the edge that is irregular is; untold, the record times show it (on one grid, samples of an edge
    received within one tick)."""
    untold = recording_of(heard_on_a_clock(10 * MS, 0))
    assert untold.timeline.record_step == 10 * MS
    assert [f.frames for f in check(untold).findings if f.code == "rate"] == [("map", "odom")]
    knowing = recording_of(heard_on_a_clock(10 * MS, 0), record_step=10 * MS)
    rates = [f for f in check(knowing).findings if f.code == "rate"]
    assert [f.frames for f in rates] == [("map", "odom")] and "publishes irregularly" in rates[0].message
    assert knowing.timeline.record_step == 10 * MS and "ticks every 0.010 s" in knowing.timeline.describe()
    report = monitor_buffer(knowing.buffer, window=TimeWindow(timeline=knowing.timeline))
    assert all(math.isnan(e.delay_mean) for e in report.edges) and "0.010 s (100 Hz)" in report.delays_unavailable


def test_a_recording_made_on_sim_time_has_record_times_as_coarse_as_its_clock(tmp_path: Path) -> None:
    """``ros2 bag record --use-sim-time``: each message recorded at the last /clock value (10 Hz here)."""
    clock = [ClockMessage(100 * S + (k - 1) * S // 10, 100 * S + k * S // 10) for k in range(1, 100)]
    tf = [
        TfMessage("/tf", 100 * S + (i // 3) * S // 10, [moving("odom", "base", 100 * S + i * S // 30)])
        for i in range(3, 290)
    ]
    recording = read_recording([write_bag(tmp_path / "on_sim", tf, BagFormat.rosbag2_sqlite3, clock)])
    assert recording.timeline.record_step == S // 10 and recording.timeline.resolution == S // 10
    assert "ticks every 0.100 s" in recording.timeline.delays_unavailable
    # /clock on wall time, recorded 3 ms after each value by a recorder on the wall clock (its record times all on
    # that clock: 50 years from the rest, one message's would be left out as damaged): not a grid to read them off
    wall = [ClockMessage(WALL + k * S // 100 + 3 * MS, WALL + k * S // 100) for k in range(100)]
    on_wall = [dataclasses.replace(m, record_time=m.record_time - 100 * S + WALL) for m in tf]
    recorded = read_recording([write_bag(tmp_path / "on_wall", on_wall, BagFormat.rosbag2_sqlite3, wall)])
    assert recorded.timeline.record_step == 0 and not recorded.contents.problems


def stage_on_sim_time(tick: int) -> list[TfMessage]:
    """Stage and amcl recorded under use_sim_time without /clock (ros1_stage_amcl_sim_time_2015): stamps
    exactly 0.1 s apart, each message recorded at the simulation's last ``tick`` when it arrived (now in the
    tick of its stamp, now in the next); amcl post-dates map -> odom by 1.0 s (its transform_tolerance)."""
    rng = np.random.default_rng(3)
    messages = []
    for k in range(200):
        stamp = 100 * S + k * S // 10
        late = int(rng.integers(0, 2)) * tick
        messages.append(TfMessage("/tf", stamp + late, [moving("odom", "base", stamp)], "/stageros"))
        messages.append(TfMessage("/tf", stamp + late, [moving("map", "odom", stamp + S)], "/amcl"))
    return messages


@pytest.mark.parametrize("tick", [S // 10, 0], ids=["sim-ticks", "wall-clock"])
def test_record_times_on_a_simulations_ticks_are_as_coarse_as_them(tmp_path: Path, tick: int) -> None:
    """Stage's ticks are 100 ms: a steady 10 Hz edge's arrivals read 0, 0.1 or 0.2 s apart, and amcl's 1.0 s of
    post-dating up to 1.1 s: 'rate' warnings on every steady edge and a 'future' error, until the grid every
    record time lies on was taken for the record clock's step. Record times as fine as a wall clock's
    (here: 0.3 ms after the stamps) have no step."""
    messages = (
        stage_on_sim_time(tick)
        if tick
        else [
            TfMessage(m.topic, m.record_time + 300_000 + i, m.transforms, m.publisher)
            for i, m in enumerate(stage_on_sim_time(0))
        ]
    )
    recording = read_recording([write_bag(tmp_path / "stage.bag", messages, BagFormat.ros1)])
    assert recording.timeline.record_step == tick
    codes = {f.code for f in check(recording).findings}
    assert "rate" not in codes and "future" not in codes


@pytest.mark.parametrize("window_messages", [50, 100_000], ids=["windows", "whole"])
def test_a_stream_finds_the_ticks_a_whole_read_finds(tmp_path: Path, window_messages: int) -> None:
    """ros1_stage_amcl_sim_time_2015's replay: its stream's timeline had no record step (the whole read's found
    Stage's 100 ms ticks), so --play said amcl's and the fixed joints' delays a tick further from zero than the
    whole read (-0.5 s for -0.4 s). Read in windows of 50 messages or at once, the stream finds them too."""
    bag = write_bag(tmp_path / "stage.bag", stage_on_sim_time(S // 10), BagFormat.ros1)
    assert read_recording([bag]).timeline.record_step == S // 10
    with stream_recording([bag], window_messages=window_messages) as streamed:
        assert len(streamed.windows) == (8 if window_messages == 50 else 1)
        assert streamed.timeline.record_step == streamed.timeline.resolution == S // 10


def test_a_replay_says_the_delays_of_a_whole_read_on_a_simulations_ticks(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "stage.bag", stage_on_sim_time(S // 10), BagFormat.ros1)
    whole = {e.key: (e.delay_mean, e.delay_max) for e in monitor(read_recording([bag]), MonitorQuery()).edges}
    reports: list[MonitorReport] = []
    with stream_recording([bag], window_messages=50) as stream:
        monitor_stream(stream, MonitorQuery(window=100 * S), lambda live: reports.append(live.report()), speed=1000)
    assert {e.key: (e.delay_mean, e.delay_max) for e in reports[-1].edges} == whole
    # amcl's map -> odom, post-dated 1.0 s and read off the tick of its stamp or the next: -1.0 or -0.9 s, each
    # up to a tick more (figures.delays): -0.8 s at most, as the whole read says, not the replay's -0.9
    assert whole[("map", "odom")][1] == -8 * S // 10


def test_record_grid_needs_enough_times_on_one_grid() -> None:
    """A grid is read off 15 or more distinct record times, every step a multiple of the smallest, that of a
    millisecond or more: not off a few, nor off a wall clock's. A PFMS quiz's Stage bag of 1.7 s holds 18 ticks
    of 0.1 s (ros1_pfms_quiz5_a1_stage_three_robots_joined.bag): its stamps one tick ahead are no delay of -0.1 s."""
    ticks = 100 * S + np.arange(40, dtype=np.int64) * 3 * MS
    assert record_grid(ticks) == 3 * MS and record_grid(np.repeat(ticks, 2)) == 3 * MS
    jittered = ticks + np.random.default_rng(5).integers(0, 1000, 40)
    assert record_grid(ticks[:10]) == 0 and record_grid(jittered) == 0
    stage = 429_500 * MS + np.arange(18, dtype=np.int64) * 100 * MS
    assert record_grid(stage) == 100 * MS
    assert record_grid(100 * S + np.arange(40, dtype=np.int64) * 10_000) == 0  # 10 us apart: fine


def test_a_fleet_of_corpus_recordings_reports_no_trend_of_one_recording(tfx: Tfx) -> None:
    """'TRENDS (17 days, 1970-01-01 ...)': the JSON MCAP dated 1970 by its messages logged at 0, and the
    Nav2 simulation's notes, one recording's, called problems that started on its day."""
    fleet = [
        corpus(n) for n in ("json_mcap_lbx_franka.mcap", "ros2_mcap_nav2_turtlebot4.mcap", "ros1_evo_tf_example.bag")
    ]
    shown = tfx("wtf", *fleet)
    assert "ACROSS THE FLEET" in shown.stdout and "TRENDS" not in shown.stdout and "1970" not in shown.stdout
    days = json.loads(tfx("wtf", *fleet, "-f", "json").stdout)["fleet"]["days"]
    assert len(days) == 3 and min(days) > "2020"


def test_a_json_mcap_replays_from_its_first_known_time(tfx: Tfx) -> None:
    """Its messages logged at time 0 made a replay start at 0: 55 years before its tf."""
    bag = corpus("json_mcap_lbx_franka.mcap")
    streamed = stream_recording([bag])
    assert streamed.timeline.record_start == read_recording([bag]).start
    moved = np.concatenate([part.record_time for part in streamed.parts()])
    # those logged at 0 play 1 ns before the first known time: first, and of unknown arrival as in a whole read
    assert moved.min() == streamed.timeline.unknown_played == streamed.timeline.record_start - 1
    assert streamed.timeline.record_start > 1_700_000_000 * S
    assert streamed.replay(rate=10).begin == streamed.timeline.unknown_played
    played = tfx("monitor", "-b", bag, "--play", "--rate", "10", "-f", "json")
    windows = [json.loads(line)["window"] for line in played.stdout.splitlines()]
    assert played.code == 0 and windows and all(w["end"] > 1_748_331_282 for w in windows)


SAMPLE = Path(__file__).resolve().parents[2] / "sample_bags" / "robot.bag"


def sample_replayed_on_sim_time(step: int) -> RecordingContents:
    """The healthy sample robot as a listener on use_sim_time hears ``rosbag play --clock``: the player
    publishes /clock (every ``step``) in the loop that publishes the messages, so a message and the tick
    for its time race on two connections: it is received at its time, or at the tick before (a step
    and a little more earlier: /clock's values come from the wall clock)."""
    rng = np.random.default_rng(0)
    heard = read_recording([SAMPLE]).transforms
    sent = heard.record_time.copy()
    late_tick = rng.random(len(sent)) < 0.5
    heard.record_time[:] = np.where(late_tick, sent - step - rng.integers(1, 300_000, len(sent)), sent)
    heard = take_rows(heard, np.argsort(heard.record_time, kind="stable"))
    info = SourceInfo("a replay", "ros1-live", int(heard.record_time.min()), int(heard.record_time.max()), len(heard))
    return RecordingContents([heard], [info], ("/tf", "/tf_static"))


def test_the_healthy_sample_replayed_on_sim_time_gets_no_rate_warning() -> None:
    """'tfx wtf -d 12' beside 'rosbag play --clock' of the sample bag: its 50 Hz edges' arrivals, read off
    /clock, are 10 or 30 ms apart as often as 20. That once gave 7 'rate' warnings ('33% of its intervals are
    more than 50% off'); their stamps are steady, so arrivals in a clock's steps are no irregular rate,
    whether the clock's step (the source's) is known or not."""
    blind = check(recording_of(sample_replayed_on_sim_time(10 * MS)))
    assert [f.message for f in blind.findings] == []
    knowing = check(recording_of(sample_replayed_on_sim_time(10 * MS), record_step=10 * MS))
    assert [f.message for f in knowing.findings] == []


@pytest.mark.parametrize("clock_hz", [100, 10])
def test_a_simulation_recorded_on_wall_time_says_what_is_measured_against_its_clock(
    tmp_path: Path, clock_hz: int
) -> None:
    """A simulation recorded without --use-sim-time (ros2_db3_tb3_gazebo_amcl_static_resent): the clock note
    said 'ages are measured against /clock at arrival, and delays', a sentence cut short: ages and delays
    where /clock is fine enough to time them, ages alone (and why not delays) where it is not."""
    step = S // clock_hz
    clock = [ClockMessage(WALL + k * step + 2 * MS, 100 * S + k * step) for k in range(20 * clock_hz)]
    tf = [
        TfMessage("/tf", WALL + i * S // 20 + 32 * MS, [moving("odom", "base", 100 * S + i * S // 20)])
        for i in range(390)
    ]
    recording = read_recording([write_bag(tmp_path / "sim_on_wall", tf, BagFormat.rosbag2_sqlite3, clock)])
    (note,) = [f for f in check(recording).findings if f.code == "clock"]
    assert "recorded without --use-sim-time" in note.message
    unavailable = recording.timeline.delays_unavailable
    if unavailable:
        assert note.message.endswith(f"ages are measured against /clock at arrival; {unavailable}")
    else:
        assert note.message.endswith("ages and delays are measured against /clock at arrival")
    assert bool(unavailable) == (clock_hz == 10)
