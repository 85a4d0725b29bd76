"""Edges and sensor streams over time: each figure the local form of the one ``tfx monitor`` and ``tfx wtf``
give for the whole recording."""

from __future__ import annotations

import numpy as np
import pytest

from tests.analysis.wtf_scenes import PROBLEMS, START, _t, amcl, healthy, map_odom, periodic, recording, sensor
from tests.bags import TfMessage
from tftools.analysis.edges import TimeWindow, edge_stats
from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.analysis.monitor import monitor_buffer
from tftools.analysis.timelines import (
    MAX_BINS,
    MAX_CELLS,
    MIN_BINS,
    Bins,
    EdgeTimeline,
    MonitorTrace,
    bins_over,
    edge_axis,
    edge_timelines,
    local_rate,
    stream_timelines,
)
from tftools.core.figures import pauses, seconds
from tftools.core.time import NS_PER_S

MS = 1_000_000


@pytest.mark.parametrize("span_s", [0.001, 1.0, 9.95, 15.0, 3600.0, 86400.0 * 3])
def test_bins_are_round_and_cover_the_span(span_s: float) -> None:
    span = round(span_s * NS_PER_S)
    bins = bins_over(START, START + span)
    digits = str(bins.width).rstrip("0")
    assert digits in {"1", "2", "5"} and bins.width >= MS
    end = int(bins.edges()[-1])
    assert bins.count <= MAX_BINS and end >= START + span > end - bins.width


