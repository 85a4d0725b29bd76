"""Re-sends told apart from what they are not, on the shapes of recordings nobody here had seen (issue 39):
a SLAM node re-sending its latest correction to the end is not stale, a joint stepping is not a
localization correction, a sample delivered again is not one out of order; and ``tfx monitor`` counts the
messages a publisher sent, re-sent ones too, the same in a whole read and a replay."""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import pytest

from tests.analysis.wtf_scenes import MS, SECONDS, SIM_START, START, _t, periodic, recording, statics
from tests.bags import BagFormat, ClockMessage, TfMessage, write_bag
from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

#: A simulation at 1/15 of real time (ros2_db3_jetacker_slam_toolbox_static_map's ran at 0.067x).
SLOW = 15


def _slow(t: int) -> int:
    return SIM_START + (t - START) // SLOW


def _slam(t: int) -> list[Transform]:
    """slam_toolbox's map -> odom, sent every 20 ms of wall time with the stamp of its latest scan (one
    every 0.14 s of simulated time, 2.1 s of wall time here): each stamp re-sent ~105 times, identical."""
    scan = _slow(t) - (_slow(t) - SIM_START) % (140 * MS)
    return [_t("map", "odom", scan, 0.01 * ((scan - SIM_START) // (140 * MS)))]


def _slam_run() -> list[TfMessage]:
    def odometry_at(stamp: int) -> list[Transform]:
        return [_t("odom", "base_link", stamp, 0.4 * (stamp - SIM_START) / NS_PER_S)]

    odometry = periodic("/tf", 30, odometry_at, stamp=_slow)
    slam = periodic("/tf", 50, _slam, delay=3 * MS)  # its stamps come from _slow already
    return sorted([statics(), *odometry, *slam], key=lambda m: m.record_time)


def _codes(findings: list[Finding]) -> set[str]:
    return {f.code for f in findings}


def test_a_correction_re_sent_to_the_end_is_not_stale() -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map: map -> odom's newest stamp first arrived 1.4 s before the
    recording's end and was re-sent every 20 ms until it: 'stopped at 18.800, 1.4 s before the recording
    ends' was an error about a publisher that never stopped (ROS 2's tf2 stores an identical sample once)."""
    findings = check(recording(_slam_run(), ros1=False)).findings
    assert "stale" not in _codes(findings), [f.message for f in findings if f.code == "stale"]


def test_a_correction_re_sent_with_a_stamp_frozen_behind_its_clock_is_still_stale() -> None:
    """The same re-sends, but the odometry's clock went on 5 s past the correction's last stamp: stale, said
    as a stamp that stopped advancing while the transform was still sent."""
    late = START + 4 * NS_PER_S
    frozen = [m for m in _slam_run() if not (m.transforms[0].child_frame_id == "odom" and m.record_time > late)]
    last = max(m.transforms[0].stamp for m in frozen if m.transforms[0].child_frame_id == "odom")
    resent = [TfMessage("/tf", START + 4 * NS_PER_S + k * 20 * MS + 1, [_t("map", "odom", last, 0.01)], "/tf")
              for k in range(300)]  # fmt: skip
    fast = periodic("/tf", 30, lambda s: [_t("odom", "base_link", s, 0.1)], stamp=lambda t: SIM_START + (t - START))
    messages = [m for m in frozen if m.transforms[0].child_frame_id != "base_link"] + resent + fast
    findings = check(recording(sorted(messages, key=lambda m: m.record_time), ros1=False)).findings
    (stale,) = [f for f in findings if f.code == "stale"]
    assert stale.frames == ("map", "odom") and "stopped advancing" in stale.message and "re-sent" in stale.message


def _joints(flip_every: int) -> list[TfMessage]:
    """robot_state_publisher's two joints of an Ackermann robot in each message: steering and a wheel, the
    wheel's angle from two /joint_states sources taking turns every ``flip_every`` messages (one says 0)."""
    messages = []
    for k in range(int(SECONDS * 20)):
        t = START + k * 50 * MS
        angle = 0.0 if (k // flip_every) % 2 else 2.0 * k / 20
        steer = Transform.from_rpy((0, 0, -0.1), (0, 0, 0.1 * math.sin(k / 40)), t, "base_link", "steer")
        roll = Transform.from_rpy((0, 0, 0.17), (angle, 0, 0), t, "steer", "wheel")
        messages.append(TfMessage("/tf", t + 2 * MS, [steer, roll], "/tf"))
    return messages


def test_a_joint_stepping_is_told_about_joint_states_not_localization() -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map: bottom_wheel_base_link -> wheel_link (sent with three other
    joints in every message) stepped 29 times; the hint said to publish a localization correction as
    map -> odom."""
    findings = check(recording(sorted([statics(), *_joints(3)], key=lambda m: m.record_time), ros1=False)).findings
    (jump,) = [f for f in findings if f.code == "jump"]
    assert jump.frames == ("steer", "wheel")
    assert "/joint_states" in jump.hint and "map -> odom" not in jump.hint


def test_a_localizer_stepping_alone_keeps_the_correction_hint() -> None:
    def corrected(t: int) -> list[Transform]:
        second = (t - START) // NS_PER_S
        return [_t("base_link", "tracker", t, 0.01 * second + (0.5 if second == 5 else 0.0))]

    messages = sorted([statics(), *periodic("/tf", 20, corrected)], key=lambda m: m.record_time)
    findings = check(recording(messages, ros1=False)).findings
    (jump,) = [f for f in findings if f.code == "jump"]
    assert "map -> odom" in jump.hint


def _wheel_and_body(times: Sequence[float], angle_at: Callable[[float], float]) -> list[TfMessage]:
    """robot_state_publisher's messages at ``times`` (seconds): a wheel at ``angle_at(seconds)`` radians beside
    a caster that never moves (so that the wheel is a joint: it comes in messages with other edges)."""
    messages = []
    for seconds in times:
        t = START + round(seconds * NS_PER_S)
        roll = Transform.from_rpy((0, 0.12, 0.03), (angle_at(seconds), 0, 0), t, "base_link", "wheel")
        caster = Transform.from_rpy((-0.1, 0, 0.01), (0, 0, 0), t, "base_link", "caster")
        messages.append(TfMessage("/tf", t + MS, [roll, caster], "/tf"))
    return sorted([statics(), *messages], key=lambda m: m.record_time)


def _every(seconds: float) -> list[float]:
    return [k * seconds for k in range(int(SECONDS / seconds))]


def _nudged(seconds: float) -> float:
    """A wheel at rest, turned 0.55 rad in half a second at 5 s (the robot nudged), at rest again."""
    return 0.0 if seconds < 5 else 0.55 if seconds >= 5.5 else 0.55 * (1 - math.cos(math.pi * (seconds - 5) / 0.5)) / 2


#: Sample times 0.1 s apart but one interval in four of 0.13 s, as a Unity robot's ROS-TCP endpoint sent them.
UNEVEN = list(itertools.accumulate([0.1, 0.1, 0.1, 0.13] * 25, initial=0.0))


@pytest.mark.parametrize(
    ("times", "angle_at"),
    [
        (_every(0.25), _nudged),
        (UNEVEN, lambda seconds: 63.0 * seconds),
        (_every(1 / 2.4), lambda seconds: math.radians(165.0) * 2.4 * seconds),
    ],
    ids=["stopped-between-samples", "a-turn-a-sample", "nearly-half-a-turn-a-sample"],
)
def test_a_joint_moving_faster_than_its_samples_is_no_jump(
    times: list[float], angle_at: Callable[[float], float]
) -> None:
    """A real TurtleBot2's wheels at 4.2 Hz (a nudge: 0.7, -7.3, -31.4, -18.4, 0 degrees a sample) and a Unity
    robot's wheels (about a turn a sample at 2 m/s, seen modulo a turn: the longer intervals look like steps)
    were said to jump, with the hint of two /joint_states sources taking turns: a step that neither leaves a
    position the joint comes back to nor comes back to one it held is motion too fast for its samples. So is a
    real Neato's wheel turning 150-177 degrees a sample at 2.4 Hz (ros2_db3_neato_obstacle_avoider_burst_2023,
    which ``multiple_authorities`` once took for two places): near where it was two samples before, each time
    further on, never back to a place it held (unlike the JetAcker's wheel toggling between rest and 2.1 rad)."""
    findings = check(recording(_wheel_and_body(times, angle_at), ros1=True)).findings
    assert "jump" not in _codes(findings), [f.message for f in findings if f.code == "jump"]


def _driven_alone(parent: str, child: str) -> list[TfMessage]:
    """A real Neato's driver at 8.5 Hz sending each transform in a message of its own
    (ros2_db3_neato_real_checkpoint_joloujo_2023): ``parent -> child`` about a fixed origin at rest for 5 s,
    turned 157 degrees between two samples (the wheel, as the base then moved 0.097 m), at rest again."""

    def turned(t: int) -> list[Transform]:
        angle = math.radians(157.0) if t - START >= 5 * NS_PER_S else 0.0
        return [Transform.from_rpy((0.0, 0.12, 0.03), (0.0, angle, 0.0), t, parent, child)]

    def base(t: int) -> list[Transform]:
        return [_t("odom", "base_footprint", t, 0.097 if t - START >= 5 * NS_PER_S else 0.0)]

    messages = periodic("/tf", 8.5, turned) + periodic("/tf", 8.5, base, delay=3 * MS)
    return sorted([statics(), *messages], key=lambda m: m.record_time)


def test_a_wheel_sent_alone_turning_between_samples_is_no_jump() -> None:
    """ros2_db3_neato_real_checkpoint_joloujo_2023: the driver sends each wheel in a message of its own, so it was
    not taken for a joint, and each wheel's 157-158 degree turn between two samples (the turn the base's 0.097 m
    step takes) was said to jump: an edge turning about a fixed origin is a joint, its angle seen modulo a turn."""
    findings = check(recording(_driven_alone("base_footprint", "wheel_left_link"), ros1=False)).findings
    assert not [f for f in findings if f.code == "jump" and f.frames[1] == "wheel_left_link"], [
        f.message for f in findings if f.code == "jump"
    ]


def test_a_heading_alone_under_odom_stepping_still_jumps() -> None:
    """The same step on an orientation-only odometry (odom -> base_link, its origin fixed): a localizer's heading,
    not a joint, so its step that stays is a jump."""
    findings = check(recording(_driven_alone("odom", "base_link"), ros1=False)).findings
    assert any(f.code == "jump" and f.frames == ("odom", "base_link") for f in findings), [f.message for f in findings]


def test_a_joint_out_and_back_for_one_sample_still_jumps() -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map's steering: pi for one sample, then back where it was (here
    on a joint that goes on moving slowly, so that it comes back near, not to, the position it left)."""
    one_sample = _wheel_and_body(_every(0.1), lambda s: math.pi if 4.95 < s < 5.05 else 0.1 * s)
    (jump,) = [f for f in check(recording(one_sample, ros1=True)).findings if f.code == "jump"]
    assert jump.frames == ("base_link", "wheel") and "/joint_states" in jump.hint
    assert "jumped once, out and back, further" in jump.message and jump.count == 2, jump.message


def test_a_joints_step_out_and_its_step_back_are_one_jump() -> None:
    """The JetAcker slam_toolbox recording's steering was at 180 degrees for one sample, said as "jumped 2 times"
    (issue 39): a step out and the step back within ``BACK_WITHIN`` samples are one excursion; two spikes are
    two."""
    spikes = _wheel_and_body(_every(0.1), lambda s: math.pi if min(abs(s - 3), abs(s - 5)) < 0.05 else 0.1 * s)
    (jump,) = [f for f in check(recording(spikes, ros1=True)).findings if f.code == "jump"]
    assert "jumped 2 times, each out and back, further" in jump.message and jump.count == 4, jump.message


def test_a_localizers_spike_and_step_that_stays_are_told_apart() -> None:
    """A one-sample spike (3 s) and a step that stays (6 s) on an edge sent alone: two jumps, one out and back."""

    def tracked(t: int) -> list[Transform]:
        s = (t - START) / NS_PER_S
        return [_t("base_link", "tracker", t, 0.001 * s + (0.5 if abs(s - 3) < 0.01 or s > 5.99 else 0.0))]

    messages = sorted([statics(), *periodic("/tf", 20, tracked)], key=lambda m: m.record_time)
    (jump,) = [f for f in check(recording(messages, ros1=False)).findings if f.code == "jump"]
    assert "jumped 2 times (1 of them out and back) further" in jump.message and jump.count == 3, jump.message


def _delivered_again(new_out_of_order: bool) -> list[TfMessage]:
    """A joint at 10 Hz over a lossy link that, every second, delivers the last two messages again 60 ms
    later (ros2_db3_jetacker_real_stamps_back: 12 of base_link -> link1's 19 late arrivals were identical
    to ones received); with ``new_out_of_order``, one new message every second arrives after a newer one."""
    messages = []
    for k in range(100):
        t = START + k * 100 * MS
        messages.append(TfMessage("/tf", t + 2 * MS, [_t("base_link", "link1", t, 0.03)], "/tf"))
        if k % 10 == 9 and k > 1:
            for back in (1, 0):
                again = START + (k - back) * 100 * MS
                messages.append(TfMessage("/tf", t + 60 * MS + back, [_t("base_link", "link1", again, 0.03)], "/tf"))
        if new_out_of_order and k % 10 == 5:
            messages.append(TfMessage("/tf", t + 3 * MS, [_t("base_link", "link1", t - 50 * MS, 0.03)], "/tf"))
    return sorted([statics(), *messages], key=lambda m: m.record_time)


def test_samples_delivered_again_are_not_out_of_order() -> None:
    findings = check(recording(_delivered_again(False), ros1=False)).findings
    assert "time_backwards" not in _codes(findings), [f.message for f in findings]


def test_new_samples_out_of_order_are_counted_without_those_delivered_again() -> None:
    findings = check(recording(_delivered_again(True), ros1=False)).findings
    (late,) = [f for f in findings if f.code == "time_backwards"]
    assert "10 transforms arrived out of order" in late.message


def _monitor(tfx: Tfx, tmp_path: Path, messages: list[TfMessage], play: bool) -> dict[str, Any]:  # noqa: F811
    """``tfx monitor -f json`` on ``messages`` written as a rosbag2 .db3, read whole or replayed (its last table)."""
    bag = write_bag(tmp_path / "slam", messages, BagFormat.rosbag2_sqlite3)
    window = ["--play", "--rate", "500", "--window", "100"] if play else []
    result = tfx("monitor", "-b", bag, "-f", "json", *window)
    assert result.code == 0, result.stderr
    report: dict[str, Any] = json.loads(result.stdout.splitlines()[-1] if play else result.stdout)
    return report


@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_monitor_counts_the_messages_a_slam_node_re_sent(tfx: Tfx, tmp_path: Path, play: bool) -> None:  # noqa: F811
    """ros2_db3_jetacker_slam_toolbox_static_map: /tf held 3,376 messages, 3,142 of them slam_toolbox's
    re-sends; monitor said 278 (the distinct samples tf2 stored), and with --play showed no moving edge at
    all (its last window, on the replay's clock, was compared with the stamps of a 0.067x simulation)."""
    messages = _slam_run()
    report = _monitor(tfx, tmp_path, messages, play)
    publishers = {a["authority"]: a for a in report["authorities"]}
    assert publishers["/tf"]["messages"] == sum(m.topic == "/tf" for m in messages)
    assert {e["child"] for e in report["edges"] if not e["static"]} == {"odom", "base_link"}


def test_a_stamp_re_valued_then_re_sent_is_one_stamp() -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map: slam_toolbox sent map -> odom at 15.020 twice as identity,
    then its new correction at that same stamp 77 times; 'sent 77 transforms with a stamp it had already
    sent' counted the re-sends of one new value as 77 updates."""

    def revalued(t: int) -> list[Transform]:
        stamp = START + (t - START) // NS_PER_S * NS_PER_S  # a new stamp each second, re-sent at 50 Hz
        fixed = (t - START) % NS_PER_S >= 500 * MS and stamp == START + 5 * NS_PER_S
        return [_t("map", "odom", stamp, 0.01 if fixed else 0.0)]

    messages = sorted([statics(), *periodic("/tf", 50, revalued)], key=lambda m: m.record_time)
    (again,) = [f for f in check(recording(messages, ros1=False)).findings if f.code == "time_backwards"]
    assert "1 stamp it had already sent came again with other values (25 transforms)" in again.message


@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_monitor_counts_a_static_message_ros2s_tf2_replaced(tfx: Tfx, tmp_path: Path, play: bool) -> None:  # noqa: F811
    """ros2_db3_jetacker_slam_toolbox_static_map: /tf_static held 2 messages, the second an identity map -> odom
    that slam_toolbox's map -> odom on /tf then replaced in ROS 2's tf2 (the frame's cache switches topics);
    monitor said 1 (and --play 0: that message, recorded long before /tf began on a simulation's clock,
    played at a time before the replay clock's 0, taken for unknown). Messages are what was sent and recorded,
    whatever tf2 then kept."""
    early = TfMessage("/tf_static", START - 110 * NS_PER_S, [_t("map", "odom", START - 229 * NS_PER_S)], "/tf_static")
    messages = [early, *_slam_run()]
    report = _monitor(tfx, tmp_path, messages, play)
    publishers = {a["authority"]: a for a in report["authorities"]}
    assert publishers["/tf_static"]["messages"] == sum(m.topic == "/tf_static" for m in messages) == 2
    assert ["map", "odom"] in publishers["/tf_static"]["edges"]
    assert publishers["/tf"]["messages"] == sum(m.topic == "/tf" for m in messages)


@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_monitor_counts_static_messages_recorded_before_the_first_clock(tfx: Tfx, tmp_path: Path, play: bool) -> None:  # noqa: F811
    """ros2_db3_tb3_gazebo_two_rsp (and ros2_db3_webots_epuck): /tf_static messages recorded before the
    simulation's first /clock all play at one time, so --play counted them as 1 message (2 and 8 were sent):
    a publisher sent at least as many messages as one of its edges had samples, on /tf_static as on /tf."""
    laser = [_t("base_link", "laser", 0)]
    statics_sent = [TfMessage("/tf_static", START + i * MS, laser, "/tf_static") for i in range(3)]
    ticks = range(1, 101)
    clock = [ClockMessage(START + 100 * MS + i * 20 * MS, SIM_START + i * 20 * MS) for i in ticks]
    odometry = [
        TfMessage("/tf", START + 100 * MS + i * 20 * MS + MS, [_t("odom", "base_link", SIM_START + i * 20 * MS)])
        for i in ticks
    ]
    bag = write_bag(tmp_path / "sim", [*statics_sent, *odometry], BagFormat.rosbag2_sqlite3, clock=clock)
    window = ["--play", "--rate", "500", "--window", "100"] if play else []
    result = tfx("monitor", "-b", bag, "-f", "json", *window)
    assert result.code == 0, result.stderr
    report = json.loads(result.stdout.splitlines()[-1] if play else result.stdout)
    publishers = {a["authority"]: a["messages"] for a in report["authorities"]}
    assert publishers == {"/tf_static": 3, "/tf": 100}


def test_a_localizer_sending_odom_with_map_in_one_message_is_no_joint() -> None:
    """ros1_okoslam_cartographer_2019-05-12-18-44-11.bag: cartographer sends map -> odom and odom -> base_link in
    every message (it provides the odom frame), so odom -> base_link was taken for a state publisher's joint and
    its heading turning 21.8 degrees in one step, and staying, was dropped as motion too fast for its samples.
    Edges under odom sent only with map -> odom are a localizer's output: the step is a jump. A state
    publisher's odom edge sent with the robot's joints (a Unity robot's whole tree in one message) stays one."""

    def localizer(t: int) -> list[Transform]:
        yaw = math.radians(21.8) if t - START >= 5 * NS_PER_S else 0.0
        return [_t("map", "odom", t), _t("odom", "base_link", t, 0.01 * (t - START) / NS_PER_S, yaw)]

    messages = sorted([statics(), *periodic("/cartographer", 50, localizer)], key=lambda m: m.record_time)
    (jump,) = [f for f in check(recording(messages, ros1=True)).findings if f.code == "jump"]
    assert jump.frames == ("odom", "base_link") and "REP 105" in jump.hint

    def whole_tree(t: int) -> list[Transform]:
        wheel = Transform.from_rpy((0, 0.12, 0.03), (0, 0, 0), t, "base_link", "wheel")
        return [*localizer(t), wheel]

    messages = sorted([statics(), *periodic("/unity", 50, whole_tree)], key=lambda m: m.record_time)
    assert "jump" not in _codes(check(recording(messages, ros1=True)).findings)


def _re_valued(t: int) -> list[Transform]:
    """A new stamp each second, re-sent at 50 Hz; the one at +5 s takes a new value half-way through its
    second (slam_toolbox's map -> odom in ros2_db3_jetacker_slam_toolbox_static_map)."""
    stamp = START + (t - START) // NS_PER_S * NS_PER_S
    fixed = (t - START) % NS_PER_S >= 500 * MS and stamp == START + 5 * NS_PER_S
    return [_t("odom", "base_link", stamp, 0.01 if fixed else 0.0)]


@pytest.mark.parametrize("ahead", [False, True], ids=["alone", "beside-a-clock-ahead"])
def test_ros2s_tf2_refuses_samples_older_than_its_cache_before_it_compares_stamps(ahead: bool) -> None:
    """ROS 2's ``TimeCache::insertData`` (rolling, humble) refuses a sample more than its cache behind the
    frame's newest (TF_OLD_DATA) before it looks for a sample at that stamp, as ROS 1's does: after one
    sample on another tf topic stamped 5 h ahead, each of the stream's samples is refused, none kept twice.
    Alone, ROS 2's tf2 keeps both values of the stamp that came again, and time_backwards says so."""
    camera = periodic("/tf", 50, _re_valued)
    arrived = START + 2 * NS_PER_S + 5 * MS
    ekf = [TfMessage("/ekf/tf", arrived, [_t("odom", "base_link", arrived + 5 * 3600 * NS_PER_S)], "/ekf/tf")]
    messages = sorted([statics(), *camera, *(ekf if ahead else [])], key=lambda m: m.record_time)
    findings = check(recording(messages, topics=("/tf", "/tf_static", "/ekf/tf"), ros1=False)).findings
    again = [f for f in findings if f.code == "time_backwards" and "came again with other values" in f.message]
    assert bool(again) is not ahead, [f.message for f in findings]
    for f in again:  # ROS 2's words: cache.cpp's insertData keeps both, the last received before the first
        assert "ROS 2's tf2 keeps every value (it has no TF_REPEATED_DATA)" in f.message, f.message
        assert "answer from the one received last (the first while it is the oldest stamp held)" in f.message


@pytest.mark.parametrize("grows", [False, True], ids=["the same", "grown"])
def test_a_static_publisher_told_apart_is_said_to_repeat_what_it_repeated(grows: bool) -> None:
    """A copy ``tfx static --repair`` wrote of the real Create 3 (two descriptions on /tf_static, no publisher
    named): its second publisher's first message held 23 transforms, its 9 re-sends the merged 35, and
    static_conflict said "(the same 10 times)". Its words now say what the later messages held; a publisher
    that re-sends its first message is still "the same N times"."""
    frames = ["a", "b", "c"]
    driver = [_t("base_link", f, START, 0.3) for f in frames[:2]]
    later = [*driver, _t("base_link", "c", START, 0.1)] if grows else driver
    messages = periodic("/tf", 20, lambda stamp: [_t("odom", "base_link", stamp, 0.01 * (stamp - START) / NS_PER_S)])
    messages.append(TfMessage("/tf_static", START + 10 * MS, [_t("base_link", f, START, 0.1) for f in frames]))
    messages.append(TfMessage("/tf_static", START + 500 * MS, driver))
    messages += [TfMessage("/tf_static", START + k * 2 * NS_PER_S, later) for k in (1, 2, 3)]
    findings = check(recording(sorted(messages, key=lambda m: m.record_time), ros1=False)).findings
    (conflict,) = [f for f in findings if f.code == "static_conflict"]
    said = "(3 more messages with up to 3 transforms)" if grows else "(the same 4 times)"
    assert f"publisher 2: 2 transforms at 1700000000.500 (+0.5 s) {said}" in conflict.message, conflict.message


@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_monitor_says_what_a_publishers_delay_is_over_where_it_re_sent(tfx: Tfx, tmp_path: Path, play: bool) -> None:  # noqa: F811
    """Gazebo's drone pose re-sent on 1 ms sim ticks (corpus, tests/corpus/test_diff43.py): ROS 1's tf2 refuses a
    stamp sent again, so the edge's delay is over the samples it stored and the publisher's over every one it
    sent (tf_monitor's Node line), later re-sends among them. The two differ, each right: the JSON says over how
    many transforms the publisher's is, and how many of them no edge's delay holds; the table says it in a line."""

    def odometry(stamp: int) -> list[Transform]:
        return [_t("odom", "base_link", stamp, 0.001 * (stamp - START) / MS)]

    first = periodic("/ekf", 10, odometry, delay=2 * MS)
    again = periodic("/ekf", 10, odometry, delay=30 * MS)
    messages = sorted([statics(), *first, *again], key=lambda m: m.record_time)
    bag = write_bag(tmp_path / "resent.bag", messages, BagFormat.ros1)
    window = ["--play", "--rate", "500", "--window", "100"] if play else []
    result = tfx("monitor", "-b", bag, "-f", "json", *window)
    report = json.loads(result.stdout.splitlines()[-1] if play else result.stdout)
    (ekf,) = [a for a in report["authorities"] if a["authority"] == "/ekf"]
    (edge,) = [e for e in report["edges"] if e["child"] == "base_link"]
    assert (ekf["delays_counted"], ekf["delays_beyond_edges"]) == (2 * len(first), len(first)), ekf
    assert edge["delay_mean_s"] < ekf["delay_mean_s"]  # 2 ms, against the mean of 2 and 30 ms
    text = " ".join(tfx("monitor", "-b", bag).stdout.split())
    assert (
        f"/ekf: its delays are over the {2 * len(first)} transforms it sent on /tf (tf_monitor's Node line), " in text
    )
    (rsp,) = [a for a in report["authorities"] if a["authority"] == "/rsp"]
    assert rsp["delays_beyond_edges"] == 0 and "/rsp: its delays" not in text
