"""The frame graph model: every edge with its statistics, and each problem pinned on the edge or frame it is about."""

from __future__ import annotations

import math
import re

import pytest

from tests.analysis.wtf_scenes import PROBLEMS, SECONDS, ekf, recording
from tests.analysis.wtf_scenes import healthy as robot
from tftools.analysis.edges import edge_stats
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.frames import tree_of
from tftools.analysis.graph import FrameGraph, frame_graph, view_frames
from tftools.analysis.monitor import MonitorQuery, monitor
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.batch import BatchBuilder
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S, SimClock
from tftools.core.transform import Transform
from tftools.render.graph import to_digraph
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.sensor_headers import capture_live

START = 1_700_000_000 * NS_PER_S
END = START + 10 * NS_PER_S


def publish(
    buffer: Buffer,
    parent: str,
    child: str,
    hz: float = 10.0,
    start_s: float = 0.0,
    end_s: float = 10.0,
    authority: str = "/node",
    skip: tuple[float, float] | None = None,
) -> None:
    """``parent -> child`` moving at ``hz`` over ``[start_s, end_s)`` after START, silent during ``skip``."""
    n = round((end_s - start_s) * hz)
    for i in range(n):
        t = start_s + i / hz
        if skip and skip[0] <= t < skip[1]:
            continue
        stamp = START + round(t * NS_PER_S)
        buffer.set_transform(Transform((0.1 * t, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, parent, child), authority)


def publish_static(buffer: Buffer, parent: str, child: str, authority: str = "/rsp") -> None:
    buffer.set_transform(Transform((0.0, 0.0, 0.2), (0.0, 0.0, 0.0, 1.0), START, parent, child), authority, static=True)


def healthy() -> Buffer:
    buffer = Buffer(None, SimClock(END))
    publish(buffer, "map", "odom", hz=10)
    publish(buffer, "odom", "base_link", hz=50)
    publish_static(buffer, "base_link", "laser")
    publish_static(buffer, "base_link", "camera")
    return buffer


def codes(graph: FrameGraph) -> list[str]:
    return [f.code for f in graph.findings]


def pinned_edges(graph: FrameGraph, code: str) -> set[tuple[str, str]]:
    return {(e.parent, e.child) for e in graph.edges if any(graph.findings[i].code == code for i in e.problems)}


def pinned_nodes(graph: FrameGraph, code: str) -> set[str]:
    return {n.name for n in graph.nodes if any(graph.findings[i].code == code for i in n.problems)}


def test_healthy_tree_has_every_frame_and_edge_with_its_statistics_and_no_problem() -> None:
    buffer = healthy()
    graph = frame_graph(Scene(buffer))
    assert [n.name for n in graph.nodes] == buffer.frames
    assert graph.roots == ["map"]
    assert {(e.parent, e.child) for e in graph.edges} == {
        (f.parent, f.frame) for f in tree_of(buffer).frames.values() if f.parent
    }
    stats = {s.key: s for s in edge_stats(buffer)}
    for edge in graph.edges:
        assert edge.stats == stats[(edge.parent, edge.child)]
        assert not edge.problems and not edge.rejected
    assert {(e.parent, e.child) for e in graph.edges if e.static} == {("base_link", "laser"), ("base_link", "camera")}
    assert graph.edges[1].stats is not None and graph.edges[1].stats.rate_hz == pytest.approx(50)
    assert graph.findings == () and graph.now == END


def test_two_trees_mark_each_root_and_no_edge() -> None:
    buffer = healthy()
    publish_static(buffer, "world", "rig")
    publish_static(buffer, "rig", "rig_camera")
    graph = frame_graph(Scene(buffer))
    assert codes(graph) == ["disconnected"]
    assert graph.findings[0].severity is Severity.error
    assert pinned_nodes(graph, "disconnected") == {"map", "world"}
    assert pinned_edges(graph, "disconnected") == set()
    assert "map (5 frames:" in graph.findings[0].message and "world (3 frames:" in graph.findings[0].message


def test_a_loop_marks_its_edges() -> None:
    buffer = healthy()
    publish(buffer, "odom", "a")
    publish(buffer, "a", "b")
    publish(buffer, "b", "a", start_s=5.05)  # a re-parented under b (its newest sample): a -> b -> a
    graph = frame_graph(Scene(buffer))
    assert "cycle" in codes(graph)
    assert pinned_edges(graph, "cycle") == {("a", "b"), ("b", "a")}
    # a had two parents: both edges into it are marked, not the edges between those parents
    assert pinned_edges(graph, "multiple_parents") == {("odom", "a"), ("b", "a")}


def test_several_parents_mark_the_edges_into_the_frame_only() -> None:
    buffer = healthy()
    publish(buffer, "base_link", "imu", end_s=5)
    publish(buffer, "odom", "imu", start_s=5)
    graph = frame_graph(Scene(buffer))
    assert codes(graph) == ["multiple_parents"]  # the old edge stopped, but imu goes on: not stale
    assert pinned_edges(graph, "multiple_parents") == {("base_link", "imu"), ("odom", "imu")}
    assert ("odom", "base_link") not in pinned_edges(graph, "multiple_parents")
    assert pinned_nodes(graph, "multiple_parents") == set()


def test_a_frame_on_both_topics_marks_the_edges_into_it_not_those_between_its_parents() -> None:
    """ros4hri's RealSense (2022): camera_color_optical_frame under camera_color_frame on /tf_static, under camera_link
    on /tf; view-frames drew camera_link -> camera_color_frame, a healthy /tf_static edge, red for mixed_static."""
    buffer = healthy()
    publish_static(buffer, "base_link", "camera_link")
    publish_static(buffer, "camera_link", "camera_color_frame")
    publish_static(buffer, "camera_color_frame", "optical")
    publish(buffer, "camera_link", "optical", start_s=0.1)
    graph = frame_graph(Scene(buffer))
    assert "mixed_static" in codes(graph), codes(graph)
    assert ("camera_link", "camera_color_frame") not in pinned_edges(graph, "mixed_static")
    assert ("camera_link", "camera_color_frame") not in pinned_edges(graph, "multiple_parents")


def test_several_publishers_of_one_edge_are_a_warning_on_that_edge() -> None:
    buffer = healthy()
    publish(buffer, "base_link", "wheel", hz=10, authority="/a")
    publish(buffer, "base_link", "wheel", hz=10, start_s=0.05, authority="/b")
    graph = frame_graph(Scene(buffer))
    assert codes(graph) == ["multiple_authorities"]
    assert graph.findings[0].severity is Severity.warning
    assert graph.findings[0].authorities == ("/a", "/b")
    assert pinned_edges(graph, "multiple_authorities") == {("base_link", "wheel")}


def test_an_edge_that_stops_is_stale_and_one_that_pauses_has_a_gap() -> None:
    buffer = healthy()
    publish(buffer, "base_link", "wheel", hz=30, end_s=4)
    publish(buffer, "base_link", "arm", hz=50, skip=(3.0, 6.0))
    publish(buffer, "base_link", "slow", hz=1)  # 1 Hz: its last sample is 1 s old, as it should be
    graph = frame_graph(Scene(buffer))
    assert pinned_edges(graph, "stale") == {("base_link", "wheel")}
    assert pinned_edges(graph, "rate") == {("base_link", "arm")}
    stale = next(f for f in graph.findings if f.code == "stale")
    assert stale.severity is Severity.error and "stopped at 1700000003.967" in stale.message
    gap = next(f for f in graph.findings if f.code == "rate")
    assert gap.severity is Severity.warning and "3.0 s from 1700000002.980" in gap.message  # 2.98 s to 6.0 s


def test_rejected_samples_show_on_their_edge_even_when_none_was_accepted() -> None:
    buffer = healthy()
    nan = Transform((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START, "base_link", "arm")
    buffer.set_transform(nan, "/arm")
    repeated = Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START, "map", "odom")
    buffer.set_transform(repeated, "/node")  # stamp already held
    buffer.set_transform(Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START, "laser", "laser"), "/x")
    graph = frame_graph(Scene(buffer))
    edges = {(e.parent, e.child): e for e in graph.edges}
    assert edges[("base_link", "arm")].stats is None
    assert edges[("base_link", "arm")].rejected == (("TF_NAN_INPUT", 1),)
    assert edges[("map", "odom")].stats is not None
    assert edges[("map", "odom")].rejected == (("TF_REPEATED_DATA", 1),)
    assert edges[("laser", "laser")].rejected == (("TF_SELF_TRANSFORM", 1),)
    assert "arm" in [n.name for n in graph.nodes]
    assert pinned_edges(graph, "invalid_values") == {("base_link", "arm")}
    assert pinned_edges(graph, "time_backwards") == {("map", "odom")}
    assert pinned_edges(graph, "self_transform") == {("laser", "laser")}


