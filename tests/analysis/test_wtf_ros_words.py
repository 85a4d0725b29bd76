"""Issue 39 item 5: each hint names the tools and concepts of the recording's own ROS (as ``no_tf`` and
``leading_slash`` do): latched in ROS 1, transient local durability (QoS) in ROS 2, and each ROS's commands."""

from __future__ import annotations

import numpy as np
import pytest

from tests.analysis import wtf_scenes as scenes
from tests.analysis.wtf_scenes import PROBLEMS, recording, sim_clock, simulated
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import Scene, findings_of
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.sources.contents import ClockSamples


def _only(code: str, ros1: bool) -> Finding:
    (found,) = [f for f in check(recording(PROBLEMS[code].make(), ros1=ros1)).findings if f.code == code]
    return found


@pytest.mark.parametrize(
    ("ros1", "said", "unsaid"),
    [
        (True, ("latched", "rosbag play without -s"), ("transient local", "ros2 bag")),
        (False, ("transient local", "ros2 bag play without --start-offset"), ("latched", "rosbag play")),
    ],
    ids=["ros1", "ros2"],
)
def test_statics_only_at_the_start_are_repaired_in_the_recordings_own_words(
    ros1: bool, said: tuple[str, ...], unsaid: tuple[str, ...]
) -> None:
    hint = _only("statics_early", ros1).hint
    assert all(words in hint for words in said), hint
    assert not any(words in hint for words in unsaid), hint


#: Words only true of one ROS: its commands, and how it keeps /tf_static for late subscribers.
ROS1_WORDS = ("rosrun ", "roslaunch ", "rostopic ", "rosbag ", "rosparam ", "latched", "ros::Time", "ROS Hydro")
ROS2_WORDS = ("ros2 ", "transient local", "transient_local", "node->now()", "--qos-profile")


def _scenes() -> dict[str, tuple[list[TfMessage], ClockSamples | None, tuple[str, ...] | None]]:
    """Every designed problem, and simulations recorded on wall time (with and without /clock)."""
    made = {name: (p.make(), p.clock() if p.clock else None, p.topics) for name, p in PROBLEMS.items()}
    made["sim_on_wall_with_clock"] = (simulated(), sim_clock(), None)
    made["sim_on_wall"] = (simulated(), None, None)
    return made


SCENES = _scenes()


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
@pytest.mark.parametrize("name", list(SCENES))
def test_no_finding_speaks_of_the_other_ros(name: str, ros1: bool) -> None:
    """On each designed problem of each ROS, no message or hint names the other ROS's commands or concepts."""
    messages, clock, topics = SCENES[name]
    problem = PROBLEMS.get(name)
    streams = problem.streams() if problem is not None and problem.streams else ()
    findings = findings_of(Scene(recording(messages, topics, ros1=ros1, clock=clock), streams=streams))
    foreign = ROS2_WORDS if ros1 else ROS1_WORDS
    said = [(f.code, w) for f in findings for w in foreign if w in f.message + " " + f.hint]
    assert said == [], [f.hint for f in findings]


@pytest.mark.parametrize(
    ("ros1", "words"),
    [(True, "rosbag record with /use_sim_time true"), (False, "ros2 bag record --use-sim-time")],
    ids=["ros1", "ros2"],
)
def test_a_simulation_recorded_on_wall_time_is_told_its_own_recorders_way(ros1: bool, words: str) -> None:
    """ROS 2's recorder has --use-sim-time; ROS 1's follows /clock when /use_sim_time is true."""
    (note,) = [f for f in check(recording(simulated(), clock=sim_clock(), ros1=ros1)).findings if f.code == "clock"]
    assert words in note.hint, note.hint


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_tf_on_boot_time_without_clock_is_not_called_a_simulation_alone(ros1: bool) -> None:
    """Stamps since boot with no /clock come from a simulation recorded on wall time or from a real driver
    stamping on its own clock (a real Neato's): the note says both, and what to do for each."""
    (note,) = [f for f in check(recording(simulated(), ros1=ros1)).findings if f.code == "clock"]
    assert "or a driver stamping on its own clock" in note.message, note.message
    assert "a driver stamping on its own clock (time since boot): stamp with the ROS time" in note.hint, note.hint


