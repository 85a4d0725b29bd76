"""tf_monitor's numbers on recordings whose truth is known: rates, jitter, gaps, delays, chains."""

from __future__ import annotations

import itertools
import math
import statistics
from pathlib import Path

import numpy as np
import pytest

import tftools.analysis.monitor as monitor_module
from tests.analysis.monitor_scenes import (
    DROP,
    FORMATS,
    JITTER_SIGMA,
    LAG,
    START,
    Scene,
    scene,
    scene_buffer,
    write_scene,
)
from tests.bags import BagFormat, TfMessage, write_bag
from tftools.analysis.edges import EdgeStats, TimeWindow
from tftools.analysis.monitor import LiveMonitor, MonitorQuery, MonitorReport, monitor, monitor_buffer, monitor_stream
from tftools.analysis.times import Offset
from tftools.core.batch import BatchBuilder
from tftools.core.buffer import Buffer
from tftools.core.errors import ConnectivityError
from tftools.core.figures import seconds, silence_in_words
from tftools.core.time import NS_PER_S, SimClock
from tftools.core.transform import Transform
from tftools.sources import read_recording
from tftools.sources.contents import SentMessages
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.stream import stream_recording

MS = 1_000_000


@pytest.fixture(scope="module")
def truth_scene() -> Scene:
    return scene()


def _by_child(report: MonitorReport) -> dict[str, EdgeStats]:
    return {e.child: e for e in report.edges}


def _check_edges_against_truth(report: MonitorReport, truth_scene: Scene) -> None:
    edges = _by_child(report)
    assert set(edges) == {*truth_scene.truth, "laser"}
    for child, t in truth_scene.truth.items():
        e = edges[child]
        assert (e.parent, e.static, e.count) == (t.parent, False, len(t.stamps))
        span_s = (t.stamps[-1] - t.stamps[0]) / NS_PER_S
        assert e.rate_hz == pytest.approx((len(t.stamps) - 1) / span_s, rel=1e-9)
        intervals = [b - a for a, b in itertools.pairwise(t.stamps)]
        assert seconds(e.jitter) == pytest.approx(statistics.pstdev(intervals) / NS_PER_S, rel=1e-6)
        assert seconds(e.longest_interval) == pytest.approx(max(intervals) / NS_PER_S, abs=1e-9)
        assert seconds(e.delay_mean) == pytest.approx(statistics.mean(t.delays) / NS_PER_S, rel=1e-9)
        assert seconds(e.delay_max) == pytest.approx(max(t.delays) / NS_PER_S, abs=1e-9)
        assert (e.first_stamp, e.last_stamp) == (t.stamps[0], t.stamps[-1])
        if child != "odom":  # the hole lowers the localizer's average rate
            assert e.rate_hz == pytest.approx(t.hz, rel=0.01)
    laser = edges["laser"]
    assert (laser.parent, laser.static, laser.rate_hz) == ("base_link", True, 0.0)
    assert math.isnan(laser.delay_mean) and math.isnan(laser.delay_max)


def _check_designed_effects(report: MonitorReport) -> None:
    """The effects the scene was built with, in the units a user reads."""
    edges = _by_child(report)
    # Stamp noise of sigma on each stamp spreads the intervals by sigma * sqrt(2).
    assert seconds(edges["base_link"].jitter) == pytest.approx(JITTER_SIGMA * math.sqrt(2) / NS_PER_S, rel=0.15)
    assert seconds(edges["wheel"].jitter) < 1e-9  # a perfect clock
    hole = edges["odom"]
    assert seconds(hole.longest_interval) == pytest.approx((DROP[1] - DROP[0] + 50 * MS) / NS_PER_S, abs=1e-6)
    assert DROP[0] - 50 * MS <= hole.longest_interval_start - START < DROP[0]
    assert hole.rate_hz == pytest.approx(20 * (1 - 2.5 / 30), rel=0.01)  # 50 samples missing of 600
    lagging = edges["camera"]
    assert LAG[0] / NS_PER_S <= seconds(lagging.delay_mean) <= (LAG[0] + LAG[1]) / NS_PER_S
    assert seconds(lagging.delay_mean) == pytest.approx((LAG[0] + LAG[1] / 2) / NS_PER_S, abs=0.004)
    assert all(seconds(edges[c].delay_max) < 0.004 for c in ("base_link", "odom", "wheel"))