def test_one_sample_refused_for_two_reasons_is_one_finding() -> None:
    buffer = healthy()
    both = Transform((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 2.0), START, "base_link", "arm")
    buffer.set_transform(both, "/arm")
    findings = findings_of(Scene(buffer))
    assert [f.code for f in findings] == ["invalid_values"]
    assert findings[0].count == 1 and "1 transform base_link -> arm by /arm refused" in findings[0].message


def test_given_findings_replace_the_engines_and_are_pinned_the_same_way() -> None:
    buffer = healthy()
    publish(buffer, "base_link", "wheel", end_s=2)  # the engine would call this stale
    mine = [
        Finding(Severity.warning, "delay", "odom -> base_link arrives late", "hint", ("odom", "base_link")),
        Finding(Severity.info, "note", "camera is fine", "hint", ("camera",)),
    ]
    graph = frame_graph(Scene(buffer), mine)
    assert graph.findings == tuple(mine)
    assert pinned_edges(graph, "delay") == {("odom", "base_link")}
    assert pinned_nodes(graph, "delay") == set()
    assert pinned_nodes(graph, "note") == {"camera"}
    assert graph.severity(next(e for e in graph.edges if e.child == "base_link").problems) is Severity.warning
    assert pinned_edges(graph, "stale") == set()


