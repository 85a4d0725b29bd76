"""``sim_clock``'s times are on the stamps' clock, as every finding's (``Scene.ros_times``, the rule
``statics_early`` follows): a simulation recorded on wall-clock receive times (``ros2 bag record`` without
``--use-sim-time``) has its record times 1.7e9 s from its stamps; ``sim_clock`` gave those record times as its
first and last times, while ``statics_early`` and the others give ROS time. The message says which clock."""

from __future__ import annotations

import numpy as np

from tests.analysis.wtf_scenes import MS, SIM_START, START, recording, sim_clock, simulated
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.sources.contents import ClockSamples


def _sim_clock(clock: ClockSamples) -> list[Finding]:
    return [f for f in check(recording(simulated(), clock=clock, ros1=False)).findings if f.code == "sim_clock"]


def _paused(at_s: float, for_s: float) -> ClockSamples:
    """/clock at 100 Hz, silent for ``for_s`` s of wall time from ``at_s`` (the simulator stalled), then on
    from the reading it stopped at."""
    clock = sim_clock()
    wall, sim = clock.record_time.copy(), clock.clock.copy()
    later = wall > START + round(at_s * NS_PER_S)
    wall[later] += round(for_s * NS_PER_S)
    return ClockSamples(clock.topic, wall, sim)


def test_a_clock_going_back_is_timed_on_ros_time() -> None:
    (back,) = _sim_clock(sim_clock(back=(6.0, 0.5)))
    jumped = SIM_START + 6 * NS_PER_S - NS_PER_S // 2  # /clock's reading right after it went back
    assert (back.first_time, back.last_time) == (jumped, jumped)
    assert "first at 105.500 (+5.5 s) in ROS time" in back.message, back.message
    assert all(abs(t - START) > 1000 * NS_PER_S for t in (back.first_time, back.last_time))  # not record times


def test_a_clock_pausing_is_timed_on_ros_time_and_its_length_on_the_record_clock() -> None:
    (paused,) = _sim_clock(_paused(4.0, 3.0))
    stopped = SIM_START + 4 * NS_PER_S - 10 * MS  # its last reading before the pause (the simulation stood still)
    assert (paused.first_time, paused.last_time) == (stopped, stopped + 10 * MS), paused  # and its next one after
    assert "the longest for 3.0 s (record clock) from 103.990 (+4.0 s) in ROS time" in paused.message, paused.message


def test_a_clock_pausing_before_any_tf_arrived_is_the_simulator_starting_not_a_pause() -> None:
    """The roomba walker's Gazebo (corpus ros2-turtlebot3-gazebo-roomba-walker-clock-at-sim-start-2023-db3):
    /clock 0.093 then 0.169 s, 1.02 s of record time apart, its first tf 33 ms after the second tick. Nothing
    was stamped on that clock yet, so no lookup or timer waited: no warning. The same pause once tf flows is one."""
    clock = sim_clock()
    wall = clock.record_time - 2 * NS_PER_S  # /clock from 2 s before the first tf, silent 1 s of it
    wall[wall < START - NS_PER_S // 2] -= NS_PER_S
    started = ClockSamples(
        clock.topic,
        np.concatenate(([wall[0] - NS_PER_S], wall)),
        np.concatenate(([clock.clock[0] - 10 * MS], clock.clock)),
    )
    assert not _sim_clock(started)
    assert _sim_clock(_paused(4.0, 3.0))
