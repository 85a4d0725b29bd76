"""A recording's timeline: each frame's clock medians as numpy's median gives them."""

from __future__ import annotations

import numpy as np
import pytest

from tftools import BatchBuilder, Buffer
from tftools.sources.contents import ClockSamples
from tftools.sources.edge_clocks import stamps_behind
from tftools.sources.timeline import seconds_since, timeline_of

START = 1_700_000_000 * 10**9


@pytest.mark.parametrize("rows", [1, 2, 7, 10])
@pytest.mark.parametrize("records_in_order", [True, False])
def test_edge_medians_are_exact(rows: int, records_in_order: bool) -> None:
    """Stamps far apart (np.median rounds their mean through a double, by up to 128 ns at 1.7e18 ns: a replay
    moved by such an offset played a transform stamped at its window's end after it), record times in or
    out of order: the middle value, or the middle two's mean towards zero, in integers."""
    rng = np.random.default_rng(rows)
    stamps = np.sort(START + rng.integers(0, 10**12, rows))
    records = stamps + rng.integers(1, 10**9, rows)
    if not records_in_order:
        records = records[::-1].copy()
    builder = BatchBuilder()
    for stamp, record in zip(stamps.tolist(), records.tolist(), strict=True):
        builder.add("odom", "base", stamp, (0, 0, 0), (0, 0, 0, 1), record_time=record)
    builder.add("base", "laser", START, (0, 0, 0), (0, 0, 0, 1), static=True, record_time=START)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    (edge,) = timeline_of(buffer, ClockSamples.empty(), START, START + 10**12).edges
    assert (edge.child, edge.arrivals) == ("base", rows)
    assert edge.median_stamp == _exact_median(stamps)
    assert edge.median_record == _exact_median(records)
    assert edge.offset_record == _exact_median(records - stamps)