@pytest.mark.parametrize(
    ("statics_at_s", "said"),
    [(0.0, "all in its first millisecond"), (2.5, "the last 2.5 s into it")],
    ids=["first-instant", "later"],
)
def test_statics_early_says_when_the_last_static_came_never_0_000_s(statics_at_s: float, said: str) -> None:
    """A real TurtleBot3's 22.7 min lap recorded its statics in its first instant, said as "the last 0.000 s
    into 22.7 min" (issue 39)."""
    statics = [scenes.statics(record=scenes.START + round(statics_at_s * NS_PER_S))]
    made = scenes.healthy(
        amcl=scenes.amcl(end=scenes.LONG), ekf=scenes.ekf(end=scenes.LONG), wheels=scenes.wheels(end=scenes.LONG)
    )
    messages = statics + [m for m in made if m.topic != "/tf_static"]
    (found,) = [f for f in check(recording(messages)).findings if f.code == "statics_early"]
    assert said in found.message and "0.000 s" not in found.message, found.message
    assert "only at the start of 70.0 s" in found.message, found.message


def _long_clock() -> ClockSamples:
    """The simulator's /clock at 100 Hz over the whole long recording (``sim_clock`` covers 10 s)."""
    wall = scenes.START + np.arange(round(scenes.LONG * 100)) * (NS_PER_S // 100)
    return ClockSamples("/clock", wall, wall - scenes.START + scenes.SIM_START)


@pytest.mark.parametrize("clock", ["record", "sim_clock", "none"])
def test_statics_early_places_its_times_on_the_stamps_clock_or_none(clock: str) -> None:
    """A real JetAcker's record times are 184 days from its stamps, with no /clock: statics_early's times were
    its record times, which the report showed as "1773339662.162 (another clock) to 1773339663.637 (another
    clock)" (issue 39). Its times are ROS time at arrival where that is known (the record clock itself where
    the stamps are on it; /clock's reading), none where not; the message and figures say them from the
    recording's start."""
    record = scenes.START + round(2.5 * NS_PER_S)
    on = {"stamp": scenes.sim} if clock != "record" else {}
    long = {"end": scenes.LONG, **on}
    made = scenes.healthy(amcl=scenes.amcl(**long), ekf=scenes.ekf(**long), wheels=scenes.wheels(**long))
    messages = [scenes.statics(record=record)] + [m for m in made if m.topic != "/tf_static"]
    found = check(recording(messages, clock=_long_clock() if clock == "sim_clock" else None)).findings
    (early,) = [f for f in found if f.code == "statics_early"]
    start = min(m.record_time for m in messages)
    # under /clock, the tick last heard: the first message came 2 ms after the first tick
    expected = {"record": (start, record), "sim_clock": (scenes.SIM_START, scenes.sim(record)), "none": (0, 0)}
    assert (early.first_time, early.last_time) == expected[clock], early
    assert early.figures == {
        "recording_s": (max(m.record_time for m in messages) - start) / NS_PER_S,
        "last_static_after_start_s": (record - start) / NS_PER_S,
    }
    assert "the last 2.5 s into it" in early.message, early.message


@pytest.mark.parametrize(("ros1", "words"), [(True, "rosbag play --clock"), (False, "ros2 bag play --clock")])
def test_epoch_stamps_days_behind_are_told_a_replay_not_a_simulation(ros1: bool, words: str) -> None:
    """CougUV's AUV (ros2_mcap_coug_auv_replayed, 6 days) and foxglove-wizard's drone flight (2018 stamps
    recorded in 2024): epoch stamps days behind the record clock are an earlier run replayed without its
    clock, not a simulation's time or a boot clock, which count from zero."""
    days = 6 * 86_400 * NS_PER_S

    def behind(t: int) -> int:
        return t - days

    messages = scenes.healthy(
        amcl=scenes.amcl(stamp=behind), ekf=scenes.ekf(stamp=behind), wheels=scenes.wheels(stamp=behind)
    )
    (note,) = [f for f in check(recording(messages, ros1=ros1)).findings if f.code == "clock"]
    assert note.hint.startswith("a replay of an earlier recording") and words in note.hint, note.hint
    assert "a simulation" not in note.hint