@pytest.mark.parametrize("fmt", FORMATS)
def test_bag_numbers_match_the_truth(tmp_path: Path, truth_scene: Scene, fmt: BagFormat) -> None:
    recording = read_recording([write_scene(tmp_path, fmt, truth_scene.messages)])
    report = monitor_buffer(recording.buffer, window=TimeWindow(by_record_time=True))
    _check_edges_against_truth(report, truth_scene)
    _check_designed_effects(report)


def test_publishers_rates_delays_and_edges(truth_scene: Scene) -> None:
    report = monitor_buffer(scene_buffer(truth_scene.messages))
    publishers = {a.authority: a for a in report.authorities}
    assert set(publishers) == {t.publisher for t in truth_scene.truth.values()}
    for t in truth_scene.truth.values():
        p = publishers[t.publisher]
        records = sorted(set(t.records))
        assert p.rate_hz == pytest.approx((len(records) - 1) * NS_PER_S / (records[-1] - records[0]), rel=1e-9)
        assert p.rate_hz == pytest.approx(t.hz, rel=0.01 if t.child != "odom" else 0.1)
        if t.publisher == "/state_publisher":  # also sent the static laser: one more message, not in its rhythm
            assert set(p.edges) == {("base_link", "wheel"), ("base_link", "laser")}
            assert p.messages == len(records) + 1
        else:
            assert p.edges == ((t.parent, t.child),)
            assert p.messages == len(records)
        assert seconds(p.delay_mean) == pytest.approx(statistics.mean(t.delays) / NS_PER_S, rel=1e-9)
        assert seconds(p.delay_max) == pytest.approx(max(t.delays) / NS_PER_S, abs=1e-9)


def test_two_publishers_of_one_edge_are_both_named() -> None:
    buffer = Buffer(cache_time=None)
    for k in range(10):
        stamp = START + k * 100 * MS
        publisher = "/a" if k % 2 else "/b"
        odom = Transform((0, 0, 0), (0, 0, 0, 1), stamp, "map", "odom")
        buffer.set_transform(odom, publisher, record_time=stamp + MS)
    (edge,) = monitor_buffer(buffer).edges
    assert sorted(edge.authorities) == ["/a", "/b"]
    assert edge.rate_hz == pytest.approx(10.0, rel=1e-9)


def test_a_window_counts_only_what_arrived_in_it(truth_scene: Scene) -> None:
    buffer = scene_buffer(truth_scene.messages)
    start, end = START + 5 * NS_PER_S, START + 8 * NS_PER_S
    edges = _by_child(monitor_buffer(buffer, window=TimeWindow(start, end, by_record_time=True)))
    for child, t in truth_scene.truth.items():
        inside = [s for s, r in zip(t.stamps, t.records, strict=True) if start <= r <= end]
        assert edges[child].count == len(inside)
        assert edges[child].first_stamp == inside[0]
        assert edges[child].rate_hz == pytest.approx(t.hz, rel=0.02)
    assert edges["laser"].static  # static edges hold at every time: always listed


def _chain_delay_by_lookups(
    buffer: Buffer, messages: list[TfMessage], target: str, source: str, times: np.ndarray
) -> np.ndarray:
    """tf_monitor's way: at each moment, now minus the stamp a latest-time lookup gets."""
    live = Buffer(cache_time=None)
    delays = []
    m = 0
    for now in times:
        while m < len(messages) and messages[m].record_time <= now:
            for t in messages[m].transforms:
                live.set_transform(t, messages[m].publisher, static=messages[m].topic == "/tf_static")
            m += 1
        delays.append((now - live.lookup(target, source, 0).stamp) / NS_PER_S)
    return np.array(delays)