def _exact_median(values: np.ndarray) -> int:
    ordered: list[int] = sorted(values.tolist())
    total = ordered[(len(ordered) - 1) // 2] + ordered[len(ordered) // 2]
    return total // 2 if total >= 0 else -(-total // 2)


def test_a_delay_read_off_a_ticking_clock_is_never_a_negative_one_its_steps_made() -> None:
    """/clock every 1 ms: a transform stamped 0.7 ms after a tick and received before the next reads
    -0.7 ms; its delay lies between that and a step more, and the value nearest zero there is 0."""
    ms = 10**6
    wall, sim = START, 100 * 10**9
    clock = ClockSamples("/clock", wall + np.arange(1000) * ms, sim + np.arange(1000) * ms)
    builder = BatchBuilder()
    for i in range(50):
        received = wall + i * 10 * ms + (900_000 if i % 2 else 5_900_000)
        builder.add("odom", "base", sim + i * 10 * ms + 700_000, (0, 0, 0), (0, 0, 0, 1), record_time=received)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    timeline = timeline_of(buffer, clock, wall, wall + 999 * ms)
    assert timeline.resolution == ms and timeline.delays_measured and timeline.delays_unavailable == ""
    history = buffer.history("base")
    assert history is not None
    delays = timeline.delays("base", history.stamps, history.record_times, history.flags)
    assert delays.tolist() == [4_300_000, 0] * 25
    coarse = timeline_of(buffer, ClockSamples("/clock", clock.record_time[::10], clock.clock[::10]), wall, wall)
    assert coarse.resolution == 10 * ms and not coarse.delays_measured
    assert len(coarse.delays("base", history.stamps, history.record_times, history.flags)) == 0
    assert coarse.delays_unavailable.startswith("ROS time at arrival is read off /clock, which ticks every 0.010 s")


def test_a_device_on_the_record_clock_beside_a_simulation_on_a_coarse_clock_has_its_delays() -> None:
    """ros2_db3_ias0220_gazebo_diff_cont_2025's shape: a simulated robot on a /clock ticking every 100 ms (its
    delays unmeasurable) beside a real device stamped on the wall clock, recorded 0.4 ms after its stamps: the
    device's delays are measured against its record times; the robot's stay unavailable, and the reason says
    which frames are measured."""
    ms = 10**6
    wall, sim = START, 1400 * 10**9
    clock = ClockSamples("/clock", wall + np.arange(100) * 100 * ms, sim + np.arange(100) * 100 * ms)
    builder = BatchBuilder()
    for i in range(200):
        builder.add("odom", "base", sim + i * 34 * ms, (0, 0, 0), (0, 0, 0, 1), record_time=wall + i * 34 * ms + ms)
    for i in range(90):
        stamp = wall + i * 100 * ms + 7 * ms
        builder.add("imu", "sonar", stamp, (0, 0, 0), (0, 0, 0, 1), record_time=stamp + 400_000)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    timeline = timeline_of(buffer, clock, wall, wall + 9_900 * ms)
    assert not timeline.delays_measured and timeline.record_clocked == {"sonar"} and timeline.delays_anywhere
    device, robot = buffer.history("sonar"), buffer.history("base")
    assert device is not None and robot is not None
    assert timeline.delays("sonar", device.stamps, device.record_times, device.flags).tolist() == [400_000] * 90
    assert len(timeline.delays("base", robot.stamps, robot.record_times, robot.flags)) == 0
    assert timeline.delays_unavailable.endswith(
        "those of sonar (stamped on the record clock) are measured against their record times"
    )
    assert timeline.record_window(sim + 1000 * ms, sim + 2000 * ms) == (wall + 1000 * ms, wall + 2100 * ms - 1)


def test_seconds_since_the_origin_only_on_its_time_base() -> None:
    assert seconds_since(START, START + 1_500_000_000) == 1.5
    assert seconds_since(START, 0) is None and seconds_since(5 * 10**9, START) is None
    assert seconds_since(5 * 10**9, 3 * 10**9) == -2.0


def test_stamps_days_behind_the_record_clock_are_said_in_days() -> None:
    """A replayed AUV (ros2_mcap_coug_auv_replayed): tf stamped 515,220 s before it was recorded, no /clock; the
    reason said "515219.9 s", which a person has to divide to read. Said in days; the exact offset stays
    ``stamps_behind``'s."""
    behind = 515_219_908_040_448
    builder = BatchBuilder()
    for i in range(20):
        stamp = START + i * 10**8
        builder.add("odom", "base", stamp, (0, 0, 0), (0, 0, 0, 1), record_time=stamp + behind)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    timeline = timeline_of(buffer, ClockSamples.empty(), START + behind, START + behind + 19 * 10**8)
    assert timeline.reason.startswith("tf is stamped 6.0 days before the record clock"), timeline.reason
    assert stamps_behind(timeline.edges) == behind


def test_without_a_record_clock_a_question_is_spanned_on_the_clock_its_frames_share() -> None:
    """The Logistic coBot's shape (ros2_db3_logistic_cobot_pymoveit2_zero_record_times_2024): a rosbag2_py writer
    gave every message a record time of 0 to 74 ns; an arm stamped from zero, two detections on epoch time, one
    seen from the start, one only in its last 3 s. Grouped by record time minus stamp (their median stamps, 11 s
    apart) the late one was a clock of its own: ``+1`` of its chain counted from its own first stamp, while
    view-frames aged it on the detections' clock. Now one grouping, the stamps': one clock, one span, one end."""
    s, ms = 10**9, 10**6
    epoch = 1_731_467_401 * s
    builder = BatchBuilder()
    for i in range(280):  # the arm's three joints: 46-74 s from zero, every 100 ms
        for parent, child in (("base_link_inertia", "shoulder_link"), ("shoulder_link", "upper_arm_link"),
                              ("upper_arm_link", "forearm_link")):  # fmt: skip
            builder.add(parent, child, 46 * s + i * 100 * ms, (0, 0, 0), (0, 0, 0, 1), record_time=46 + i % 28)
    for i in range(250):  # seen throughout: 25 s at 10 Hz
        builder.add("base_link", "obj_12", epoch + i * 100 * ms, (0, 0, 0), (0, 0, 0, 1), record_time=46 + i % 28)
    for i in range(30):  # seen only in the last 3 s: its median stamp 11 s after obj_12's
        builder.add("base_link", "obj_6", epoch + 22 * s + i * 100 * ms, (0, 0, 0), (0, 0, 0, 1), record_time=50)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    timeline = timeline_of(buffer, ClockSamples.empty(), 46, 74)
    assert timeline.record_clock_void
    detections = (epoch, epoch + 249 * 100 * ms)
    assert timeline.span_of(["obj_6"]) == timeline.span_of(["obj_12"]) == detections
    assert timeline.span_of(["shoulder_link"]) == (46 * s, 46 * s + 279 * 100 * ms)
    (other,) = timeline.other_clocks
    assert set(other.frames) == {"obj_6", "obj_12"} and (other.first, other.last) == detections
    assert timeline.own_clock_ends["obj_6"] == timeline.own_clock_ends["obj_12"]


def _void(frames: dict[str, list[int]]) -> list[list[str]]:
    """The frames grouped by clock (``Timeline.clocks``) where every record time is 0 to 74 ns (a rosbag2_py
    writer's), each frame stamped at ``frames[child]``."""
    builder = BatchBuilder()
    for child, stamps in frames.items():
        for k, stamp in enumerate(stamps):
            builder.add("base_link", child, stamp, (0, 0, 0), (0, 0, 0, 1), record_time=k % 75)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    timeline = timeline_of(buffer, ClockSamples.empty(), 0, 74)
    assert timeline.record_clock_void
    return sorted(sorted(e.child for e in group) for group in timeline.clocks)


def test_without_a_record_clock_a_pause_of_one_clock_is_one_clock() -> None:
    """Where record times are no clock, frames are grouped by their stamps alone (``stamp_groups``). One clock that
    paused 12 s (more than ``same_clock``, 10 s) with every frame on it is one clock: each frame's stamps span the
    pause. A frame that begins only after every other one stopped, 12 s later, is told apart: nothing in such a
    recording tells that from another clock, which is why ``tfx wtf`` calls two clocks only two time bases there
    (epoch time against time counted from zero), not these groups."""
    s = 10**9
    before, after = [START + i * s // 10 for i in range(50)], [START + 17 * s + i * s // 10 for i in range(50)]
    assert _void({"arm": before + after, "gripper": before + after}) == [["arm", "gripper"]]
    assert _void({"arm": before, "late": after}) == [["arm"], ["late"]]


def test_without_a_reference_arrivals_are_seconds_into_the_recording_and_findings_stay_on_the_stamps() -> None:
    """A simulation at 0.25x recorded without /clock, its recording begun 1 s before its first transform: odometry
    stamped every 50 ms from 10 s, received every 200 ms. ``arrival`` (monitor's windows, a replay) is the record
    clock with the recording's start at the first stamp: the 6th transform arrived 2.0 s into the recording, +2.0
    (moved by the frames' median offset, the 11th's, it read -1.5); ``arrival_on_stamps`` (a finding's
    times, the report's timelines) keeps the stamps, for no time of arrival is on their clock. With a reference
    (the same transforms stamped on the record clock) both are the record times."""
    ms, sim = 10**6, 10 * 10**9
    builder = BatchBuilder()
    for k in range(21):
        builder.add(
            "odom", "base", sim + k * 50 * ms, (0, 0, 0), (0, 0, 0, 1), record_time=START + (1000 + 200 * k) * ms
        )
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    history = buffer.history("base")
    assert history is not None
    timeline = timeline_of(buffer, ClockSamples.empty(), START, START + 5000 * ms)
    assert not timeline.available
    arrived = timeline.arrival(history.stamps, history.record_times)
    assert seconds_since(timeline.origin, int(arrived[5])) == pytest.approx(2.0)
    assert (timeline.arrival_on_stamps(history.stamps, history.record_times) == history.stamps).all()
    clocked = Buffer(cache_time=None)
    builder = BatchBuilder()
    for k in range(21):
        at = START + (1000 + 200 * k) * ms
        builder.add("odom", "base", at - 5 * ms, (0, 0, 0), (0, 0, 0, 1), record_time=at)
    clocked.insert(builder.take())
    record = timeline_of(clocked, ClockSamples.empty(), START, START + 5000 * ms)
    history = clocked.history("base")
    assert history is not None and record.available
    for placed in (record.arrival, record.arrival_on_stamps):
        assert (placed(history.stamps, history.record_times) == history.record_times).all()
