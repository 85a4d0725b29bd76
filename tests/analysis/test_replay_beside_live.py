"""A recording replayed with its own /tf beside live nodes (issue 39): a ROS 1 bag written by a tool, without
callerids, in which map -> odom comes from the replay (stamped a week behind its arrival) and from a live SLAM
node (its own clock), taking turns every 25 ms, and the replay's odom -> base_link a week behind. One root
cause, said from the evidence (two time bases, each steady on its own), and every figure on one clock; first
on a designed bag, then on the real one (ros1_raspimouse_replay_beside_live_gmapping_2018.bag)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from rich.console import Console

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tests.corpus.fetch import shared_dir
from tftools.analysis.edges import TimeWindow, edge_stats, history_rate
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.frames import frame_tree
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.render.frames import write_tree
from tftools.sources.recording import read_recording

MS = scenes.MS
START = scenes.START
WEEK = 7 * 86_400 * NS_PER_S
SECONDS = 20
REAL = "corpus/ros1_raspimouse_replay_beside_live_gmapping_2018.bag"


def _replay_beside_live() -> list[TfMessage]:
    """Every 50 ms the replay sends map -> odom and odom -> base_link stamped a week behind; 25 ms later the
    live node sends its own map -> odom, post-dated 50 ms (gmapping's transform_publish_period). No callerids."""
    messages = []
    for i in range(SECONDS * 20):
        arrival = START + i * 50 * MS
        old = arrival - WEEK - 3 * MS
        messages.append(TfMessage("/tf", arrival, [scenes._t("map", "odom", old, 0.5)]))
        messages.append(TfMessage("/tf", arrival + MS, [scenes._t("odom", "base_link", old, 0.01 * i)]))
        live = arrival + 25 * MS
        messages.append(TfMessage("/tf", live, [scenes._t("map", "odom", live + 50 * MS, 0.8, 0.1)]))
    return messages


def _codes(findings: list[Finding]) -> set[str]:
    return {f.code for f in findings}


def _durations(findings: list[Finding]) -> list[float]:
    """Every figure in seconds a finding names, but absolute times (epoch seconds)."""
    said = [float(x) for f in findings for x in re.findall(r"(\d+(?:\.\d+)?) s\b", f.message)]
    return [x for x in said if x < 1e8]


@pytest.fixture(scope="module")
def bag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return scenes.write(tmp_path_factory.mktemp("replay"), "replay", BagFormat.ros1, _replay_beside_live())


def test_the_cause_is_two_publishers_on_two_clocks(bag: Path) -> None:
    findings = check(read_recording([bag])).findings
    (two,) = [f for f in findings if f.code == "multiple_authorities"]
    assert two.frames == ("map", "odom")
    assert two.figures["time_bases"] == 2 and two.figures["older_samples"] == SECONDS * 20
    assert two.figures["behind_s"] == pytest.approx(WEEK / NS_PER_S, abs=1.0)
    assert "two time bases 7.0 days apart" in two.message and "two publishers on two clocks" in two.message
    assert "clock" in _codes(findings)  # odom -> base_link, the replay's, a week behind: still said
    assert not {"rate", "time_backwards"} & _codes(findings)  # that mix seen as one publisher
    assert all(x < 86_400 for x in _durations([f for f in findings if f.code != "clock"]))
    assert not re.search(r"\(\+\d{4,}", " ".join(f.message for f in findings))  # no '+603862.8 s' moments


def test_monitor_figures_are_each_clocks_own(bag: Path) -> None:
    recording = read_recording([bag])
    stats = {(s.parent, s.child): s for s in edge_stats(recording.buffer, TimeWindow(timeline=recording.timeline))}
    both = stats[("map", "odom")]
    assert both.count == 2 * SECONDS * 20
    # both publishers side by side over the 19.975 s they arrived in (``figures.rate_of``): a sample every 25 ms;
    # not 799 samples over a week, nor one publisher's 20 Hz (the 798 intervals over both bases' spans added)
    assert both.rate_hz == pytest.approx(798 / 19.975)
    assert both.longest_interval == 50 * MS
    assert both.delay_mean == pytest.approx(-0.050 * NS_PER_S, abs=MS)  # the live node's post-dating only


def test_the_real_replay_beside_a_live_gmapping() -> None:
    path = shared_dir() / REAL
    if not path.exists():
        pytest.skip(f"{REAL} is not in the shared corpus ($TFTOOLS_SHARED_DIR)")
    recording = read_recording([path])
    findings = check(recording).findings
    (two,) = [f for f in findings if f.code == "multiple_authorities"]
    assert two.frames == ("map", "odom") and two.figures["older_samples"] == 1033
    # the replayed map -> odom arrived 603862.70 s after its stamps (median), the live one 0.050 s before its own
    assert two.figures["behind_s"] == pytest.approx(603862.70 + 0.05, abs=0.01)
    assert not {"rate", "time_backwards"} & _codes(findings)
    stats = {(s.parent, s.child): s for s in edge_stats(recording.buffer, TimeWindow(timeline=recording.timeline))}
    # 2114 samples, the replay's and the live gmapping's, in 54 s: 39.09 Hz (tfx said 0.0035 Hz before
    # clocks11, then 20.00 Hz: one publisher's rate for both)
    assert stats[("map", "odom")].rate_hz == pytest.approx(39.09, abs=0.01)
    assert stats[("map", "odom")].longest_interval < 0.1 * NS_PER_S


def test_frames_says_an_edge_on_two_clocks_spans_no_time(bag: Path) -> None:
    """`tfx frames` once printed map -> odom's first and last stamps a week apart as '(604800.0 s)' in a 20 s
    recording: its stamps are on two clocks, and the tree says so; one clock keeps its span."""
    tree = frame_tree(read_recording([bag]))
    assert tree.frames["odom"].clocks == 2 and tree.frames["base_link"].clocks == 1
    console = Console(width=300, record=True)
    write_tree(tree, console)
    text = console.export_text()
    odom = next(line for line in text.splitlines() if "odom" in line and "samples" in line and "base_link" not in line)
    assert "stamped on 2 clocks: no span" in odom and "604800" not in odom, odom
    assert re.search(r"base_link .*\(19\.\d s\)", text), text


def _replay_ending_early() -> list[TfMessage]:
    """``_replay_beside_live`` with the replay ending 3 s before the live node does, and a live base_link ->
    laser (on the live clock) that stops at 10 s on its own."""
    end = START + (SECONDS - 3) * NS_PER_S
    messages = [m for m in _replay_beside_live() if m.transforms[0].stamp > START or m.record_time < end]
    laser = [
        TfMessage("/tf", START + i * 50 * MS, [scenes._t("base_link", "laser", START + i * 50 * MS, 0.2)])
        for i in range(200)
    ]
    return sorted(messages + laser, key=lambda m: m.record_time)


def test_the_replays_clock_and_its_end_are_said_beneath_the_cause(tmp_path: Path) -> None:
    """The raspimouse replay (issue 39): the replay's odom -> base_link a week behind (clock) and stopping where
    the replay ended (stale) follow from the two publishers on two clocks: said beneath it, the cause counted
    once and as severe as they are; a live edge that stopped on its own stays a cause of its own."""
    bag = scenes.write(tmp_path, "replay", BagFormat.ros1, _replay_ending_early())
    findings = check(read_recording([bag])).findings
    (two,) = [f for f in findings if f.code == "multiple_authorities"]
    assert not two.cause and two.severity is Severity.error and two.key
    beneath = {(f.code, f.frames) for f in findings if f.cause == two.key}
    assert beneath == {("clock", ("odom", "base_link")), ("stale", ("odom", "base_link"))}, findings
    (laser,) = [f for f in findings if f.code == "stale" and f.frames == ("base_link", "laser")]
    assert not laser.cause
    assert laser.figures["arrival_minus_stamp_s"] == pytest.approx(0.0, abs=0.01)
    assert two.figures["older_offset_s"] == pytest.approx(WEEK / NS_PER_S + 0.003, abs=0.01)
    (clock,) = [f for f in findings if f.code == "clock"]  # the frames on the recording's clock said as such
    assert "stamped 7.0 days behind the recording's clock (which odom and laser follow): another clock" in clock.message


def test_the_real_replays_clock_and_its_end_are_beneath_the_cause() -> None:
    path = shared_dir() / REAL
    if not path.exists():
        pytest.skip(f"{REAL} is not in the shared corpus ($TFTOOLS_SHARED_DIR)")
    findings = check(read_recording([path])).findings
    (two,) = [f for f in findings if f.code == "multiple_authorities"]
    assert [f.code for f in findings if not f.cause and f.severity is not Severity.info] == ["multiple_authorities"]
    (clock,) = [f for f in findings if f.code == "clock"]
    assert "stamped 7.0 days behind the recording's clock (which odom follows): another clock" in clock.message
    assert {(f.code, f.frames) for f in findings if f.cause == two.key} == {
        ("clock", ("odom", "base_link")),
        ("stale", ("odom", "base_link")),
    }


def test_filter_counts_an_edges_rate_as_monitor_does(bag: Path) -> None:
    """`tfx filter` rated the edge it waited for over its newest minus its oldest stamp: on two clocks, 799
    samples over a week (0.0013 Hz), so a silence limit of 2 hours; now the rate monitor shows."""
    from tftools.analysis.filter.fates import _rate

    recording = read_recording([bag])
    stats = {s.child: s for s in edge_stats(recording.buffer, TimeWindow(timeline=recording.timeline))}
    hist = recording.buffer.history("odom")
    assert hist is not None and history_rate(hist) == pytest.approx(stats["odom"].rate_hz)
    assert _rate(recording.buffer, ("map", "odom")) == pytest.approx(798 / 19.975)
    assert _rate(recording.buffer, ("odom", "base_link")) == pytest.approx(stats["base_link"].rate_hz)


def test_view_frames_says_an_edge_on_two_clocks_has_no_buffer_length(bag: Path) -> None:
    """view-frames drew the real replay's map -> odom with 'Buffer length: 603916.781 s' in a 54 s recording:
    its newest stamp minus its oldest, on two clocks a week apart. It says the stamps are on two clocks."""
    from tests.analysis.test_graph_dot import dot_source

    recording = read_recording([bag])
    stats = {s.child: s for s in edge_stats(recording.buffer, TimeWindow(timeline=recording.timeline))}
    assert stats["odom"].clocks == 2 and stats["base_link"].clocks == 1
    dot = dot_source(recording)
    assert "Buffer length: stamped on 2 clocks, no span" in dot and "604800" not in dot
    assert re.search(r"Buffer length: 19\.\d{3} s", dot), dot  # the replay's odom -> base_link, on one clock


@pytest.mark.parametrize("target", ["map", "odom"])
def test_plus_s_through_the_replays_frame_counts_on_the_replays_clock(bag: Path, target: str) -> None:
    """`tfx echo map base_link --at +2` on the real replay asked for the live clock's first stamp + 2 s, where
    the replay's odom -> base_link (a week behind) has no data, and failed with an extrapolation 603790.9 s into
    the future: +S counts on the clock where every edge asked about has data, the replay's."""
    from tftools.analysis.echo import EchoQuery, echo_times
    from tftools.analysis.times import Offset

    recording = read_recording([bag])
    (at,) = echo_times(
        recording.buffer, recording.timeline, EchoQuery(target=target, source="base_link", at=Offset(2.0))
    )
    first_replayed = START - WEEK - 3 * MS
    assert at == first_replayed + 2 * NS_PER_S
    assert recording.buffer.lookup(target, "base_link", int(at)) is not None


def test_echo_over_an_edge_on_two_clocks_leaves_out_the_time_between_them(bag: Path) -> None:
    """`tfx echo map odom` on the real replay printed 603,917 lines a second apart, interpolated across the week
    between the replay's clock and the live node's, in which map -> odom has no sample: it echoes each clock's
    stretch, and nothing between."""
    from tftools.analysis.echo import EchoQuery, echo_times

    recording = read_recording([bag])
    times = echo_times(recording.buffer, recording.timeline, EchoQuery(target="map", source="odom"))
    replayed, live = times[times < START], times[times >= START]
    assert len(replayed) == len(live) == SECONDS  # 19.95 s of stamps on each clock: 20 ticks a second apart
    assert replayed[-1] - replayed[0] < SECONDS * NS_PER_S and live[-1] - live[0] < SECONDS * NS_PER_S
    assert live[0] - replayed[-1] > WEEK - SECONDS * NS_PER_S  # the week between: no line
    assert len(echo_times(recording.buffer, recording.timeline, EchoQuery(target="odom", source="base_link"))) == 20