def test_the_rate_over_the_whole_span_is_monitors_and_a_pause_shows_as_its_length() -> None:
    stamps = START + np.concatenate([np.arange(0, 3000, 100), np.arange(5000, 8000, 100)]) * MS  # 10 Hz, 2.1 s pause
    whole = Bins(int(stamps[0]), int(stamps[-1] - stamps[0]), 1)
    assert local_rate(stamps, whole)[0] == pytest.approx((len(stamps) - 1) / 7.9)
    bins = bins_over(int(stamps[0]), int(stamps[-1]))
    middles = (bins.edges()[:-1] + bins.width // 2 - START) / NS_PER_S
    rate = local_rate(stamps, bins)
    assert np.allclose(rate[(middles > 0.1) & (middles < 2.8)], 10.0)
    assert np.allclose(rate[(middles > 3.0) & (middles < 4.9)], 1 / 2.1)
    assert np.isnan(local_rate(stamps[:1], bins)).all()


def test_a_steady_edge_keeps_its_rate_in_the_bins_its_span_starts_and_ends_in() -> None:
    stamps = START + 7 * MS + np.arange(0, 14_980, 20) * MS  # 50 Hz from 7 ms into a bin to 13 ms before one ends
    rate = local_rate(stamps, Bins(START, NS_PER_S, 16))
    assert rate[:15] == pytest.approx(np.full(15, 50.0))
    assert np.isnan(rate[15])


def test_each_edge_over_time_agrees_with_monitor_and_wtf() -> None:
    rec = recording(PROBLEMS["rate"].make())  # map -> odom silent from 3 s to 6 s
    span = edge_axis(rec.buffer, rec.timeline)
    assert span is not None
    bins = bins_over(*span)
    timelines = {e.key: e for e in edge_timelines(rec.buffer, rec.timeline, bins, 500 * MS)}
    stats = {s.key: s for s in edge_stats(rec.buffer, TimeWindow(timeline=rec.timeline))}
    for key, timeline in timelines.items():
        s = stats[key]
        if s.static:
            assert timeline.static and timeline.samples.sum() == 0 and np.isnan(timeline.rate_hz).all()
            continue
        assert timeline.samples.sum() == s.count
        weights = timeline.samples[timeline.samples > 0]
        delays = seconds(timeline.delay_mean)[timeline.samples > 0]
        assert np.average(delays, weights=weights) == pytest.approx(seconds(s.delay_mean))
        assert np.nanmax(seconds(timeline.delay_max)) == pytest.approx(seconds(s.delay_max))
    amcl = timelines[("map", "odom")]
    hist = rec.buffer.history("odom")
    assert hist is not None
    found = pauses(hist.stamps, 500 * MS)
    assert found is not None and amcl.pauses == ((found.first, found.last),)
    assert timelines[("odom", "base_link")].pauses == ()


def test_a_frame_on_another_clock_is_placed_at_its_arrival() -> None:
    rec = recording(PROBLEMS["clock"].make())  # odom -> base_link stamped from boot
    span = edge_axis(rec.buffer, rec.timeline)
    assert span is not None and span[0] >= START and span[1] <= START + 11 * NS_PER_S
    timelines = {e.key: e for e in edge_timelines(rec.buffer, rec.timeline, bins_over(*span), 500 * MS)}
    odom = timelines[("odom", "base_link")]
    assert odom.at_arrival and np.isnan(odom.delay_mean).all() and odom.samples.sum() == 500
    assert not timelines[("map", "odom")].at_arrival


def test_re_parentings_are_marked_on_both_edges() -> None:
    rec = recording(PROBLEMS["multiple_parents"].make())  # base_link under map too, from 5 s on
    span = edge_axis(rec.buffer, rec.timeline)
    assert span is not None
    timelines = {e.key: e for e in edge_timelines(rec.buffer, rec.timeline, bins_over(*span), 500 * MS)}
    changes = timelines[("odom", "base_link")].reparentings
    assert changes and changes == timelines[("map", "base_link")].reparentings
    assert changes[0].before == "odom" and changes[0].after == "map" and changes[0].time >= START + 5 * NS_PER_S


def test_sensor_fates_over_time_add_up_to_the_filters_counts() -> None:
    rec = recording(healthy())
    streams = [sensor("/camera", "camra", 10, 5 * MS), sensor("/scan", "laser", 20, 5 * MS, phase=0.007)]
    report = filter_streams(rec.buffer, streams, FilterQuery(target="odom"))
    bins = bins_over(START, START + 10 * NS_PER_S)
    flows = {f.report.topic: f for f in stream_timelines(rec.timeline, bins, streams, report)}
    for topic, flow in flows.items():
        r = flow.report
        assert flow.fates["on_arrival"].sum() == r.on_arrival and flow.fates["later"].sum() == r.later, topic
        assert flow.fates["lost"].sum() == r.never
        assert sum(f.sum() for f in flow.fates.values()) == r.messages
    assert flows["/camera"].fates["lost"].sum() == 100


def test_a_monitor_trace_keeps_each_refresh() -> None:
    rec = recording(PROBLEMS["stale"].make())  # odom -> base_link stops at 4 s
    trace = MonitorTrace()
    refreshes = [START + s * NS_PER_S for s in (2, 6, 9)]
    for now in refreshes:
        last_second = TimeWindow(now - NS_PER_S, now, by_record_time=True, timeline=rec.timeline)
        trace.add(now, monitor_buffer(rec.buffer, window=last_second))
    series = {(s.parent, s.child): s for s in trace.series()}
    assert list(series[("map", "odom")].times) == refreshes
    assert series[("map", "odom")].rate_hz == pytest.approx([10.0, 10.0, 10.0], rel=0.15)
    odom = series[("odom", "base_link")]
    assert odom.rate_hz[0] == pytest.approx(50.0, rel=0.1) and np.isnan(odom.rate_hz[1:]).all()


def test_many_timelines_share_a_bounded_number_of_bins() -> None:
    """20,000 moving edges over 10 s: 10 bins each, not 500 (the report took 1.45 GB and wrote 152 MB)."""
    one = bins_over(0, 10 * NS_PER_S)
    many = bins_over(0, 10 * NS_PER_S, rows=20_000)
    assert one.count == 500 and many.count == MIN_BINS
    assert bins_over(0, 10 * NS_PER_S, rows=1_000).count * 1_000 <= MAX_CELLS


WEEK = 7 * 86400 * NS_PER_S
AHEAD = 5 * 3600 * NS_PER_S


def _timelines(messages: list[TfMessage]) -> tuple[Bins, dict[tuple[str, str], EdgeTimeline]]:
    rec = recording(messages)
    bins = bins_over(*edge_axis(rec.buffer, rec.timeline))
    return bins, {e.key: e for e in edge_timelines(rec.buffer, rec.timeline, bins, 500 * MS)}


def test_an_edge_whose_publishers_stamp_a_week_apart_is_drawn_over_the_recording_at_both_rates() -> None:
    """The raspimouse replayed beside live gmapping: map -> odom from both, stamps a week apart. The axis spanned
    the week (2000 s bins), the edge at 1.7e-06 Hz in most; now the 10 s recorded, at the two publishers' 20 Hz."""
    replayed = periodic("/replay", 10, map_odom, stamp=lambda t: t - WEEK, phase=0.05)
    bins, timelines = _timelines(healthy(amcl=sorted(amcl() + replayed, key=lambda m: m.record_time)))
    assert bins.width * bins.count < 11 * NS_PER_S
    odom = timelines[("map", "odom")]
    assert odom.at_arrival and odom.samples.sum() == 200
    middle = odom.rate_hz[bins.count // 4 : 3 * bins.count // 4]
    assert middle == pytest.approx(np.full(len(middle), 20.0), rel=0.2)


def test_a_frame_stamped_on_a_clock_hours_ahead_is_placed_at_its_arrival() -> None:
    """The SAIL boat's IMU, broadcast from a machine 5.8 h ahead: by its stamps the axis ran 5.8 h for 15.9 s."""
    imu = periodic("/imu_tf", 50, lambda stamp: [_t("plane", "imu_link", stamp)], stamp=lambda t: t + AHEAD)
    bins, timelines = _timelines(healthy(wheels=imu))
    assert bins.width * bins.count < 11 * NS_PER_S
    assert timelines[("plane", "imu_link")].at_arrival and timelines[("plane", "imu_link")].samples.sum() == 500
    assert not timelines[("odom", "base_link")].at_arrival