def test_empty_buffer_gives_an_empty_graph_that_says_so() -> None:
    graph = frame_graph(Scene(Buffer(None)))
    assert graph.nodes == () and graph.edges == () and codes(graph) == ["no_tf"]


def test_an_edge_stamped_on_another_clock_is_aged_on_that_clock() -> None:
    """An arm on simulated time (1234 s) among frames on epoch time: its newest sample is as old as the arm's
    own clock says, never the 54 years between the two clocks (a real UR5 recording drew 1695944400.698 s)."""
    scene = Scene(recording(PROBLEMS["clock"].make()).buffer)
    graph = frame_graph(scene)
    (arm,) = [e for e in graph.edges if e.key == ("odom", "base_link")]
    assert arm.stats is not None and graph.now_of(arm) == arm.stats.last_stamp < graph.now
    ages = [float(a) for a in re.findall(r"\(([0-9.]+) s old\)", to_digraph(graph, None).source)]
    assert ages and max(ages) < 10.0


def test_an_edge_on_another_clock_that_stopped_early_is_as_old_as_its_silence() -> None:
    """A replay's odom -> base_link 3 days behind the live frames, stopping 2.5 s before the recording ends
    (ros1_raspimouse_replay_beside_live_gmapping_2018: "(0.000 s old)" while monitor said it had been silent
    2.474 s and wtf that it stopped 2.5 s before the end): its own clock at the end is its newest stamp moved on
    by its silence, so view-frames ages it as the monitor times its silence."""
    rec = recording(robot(ekf=ekf(stamp=lambda t: t - 3 * 86400 * NS_PER_S, end=SECONDS - 2.5)))
    graph = frame_graph(Scene(rec.buffer))
    (odom,) = [e for e in graph.edges if e.key == ("odom", "base_link")]
    (silent,) = [e.silent_for for e in monitor(rec, MonitorQuery()).edges if e.key == ("odom", "base_link")]
    assert silent is not None and silent > 2 * NS_PER_S
    assert graph.age_of(odom) == silent
    assert f"({silent / NS_PER_S:.3f} s old)" in to_digraph(graph, None).source


def test_an_edge_stamped_ahead_of_the_recordings_end_is_said_ahead_never_negative_old() -> None:
    """A real TurtleBot3 whose clock runs ahead of the recorder's (ros2_db3_tb3_foxy_stamps_ahead) drew
    "(-0.051 s old)": an age is never negative, the label says what was observed instead."""
    buffer = healthy()
    publish(buffer, "base_link", "wheel", hz=10, start_s=0.05, end_s=10.15)  # newest stamp END + 0.05 s
    graph = frame_graph(Scene(buffer))
    (wheel,) = [e for e in graph.edges if e.key == ("base_link", "wheel")]
    assert graph.age_of(wheel) == -50_000_000
    source = to_digraph(graph, None).source
    assert "(stamped 0.050 s ahead of the recording's clock)" in source
    assert "(0.100 s old)" in source  # map -> odom at 10 Hz: its newest stamp 0.1 s before the end
    assert not re.search(r"-[0-9.]+ s old", source)


class _AheadRobot(LiveSource):
    """A live robot on the wall clock whose odom -> base_link is stamped 10 s ahead of the listener's clock."""

    format = "test-live"

    def __init__(self) -> None:
        super().__init__(None, False, None)

    def start(self, on_batch: OnBatch) -> None:
        builder, now = BatchBuilder(), self.clock.now()
        for i in range(5):
            stamp = now + 10 * NS_PER_S + i * NS_PER_S // 10
            builder.add("odom", "base_link", stamp, (i, 0, 0), (0, 0, 0, 1), record_time=now, authority="/odometry")
        self.message_count += 5
        self._pass_on(on_batch, builder.take())

    def describe(self) -> str:
        return "a robot ahead"

    def close(self) -> None:
        self._closed.set()


def test_a_live_edge_stamped_ahead_is_said_ahead_of_the_listeners_clock() -> None:
    graph = view_frames(capture_live(_AheadRobot(), 0.05))
    source = to_digraph(graph, None).source
    assert re.search(r"\(stamped \d+\.\d{3} s ahead of the listener's clock\)", source), source
    assert " s old" not in source