def test_chain_and_its_delay_match_latest_lookups(truth_scene: Scene) -> None:
    buffer = scene_buffer(truth_scene.messages)
    begin = START + NS_PER_S  # (a latest-time lookup fails in the first milliseconds: stamps jitter)
    chain = monitor_buffer(buffer, "map", "camera", TimeWindow(begin)).chain
    assert chain is not None
    assert chain.frames == ("camera", "base_link", "odom", "map")
    assert [e.key for e in chain.edges] == [("base_link", "camera"), ("odom", "base_link"), ("map", "odom")]
    grid = np.arange(begin, truth_scene.end, MS // 2)
    expected = _chain_delay_by_lookups(buffer, truth_scene.messages, "map", "camera", grid)
    assert seconds(chain.delay_mean) == pytest.approx(expected.mean(), rel=0.002)
    assert expected.max() <= seconds(chain.delay_max) <= expected.max() + 0.0005
    # The camera lags 250+ ms: it holds the chain back, except across the localizer's hole.
    assert chain.limiting == ("base_link", "camera")
    assert seconds(chain.delay_max) == pytest.approx((DROP[1] - DROP[0] + 50 * MS) / NS_PER_S, abs=0.005)


def test_chain_delay_over_a_window(truth_scene: Scene) -> None:
    buffer = scene_buffer(truth_scene.messages)
    start, end = START + 20 * NS_PER_S, START + 25 * NS_PER_S
    chain = monitor_buffer(buffer, "odom", "wheel", TimeWindow(start, end, by_record_time=True)).chain
    assert chain is not None
    grid = np.arange(start, end, MS // 2)
    expected = _chain_delay_by_lookups(buffer, truth_scene.messages, "odom", "wheel", grid)
    assert seconds(chain.delay_mean) == pytest.approx(expected.mean(), rel=0.002)
    assert seconds(chain.delay_max) == pytest.approx(expected.max(), abs=0.0006)


def test_a_static_chain_never_goes_stale(truth_scene: Scene) -> None:
    chain = monitor_buffer(scene_buffer(truth_scene.messages), "base_link", "laser").chain
    assert chain is not None and chain.frames == ("laser", "base_link")
    assert math.isnan(chain.delay_mean) and math.isnan(chain.delay_max) and chain.limiting is None


def test_unconnected_frames_raise_tf2s_error() -> None:
    buffer = Buffer(cache_time=None)
    buffer.set_transform(Transform((0, 0, 0), (0, 0, 0, 1), START, "a", "b"), "/x", record_time=START)
    buffer.set_transform(Transform((0, 0, 0), (0, 0, 0, 1), START, "c", "d"), "/x", record_time=START)
    with pytest.raises(ConnectivityError):
        monitor_buffer(buffer, "a", "d")


def test_a_message_with_no_record_time_is_still_a_message() -> None:
    """json_mcap_lbx_franka.mcap: its first /tf and its /tf_static message are logged at time 0 (unknown), then
    four /tf messages 0.5 s apart; ROS 2's tf2 switches base's cache /tf -> /tf_static -> /tf. Monitor said 4 /tf
    messages and 0 /tf_static ones: 5 and 1 were sent, the rate is the four timed ones' (2 Hz)."""
    buffer = Buffer(cache_time=None, semantics="ros2")
    builder = BatchBuilder()
    sent = [("/tf", 0, 0), ("/tf_static", 0, 0)] + [
        ("/tf", t, t) for t in (START + k * NS_PER_S // 2 for k in range(4))
    ]
    for topic, stamp, record in sent:
        builder.add("world", "base", stamp, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0),
                    static=topic == "/tf_static", record_time=record, authority=topic)  # fmt: skip
    buffer.insert(builder.take())
    authorities = {a.authority: a for a in monitor_buffer(buffer, window=TimeWindow(by_record_time=True)).authorities}
    assert (authorities["/tf"].messages, authorities["/tf_static"].messages) == (5, 1)
    assert authorities["/tf"].rate_hz == pytest.approx(2.0)
    assert authorities["/tf_static"].static and not authorities["/tf"].static
    assert authorities["/tf"].edges == (("world", "base"),)


def test_a_live_monitor_keeps_the_replaced_statics_it_counts_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    """A live ROS 2 monitor counts the /tf_static messages whose cache a /tf one replaced (its bounded buffer
    keeps none of them: the JetAcker's map -> odom), but a frame switching topics at every message does
    not grow it without end: the newest ``REPLACED_STATICS`` such rows are kept."""
    monkeypatch.setattr(monitor_module, "REPLACED_STATICS", 40)
    clock = SimClock()
    live = LiveMonitor(clock, 4 * NS_PER_S, semantics="ros2")
    for k in range(100):
        t = START + k * NS_PER_S // 10
        clock.set(t)
        for topic in ("/tf_static", "/tf"):
            builder = BatchBuilder()
            builder.add("map", "odom", t, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0),
                        static=topic == "/tf_static", record_time=t + (topic == "/tf"), authority=topic)  # fmt: skip
            live.add(builder.take())
        if k == 9:
            first = {a.authority: a.messages for a in live.report().authorities}
    assert first["/tf_static"] == 10
    authorities = {a.authority: a.messages for a in live.report().authorities}
    statics = sum(int(b.static.sum()) for b in live.replaced)
    assert sum(len(b) for b in live.replaced) <= 40
    assert authorities["/tf_static"] == statics >= 10


class _SimRobot(LiveSource):
    """A live system under use_sim_time whose /clock ticks every 10 ms: each tick, one message of
    ``odom -> base_link`` and one of ``base_link -> wheel`` arrive at once (one receive time, read off /clock),
    then a latched static message, twice (a broadcaster started twice)."""

    format = "test-live"

    def __init__(self) -> None:
        super().__init__(None, True, None)

    def start(self, on_batch: OnBatch) -> None:
        for k in range(20):
            now = START + k * 10 * MS
            self._clock_message(now)
            builder = BatchBuilder()  # a message a transform
            for parent, child in [("odom", "base_link"), ("base_link", "wheel")] + [("base_link", "laser")] * 2 * (
                k == 0
            ):
                static = child == "laser"
                builder.add(parent, child, now, (0.01 * k, 0, 0), (0, 0, 0, 1), static=static, record_time=now,
                            authority="/rsp" if static else "/sim")  # fmt: skip
            batch = builder.take()
            sent = SentMessages(batch.authorities, batch.authority, batch.static, batch.record_time, batch.stamp)
            self._pass_on(on_batch, batch, sent)

    def describe(self) -> str:
        return "a simulated robot"

    def close(self) -> None:
        self._closed.set()


def test_a_live_monitor_counts_the_messages_that_arrived_at_one_tick() -> None:
    """Two publishers' messages heard at one /clock tick were one message (a live ROS 1 Gazebo on a 10 ms /clock):
    each one heard is counted, and the static broadcaster's two messages too."""
    reports: list[MonitorReport] = []
    monitor_stream(_SimRobot(), MonitorQuery(), lambda live: reports.append(live.report()), duration=0.01)
    publishers = {a.authority: a for a in reports[-1].authorities}
    assert (publishers["/sim"].messages, publishers["/rsp"].messages) == (40, 2)
    assert publishers["/sim"].rate_hz == pytest.approx(39 / 0.19)


def test_a_buffer_filled_by_hand_without_record_times_counts_a_message_an_instant() -> None:
    """A buffer knows no message boundaries: a publisher's transforms of one record time are taken for one
    message, and where no record time was given, those of one stamp (two wheels sent together, ten times)."""
    buffer = Buffer(cache_time=None)
    for k in range(10):
        for wheel in ("left", "right"):
            sample = Transform((0, 0, 0), (0, 0, 0, 1), START + k * NS_PER_S // 10, "base", wheel)
            buffer.set_transform(sample, "/rsp")
    (publisher,) = monitor_buffer(buffer).authorities
    assert (publisher.authority, publisher.messages, publisher.rate_hz) == ("/rsp", 10, 0.0)


ODOM_AND_WHEELS = (("odom", "base"), ("base", "left_wheel"), ("base", "right_wheel"))


def test_a_publisher_is_rated_on_the_clock_its_window_is_counted_on(tmp_path: Path) -> None:
    """Issue 39, ros2_mcap_nav2_turtlebot4.mcap (no /clock) from +2 s to +6 s: its /tf publisher was 230 messages
    at 45.97 Hz in a whole read, 228 at 56.91 Hz replayed. With no ROS time at arrival the whole read windows by
    stamp, yet it rated the publisher over record times: a map -> odom stamped 1 s ahead of its arrival
    stretched the span by a second. Rated by stamp, a simulation at 0.07x real time was 794 msgs/s for 53.7: both
    are windowed and rated on the record clock, as a replay plays them. Here odom -> base and its wheels at 50 Hz
    and a map -> odom stamped 1 s ahead every 0.2 s, all on /tf: 201 + 20 messages that arrived over 4 s of the
    record clock moved onto the stamps' by most frames' offset; 55 Hz, read whole or replayed (which plays them
    so)."""
    sim, wall = 100 * NS_PER_S, 1_695_944_000 * NS_PER_S
    messages = []
    for i in range(400):
        at = i * 20 * MS
        base = [Transform((0, 0, 0), (0, 0, 0, 1), sim + at, parent, child) for parent, child in ODOM_AND_WHEELS]
        messages.append(TfMessage("/tf", wall + at + 2 * MS, base))
        if i % 10 == 5:
            ahead = Transform((0, 0, 0), (0, 0, 0, 1), sim + at + NS_PER_S, "map", "odom")
            messages.append(TfMessage("/tf", wall + at + 3 * MS, [ahead]))
    bag = write_bag(tmp_path / "no_clock", messages, BagFormat.rosbag2_sqlite3)
    query = MonitorQuery(start=Offset(2), end=Offset(6))
    recording = read_recording([bag])
    assert not recording.timeline.available  # stamps on simulated time, no /clock: arrival in ROS time unknown
    (whole,) = monitor(recording, query).authorities
    # windowed and rated on the record clock moved onto the stamps' by most frames' offset, as the replay plays it
    assert whole.messages == 221 and whole.rate_hz == pytest.approx(220 / 4)
    reports: list[MonitorReport] = []
    replay = MonitorQuery(start=Offset(2), end=Offset(6), window=100 * NS_PER_S)
    monitor_stream(stream_recording([bag]), replay, lambda live: reports.append(live.report()), speed=1000)
    (played,) = reports[-1].authorities
    assert played.messages == 221 and played.rate_hz == pytest.approx(220 / 4)
    # no silence said where staleness cannot be measured (no clock of the stamps), nor from the newest stamp
    # (ROS time's end, guessed) post-dated 1 s: nav2's odom -> base_link read 'silent for the last 0.904 s'
    edges = [e for e in monitor(recording, MonitorQuery()).edges if not e.static]
    assert len(edges) == 4 and not any(silence_in_words(e.silent_for, e.rate_hz) for e in edges)


def test_the_silence_after_an_edges_last_sample_is_no_gap_read_whole_or_replayed(tmp_path: Path) -> None:
    """Issue 39 (corpus8's finding; the raspimouse replay's odom -> base_link, whose replay stops 2.5 s before the
    recorder): --play's largest gap counted the silence from its last sample to the end of playback (2.4738 s)
    while the whole read said 0.1018 s. Here odom -> base every 20 ms for 10 s, then silent for the last 3 s
    while map -> odom goes on: a gap of 20 ms and a silence of 3 s, read whole or replayed to the end."""
    wall = 1_700_000_000 * NS_PER_S
    messages = []
    for i in range(651):
        at = wall + i * 20 * MS
        transforms = [Transform((0, 0, 0), (0, 0, 0, 1), at, "map", "odom")]
        if i <= 500:
            transforms.append(Transform((0, 0, 0), (0, 0, 0, 1), at, "odom", "base"))
        messages.append(TfMessage("/tf", at + MS, transforms))
    bag = write_bag(tmp_path / "stops", messages, BagFormat.ros1)
    whole = _by_child(monitor(read_recording([bag]), MonitorQuery()))
    reports: list[MonitorReport] = []
    replay = MonitorQuery(window=100 * NS_PER_S)
    monitor_stream(stream_recording([bag]), replay, lambda live: reports.append(live.report()), speed=1000)
    played = _by_child(reports[-1])
    for edges in (whole, played):
        assert edges["base"].longest_interval == 20 * MS and edges["base"].silent_for == 3 * NS_PER_S
        assert edges["odom"].longest_interval == 20 * MS and edges["odom"].silent_for == 0


def test_no_silence_is_said_where_staleness_cannot_be_measured(tmp_path: Path) -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map: a simulation at 0.067x real time recorded on wall time without
    /clock. --play counted the wall-clock silence after each edge's last new stamp into its largest gap (0.47-1.36
    s against 0.03-0.12 s whole); a silence on the record clock beside rates on simulated time is no figure.
    Here odom -> base every 20 ms of simulated time, recorded 15 times slower, the last 1.5 s of the recording
    holding only a sensor message: no silence whole or replayed, and the same largest gap."""
    sim, wall = 14 * NS_PER_S, 1_761_607_000 * NS_PER_S
    messages = [
        TfMessage("/tf", wall + i * 300 * MS, [Transform((0, 0, 0), (0, 0, 0, 1), sim + i * 20 * MS, "odom", "base")])
        for i in range(100)
    ]
    messages.append(TfMessage("/tf", wall + 31 * NS_PER_S, []))
    bag = write_bag(tmp_path / "slow_sim", messages, BagFormat.rosbag2_sqlite3)
    recording = read_recording([bag])
    assert not recording.timeline.available
    whole = _by_child(monitor(recording, MonitorQuery()))["base"]
    reports: list[MonitorReport] = []
    replay = MonitorQuery(window=100 * NS_PER_S)
    monitor_stream(stream_recording([bag]), replay, lambda live: reports.append(live.report()), speed=1000)
    played = _by_child(reports[-1])["base"]
    assert whole.silent_for is None and played.silent_for is None  # unknown, not 0: not "it just arrived"
    assert whole.longest_interval == played.longest_interval == 20 * MS


def test_transforms_without_frames_are_counted_but_name_no_edge() -> None:
    """foxglove-wizard's drone.mcap: 17 default-made transforms (no frames, stamp 0) before world -> drone on /tf.
    tf2 refuses them; the publisher sent them all the same (counted), but they name no frame: its frames read
    'drone', not 'drone, '."""
    buffer = Buffer(cache_time=None, semantics="ros2")
    builder = BatchBuilder()
    for k in range(6):
        empty = k < 2
        builder.add("" if empty else "world", "" if empty else "drone", 0 if empty else START + k * NS_PER_S // 10,
                    (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), static=False,
                    record_time=START + k * NS_PER_S // 10, authority="/tf")  # fmt: skip
    buffer.insert(builder.take())
    (publisher,) = monitor_buffer(buffer, window=TimeWindow(by_record_time=True)).authorities
    assert (publisher.messages, publisher.edges) == (6, (("world", "drone"),))


def test_a_publisher_of_one_shot_frames_has_no_rate(tmp_path: Path) -> None:
    """KB_2546's /picknplace: two fruits placed once each, 1 ms apart, beside a 10 Hz robot. The edges have no
    rhythm ("-"), nor has their publisher: not 1000 messages a second."""
    messages = [
        TfMessage(
            "/tf",
            START + k * 100 * MS + MS,
            [Transform((k, 0, 0), (0, 0, 0, 1), START + k * 100 * MS, "map", "base")],
            "/robot",
        )
        for k in range(20)
    ]
    for k, fruit in enumerate(("fruit_red", "fruit_yellow")):
        placed = START + 500 * MS + k * MS
        messages.append(
            TfMessage("/tf", placed, [Transform((1, k, 0), (0, 0, 0, 1), placed, "base", fruit)], "/picknplace")
        )
    bag = write_bag(tmp_path / "one_shot.bag", sorted(messages, key=lambda m: m.record_time))
    report = monitor(read_recording([bag]), MonitorQuery())
    publishers = {a.authority: a for a in report.authorities}
    assert publishers["/picknplace"].once and publishers["/picknplace"].messages == 2
    assert not publishers["/robot"].once
    assert publishers["/robot"].rate_hz == pytest.approx(10.0, rel=1e-9)
