"""The checker on recordings made to show one problem each: the finding it must give, and silence otherwise."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from tests.analysis.wtf_scenes import (
    DELAY,
    MS,
    PROBLEMS,
    SECONDS,
    START,
    _s,
    _t,
    amcl,
    ekf,
    healthy,
    odom_base,
    periodic,
    recording,
    sim,
    sim_clock,
    simulated,
    statics,
    wheel,
    wheels,
    with_extra,
)
from tests.bags import TfMessage
from tftools.analysis.findings import Finding, Severity, causes
from tftools.analysis.wtf import CHECKS, Scene, Thresholds, findings_of, timing
from tftools.analysis.wtf.fleet import check
from tftools.analysis.wtf.query import CheckQuery
from tftools.analysis.wtf.rows import rows_of
from tftools.core.errors import ExtrapolationError, TransformError
from tftools.core.rejection import RejectionCode
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.contents import ClockSamples


def loud(findings: list[Finding]) -> list[Finding]:
    """The findings a verdict counts (those that follow from another are counted with it), but notes."""
    return [f for f in causes(findings) if f.severity is not Severity.info]


def only(findings: list[Finding], code: str) -> Finding:
    found = [f for f in findings if f.code == code]
    assert len(found) == 1, findings
    return found[0]


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_a_healthy_robot_gives_no_finding_at_all(ros1: bool) -> None:
    assert check(recording(healthy(), ros1=ros1)).findings == []


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
@pytest.mark.parametrize("name", list(PROBLEMS))
def test_each_problem_gives_exactly_its_finding_naming_frames_and_publisher(name: str, ros1: bool) -> None:
    problem = PROBLEMS[name]
    clock = problem.clock() if problem.clock else None
    streams = problem.streams() if problem.streams else ()
    findings = findings_of(Scene(recording(problem.make(), problem.topics, ros1=ros1, clock=clock), streams=streams))
    if problem.ros1_only and not ros1:
        assert [f.code for f in loud(findings)] == ([problem.ros2_code] if problem.ros2_code else []), findings
        return
    shown = findings if problem.severity == "info" else loud(findings)
    assert [f.code for f in shown] == [problem.code], findings
    finding = findings[0]
    assert finding.severity.value == problem.severity
    assert set(problem.frames) <= set(finding.frames)
    for frame in problem.frames:
        assert frame in finding.message
    for word in problem.words:
        assert word in finding.message + finding.hint
    if ros1 and problem.publisher:
        assert problem.publisher in finding.authorities and problem.publisher in finding.message
    assert finding.hint and "\n" not in finding.message
    assert finding.first_time <= finding.last_time


@pytest.mark.parametrize("with_clock", [True, False], ids=["clock", "no_clock"])
def test_a_simulation_recorded_on_wall_time_gives_only_a_note(with_clock: bool) -> None:
    """ros2 bag record without --use-sim-time: stamps on sim time, receive times on wall time."""
    findings = check(recording(simulated(), clock=sim_clock() if with_clock else None, ros1=False)).findings
    assert loud(findings) == []
    note = only(findings, "clock")
    assert note.severity is Severity.info
    if with_clock:
        assert "without --use-sim-time" in note.message
    else:
        assert "a simulation recorded on wall time" in note.message
        assert "cannot be measured" in note.message


def test_a_simulation_recorded_on_sim_time_gives_no_finding() -> None:
    """ros2 bag record --use-sim-time: receive times and /clock on simulated time, like the stamps."""
    messages = [dataclasses.replace(m, record_time=sim(m.record_time)) for m in simulated()]
    clock = sim_clock()
    on_sim = ClockSamples(clock.topic, clock.clock + MS, clock.clock)
    assert check(recording(messages, clock=on_sim)).findings == []


def test_delays_are_measured_against_the_recorded_clock() -> None:
    """With /clock, a late frame is late in simulated time, whatever the receive times' clock."""
    messages = simulated(ekf=ekf(stamp=lambda t: sim(t) - 400 * MS))
    finding = only(check(recording(messages, clock=sim_clock())).findings, "delay")
    assert "odom -> base_link" in finding.message and "median 0.400 s" in finding.message


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_a_joint_at_rest_among_moving_joints_is_not_a_static_transform_on_tf(ros1: bool) -> None:
    """robot_state_publisher sends every movable joint in one message: a finger that did not move is no mistake."""
    finger = _t("base_link", "finger", START, 0.05)
    joints = periodic("/rsp", 20, lambda t: [*wheel(t), dataclasses.replace(finger, stamp=t)])
    assert check(recording(healthy(wheels=joints), ros1=ros1)).findings == []
    resting = periodic("/robot_state_publisher", 15, lambda t: [dataclasses.replace(finger, stamp=t)], phase=0.013)
    assert (
        check(recording(with_extra(resting))).findings == []
    )  # ROS1: robot_state_publisher sends movable joints on /tf
    alone = periodic("/finger_tf", 20, lambda t: [dataclasses.replace(finger, stamp=t)], phase=0.013)
    findings = check(recording(with_extra(alone), ros1=ros1)).findings  # constant by design, in messages of its own
    assert only(findings, "static_on_dynamic").frames == ("base_link", "finger")


def test_a_constant_edge_sent_again_is_counted_at_monitors_rate() -> None:
    """ros2_db3_jetacker_real_two_odometries: base_link -> link1, constant, 544 stamps in 570 transforms (some
    stamps sent again); wtf said '3.2 times a second (570 transforms ...)' beside monitor's 3.02 stamps/s. The
    rate is monitor's, its stamps tf2's samples; the transforms received are said beside them."""
    finger = _t("base_link", "finger", START, 0.05)
    alone = periodic("/finger_tf", 20, lambda t: [dataclasses.replace(finger, stamp=t)], phase=0.013)
    again = [dataclasses.replace(m, record_time=m.record_time + MS) for m in alone[::2]]
    scene = Scene(recording(with_extra(sorted(alone + again, key=lambda m: m.record_time)), ros1=False))
    finding = only(findings_of(scene), "static_on_dynamic")
    stats = next(s for s in scene.stats if (s.parent, s.child) == ("base_link", "finger"))
    assert stats.count == len(alone)
    assert f"{stats.rate_hz:.1f} times a second ({len(alone)} stamps in {len(alone) + len(again)} transforms" in (
        finding.message
    )


def test_a_detection_at_rest_is_no_fixed_transform_on_tf() -> None:
    """ros2_db3_logistic_cobot_pymoveit2: base_link -> obj_2, a box's detection seen in 4 bursts (monitor: 'a
    detection'), did not move: wtf said static_on_dynamic, 'publish it once on /tf_static'. A detector sends what
    it sees while it sees it; a steady constant edge is still one (the finger's)."""
    box = _t("base_link", "obj_2", START, 0.4)
    seen = periodic("/detector", 15, lambda t: [dataclasses.replace(box, stamp=t)], phase=0.013, skip=(3.0, 5.0))
    scene = Scene(recording(with_extra(seen), ros1=False))
    assert ("base_link", "obj_2") in scene.detections
    assert "static_on_dynamic" not in {f.code for f in findings_of(scene)}


def test_two_publishers_that_disagree_move_nothing_their_messages_share() -> None:
    """ros1_stage_amcl_sim_time_2015: stageros sends base_footprint -> base_link (z 0) and base_link ->
    base_laser_link, one edge a message, recorded at one tick of Stage's clock; robot_state_publisher sends
    base_footprint -> base_link at z 0.0102 m. The disagreement made stageros's constant edge 'moving', and
    the laser mount, sharing its messages' record time and stamp, passed for a joint at rest among moving
    ones: no static_on_dynamic on a mount sent on /tf 10 times a second. (Here: base_link -> deck -> lidar.)"""

    def stage(t: int) -> list[TfMessage]:
        deck = TfMessage("/tf", t + DELAY, [_t("base_link", "deck", t)], "/stageros")
        return [deck, TfMessage("/tf", t + DELAY, [_t("deck", "lidar", t, 0.2)], "/stageros")]

    stageros = [m for k in range(int(SECONDS * 10)) for m in stage(START + k * 100 * MS)]
    urdf = periodic("/robot_state_publisher", 5, lambda t: [_t("base_link", "deck", t, 0.0102)], phase=0.03)
    findings = check(recording(with_extra(stageros, urdf))).findings
    assert only(findings, "static_on_dynamic").frames == ("deck", "lidar")
    assert "multiple_authorities" in {f.code for f in findings}


def test_two_messages_a_cycle_are_a_regular_rhythm() -> None:
    """20 Hz sent as 33 ms then 67 ms (a driver's 100 ms cycle): regular; its median is either interval."""
    cycle = [t for i in range(100) for t in (i * 100, i * 100 + 33)]
    odometry = [TfMessage("/tf", START + ms * MS + DELAY, odom_base(START + ms * MS), "/ekf") for ms in cycle]
    assert check(recording(healthy(ekf=odometry))).findings == []


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_a_stamp_sent_again_with_other_values_is_judged_by_the_recordings_tf2(ros1: bool) -> None:
    """ROS 1's tf2 ignores the second sample (TF_REPEATED_DATA, an error); ROS 2's keeps both, the last counting:
    there, every stamp sent twice with other values is two publishers of the edge (a ROS 2 bag names none)."""

    def other_value(stamp: int) -> list[Transform]:  # the pose 10 ms later, under the same stamp
        return [dataclasses.replace(t, stamp=stamp) for t in odom_base(stamp + 10 * MS)]

    again = [
        TfMessage(m.topic, m.record_time + MS // 2, other_value(m.transforms[0].stamp), m.publisher) for m in ekf()
    ]
    messages = healthy(ekf=sorted(ekf() + again, key=lambda m: m.record_time))
    findings = check(recording(messages, ros1=ros1)).findings
    if ros1:
        finding = only(findings, "time_backwards")
        assert finding.severity is Severity.error and "TF_REPEATED_DATA" in finding.message
    else:
        finding = only(findings, "multiple_authorities")
        assert finding.severity is Severity.warning and "arrives twice" in finding.message
        assert "mix" in finding.hint


def test_a_stamp_sent_again_twice_with_one_other_value_is_two_rows_lost_on_one_stamp() -> None:
    """The second SAIL bag (ros1_sail_zed_revalued_stamps_2022.bag): a stamp sent A, B, B. ROS 1's tf2 keeps A and
    refuses both Bs (TF_REPEATED_DATA): two rows lost, on one stamp; an identical copy of A is a warning apart."""
    first = ekf()
    again = first[10]
    stamp = again.transforms[0].stamp
    other = [dataclasses.replace(t, stamp=stamp) for t in odom_base(stamp + 10 * MS)]
    copies = [TfMessage(again.topic, again.record_time + k * MS // 4, other, again.publisher) for k in (1, 2)]
    same = TfMessage(first[20].topic, first[20].record_time + MS // 4, first[20].transforms, first[20].publisher)
    messages = healthy(ekf=sorted([*first, *copies, same], key=lambda m: m.record_time))
    said = {f.severity: f for f in check(recording(messages)).findings if f.code == "time_backwards"}
    assert set(said) == {Severity.error, Severity.warning}, said
    assert "sent 2 transforms with a stamp it had already sent but other values than it first had (1 stamp)" in (
        said[Severity.error].message
    ), said[Severity.error].message
    assert "again with a stamp and values it had already sent" in said[Severity.warning].message
    assert "nothing is lost" in said[Severity.warning].message
    # timed when they came, as "first at" says (e-Yantra's iteration1.bag: 'first at 389.769' beside a JSON first
    # time of 389.647, the stamp), not at the stamp they repeat
    arrived = again.record_time + MS // 4  # recorded on the stamps' clock: ROS time at arrival
    assert said[Severity.error].first_time == arrived, (said[Severity.error].first_time, stamp)
    assert said[Severity.error].first_time != stamp


def test_every_registered_check_has_a_scene() -> None:
    shown = {p.code for p in PROBLEMS.values()}
    against_a_tree = {c for c in CHECKS if c.startswith("expect_")}  # each with its scene in test_expected.py
    against_a_urdf = {c for c in CHECKS if c.startswith("urdf_")}  # each with its scene in test_description.py
    # tested on files: tests/cli (bag_problem, unreadable), tests/analysis/test_wtf_hazards.py (static_volatile,
    # silent_tf: metadata.yaml says what a rosbag2 recording's topics held), tests/analysis/test_publishers.py
    # (resent: on ROS 2 bags, whose metadata.yaml counts the publishers), tests/analysis/test_wtf_odometry.py
    # (odometry: against the nav_msgs/Odometry a recording holds beside tf)
    assert set(CHECKS) - shown - against_a_tree - against_a_urdf == {
        "bag_problem",
        "unreadable",
        "static_volatile",
        "silent_tf",
        "resent",
        "odometry",
    }


def test_findings_come_errors_first() -> None:
    messages = with_extra(
        periodic("/sonar_tf", 10, lambda t: [_t("base_link", "sonar", t, 0.3)], phase=0.013), ekf=ekf(end=4.0)
    )  # a warning and an error
    findings = check(recording(messages)).findings
    assert [f.code for f in findings] == ["stale", "static_on_dynamic"]


# --- thresholds and options ------------------------------------------------------------------


def test_thresholds_move_the_limits() -> None:
    late = recording(PROBLEMS["delay"].make())
    assert check(late, CheckQuery(thresholds=Thresholds(delay=1.0))).findings == []
    assert [f.code for f in check(late, CheckQuery(thresholds=Thresholds(delay=0.4))).findings] == ["delay"]
    stopped = recording(PROBLEMS["stale"].make())
    assert check(stopped, CheckQuery(thresholds=Thresholds(stale_after=7.0))).findings == []
    gap = recording(PROBLEMS["rate"].make())
    assert check(gap, CheckQuery(thresholds=Thresholds(max_gap=4.0))).findings == []
    ahead = recording(PROBLEMS["future"].make())
    assert check(ahead, CheckQuery(thresholds=Thresholds(future=5.0))).findings == []
    replayed = recording(PROBLEMS["clock_replay"].make())  # 3 days behind: on another clock, or just late
    assert {f.code for f in check(replayed, CheckQuery(thresholds=Thresholds(clock=400_000.0))).findings} == {"delay"}


def test_the_clock_threshold_also_chooses_the_reference_clock() -> None:
    behind = {"stamp": lambda t: t - 20 * NS_PER_S}
    late = recording(healthy(amcl=amcl(**behind), ekf=ekf(**behind), wheels=wheels(**behind)))
    assert "delay" not in {f.code for f in check(late).findings}  # 20 s behind everything: stamps on no recorded clock
    delayed = {
        f.frames for f in check(late, CheckQuery(thresholds=Thresholds(clock=30.0))).findings if f.code == "delay"
    }
    assert delayed == {("map", "odom"), ("odom", "base_link"), ("base_link", "wheel")}


def test_thresholds_must_be_positive() -> None:
    with pytest.raises(ValueError, match="delay"):
        Thresholds(delay=0)


def test_ignored_checks_do_not_run_and_unknown_codes_are_refused() -> None:
    stopped = recording(PROBLEMS["stale"].make())
    assert check(stopped, CheckQuery(ignore=("stale",))).findings == []
    with pytest.raises(ValueError, match="no such check: stail"):
        check(stopped, CheckQuery(ignore=("stail",)))
    # in a ROS2 bag the rhythm check speaks for multiple_authorities: ignoring that code silences it too
    twins = recording(PROBLEMS["multiple_authorities_one_topic"].make(), ros1=False)
    assert [f.code for f in check(twins).findings] == ["multiple_authorities"]
    assert check(twins, CheckQuery(ignore=("multiple_authorities",))).findings == []


# --- what each finding says, case by case ----------------------------------------------------


def test_cycle_of_the_latest_parents_names_the_loop_in_order_and_tf2s_error() -> None:
    finding = only(check(recording(PROBLEMS["cycle"].make())).findings, "cycle")
    assert "base_link -> map -> odom -> base_link" in finding.message  # map's parent is base_link
    assert "contains a loop" in finding.message
    assert set(finding.authorities) == {"/amcl", "/ekf", "/rogue"}


def test_a_loop_only_in_the_raw_data_is_found_with_the_times_it_held() -> None:
    # odom stays under map, but between 2 s and 5 s it was also sent under base_link
    messages = with_extra(
        periodic("/rogue", 10, lambda t: [_t("base_link", "odom", t, _s(t))], start=2.0, end=5.0, phase=0.05)
    )
    findings = check(recording(messages)).findings
    assert {f.code for f in loud(findings)} == {"cycle", "multiple_parents"}
    loop = only(findings, "cycle")
    assert "transforms stamped" in loop.message and "+2.0 s" in loop.message
    assert START + 2 * NS_PER_S <= loop.first_time <= loop.last_time <= START + 5 * NS_PER_S


def test_a_loop_closed_by_one_transform_holds_at_its_stamp() -> None:
    """One transform sent once (an edge of one row, read with the other one-row edges at once) closes a loop."""
    once = START + 3 * NS_PER_S + 5 * NS_PER_S // 100
    messages = with_extra([TfMessage("/tf", once + DELAY, [_t("base_link", "odom", once)], "/rogue")])
    loop = only(check(recording(messages)).findings, "cycle")
    assert "transforms stamped" in loop.message and "+3.0" in loop.message
    assert loop.first_time == loop.last_time == once


def test_a_loop_across_times_that_never_overlap_is_no_cycle() -> None:
    # base_link under odom until 4 s, then under map; odom under base_link from 5 s: never a loop at one time
    messages = with_extra(
        periodic("/ekf", 50, lambda t: [_t("map", "base_link", t, _s(t))], start=4.0),
        periodic("/rogue", 50, lambda t: [_t("base_link", "odom", t, _s(t))], start=5.0, phase=0.01),
        ekf=ekf(end=4.0),
    )
    codes = {f.code for f in loud(check(recording(messages)).findings)}
    assert "multiple_parents" in codes and "cycle" not in codes


def test_disconnected_lists_each_tree_and_spots_a_misspelt_root() -> None:
    typo = TfMessage("/tf_static", START + 3 * MS, [_t("base_lnk", "sonar", START)], "/rsp")
    finding = only(check(recording(with_extra([typo]))).findings, "disconnected")
    assert finding.frames == ("map", "base_lnk")
    assert "map (6 frames" in finding.message and "base_lnk (2 frames: base_lnk, sonar)" in finding.message
    assert "'base_lnk' looks like a misspelling of 'base_link'" in finding.hint


def test_a_tree_like_another_under_another_namespace_lacks_a_transform_not_a_letter() -> None:
    """Three robots in Stage (ros1_stage_three_robots_pfms_week11.bag): robot_2's tree has robot_0's and robot_1's
    frames under 'robot_2/', and nothing publishes world -> robot_2/odom; 'robot_2/odom' is no misspelling of
    'robot_1/odom'."""
    messages = [
        TfMessage("/tf", START + k * MS, [_t(parent, child, START + k * MS)], "/stage")
        for k in range(3)
        for r in range(3)
        for parent, child in [
            *([("world", f"robot_{r}/odom")] if r < 2 else []),
            (f"robot_{r}/odom", f"robot_{r}/base_link"),
            (f"robot_{r}/base_link", f"robot_{r}/laser"),
        ]
    ]
    finding = only(check(recording(messages)).findings, "disconnected")
    assert "misspelling" not in finding.hint
    assert "robot_2/odom's tree has the same frames as robot_0's and robot_1's under 'robot_2/'" in finding.hint
    assert "world -> robot_0/odom and world -> robot_1/odom: publish world -> robot_2/odom" in finding.hint


def test_robots_each_in_a_tree_of_their_own_lack_a_common_parent_not_a_letter() -> None:
    """Three robots in Stage with no world recorded (ros1_pfms_a4_stage_three_robots_no_world_clock_2020.bag): each
    robot's tree is the others' under its own prefix and none is joined to anything; 'robot_1/odom' is no misspelling
    of 'robot_2/odom'."""
    messages = [
        TfMessage("/tf", START + k * MS, [_t(parent, child, START + k * MS)], "/stage")
        for k in range(3)
        for r in range(3)
        for parent, child in [(f"robot_{r}/odom", f"robot_{r}/base_link"), (f"robot_{r}/base_link", f"robot_{r}/laser")]
    ]
    finding = only(check(recording(messages)).findings, "disconnected")
    assert "misspelling" not in finding.hint
    assert "robot_0/odom, robot_1/odom and robot_2/odom head trees of the same frames" in finding.hint
    assert "world -> robot_0/odom and likewise for the others" in finding.hint


@pytest.mark.parametrize("ros1", [True, False])
def test_disconnected_without_tf_static_recorded_says_so(ros1: bool) -> None:
    # Formant's TurtleBot3 fixture (/tf alone): odom -> base_footprint and base_link's wheels, the fixed
    # base_footprint -> base_link of /tf_static never recorded; the hint says that, not "attach odom to base_link"
    base = periodic("/gazebo", 30, lambda t: [_t("odom", "base_footprint", t, 0.1 * _s(t))])
    messages = base + periodic("/rsp", 20, wheel, phase=0.01)
    finding = only(check(recording(messages, ros1=ros1)).findings, "disconnected")
    record = "rosbag record" if ros1 else "ros2 bag record"
    assert finding.hint.startswith(
        "this recording holds no /tf_static (no such topic in it): the fixed transforms that would join them"
    )
    assert f"({record} /tf /tf_static)" in finding.hint
    recorded_empty = recording([*messages, TfMessage("/tf_static", START + DELAY, [], "/rsp")], ros1=ros1)
    hint = only(check(recorded_empty).findings, "disconnected").hint
    assert hint.startswith("/tf_static was recorded but holds no transform")
    # with statics recorded, the missing transform is not /tf_static's to blame: the general hint
    with_statics = recording([*messages, statics()], ros1=ros1)
    assert only(check(with_statics).findings, "disconnected").hint.startswith("publish the transform that attaches")


def test_multiple_parents_says_who_set_each_parent_and_when() -> None:
    finding = only(check(recording(PROBLEMS["multiple_parents"].make())).findings, "multiple_parents")
    assert finding.frames == ("base_link", "odom", "map")
    assert "odom (by /ekf, 500 transforms" in finding.message and "map (by /rogue, 50 transforms" in finding.message
    assert "fight over it" in finding.hint
    assert finding.first_time == START + 5_010 * MS + 2 * MS  # the first /rogue message's arrival
    assert finding.count == 100  # base_link flips at every /rogue message and back


def test_an_edge_handed_over_from_one_publisher_to_another_is_a_note() -> None:
    messages = healthy(ekf=ekf(end=5.0) + periodic("/ekf_new", 50, odom_base, start=5.3))
    findings = check(recording(messages)).findings
    assert loud(findings) == []
    note = only(findings, "multiple_authorities")
    assert note.severity is Severity.info and note.authorities == ("/ekf", "/ekf_new")


def test_a_transform_sent_once_on_tf_is_stale_with_the_static_advice() -> None:
    once = TfMessage("/tf", START + 3 * MS, [_t("base_link", "sonar", START)], "/sonar")
    finding = only(check(recording(with_extra([once]))).findings, "stale")
    assert "sent once on /tf" in finding.message and "/tf_static" in finding.hint


def test_a_frame_moved_under_another_parent_is_not_stale() -> None:
    messages = healthy(ekf=ekf(end=5.0)) + periodic("/ekf", 50, lambda t: [_t("map", "base_link", t, _s(t))], start=5.0)
    codes = {f.code for f in check(recording(sorted(messages, key=lambda m: m.record_time))).findings}
    assert "stale" not in codes and "multiple_parents" in codes


def test_a_recorder_on_simulated_time_among_nodes_on_wall_time_is_a_note() -> None:
    """Every frame agrees with every other: lookups work, only arrival-based figures are lost."""
    sim = 500 * NS_PER_S  # the recorder's /clock
    messages = [TfMessage(m.topic, m.record_time - START + sim, m.transforms, m.publisher) for m in healthy()]
    findings = check(recording(sorted(messages, key=lambda m: m.record_time))).findings
    assert loud(findings) == []
    note = only(findings, "clock")
    assert "wall-clock time" in note.message and "record clock is simulated time" in note.message
    assert "cannot be measured" in note.message


def test_a_replay_stamped_days_before_its_record_clock_says_days_and_keeps_the_offset() -> None:
    """ros2_mcap_coug_auv_replayed: every frame stamped 515,220 s before it was recorded, no /clock; the note
    said "515219.9 s". Said in days for a person; the exact offset stays in the finding's figures (JSON)."""
    behind = 515_219_958_040_448  # a figure rounded to 0.1 s (515220.0) is off by 0.04 s
    messages = [TfMessage(m.topic, m.record_time + behind, m.transforms, m.publisher) for m in healthy()]
    note = only(check(recording(messages, ros1=False)).findings, "clock")
    assert note.message.startswith("tf is stamped 6.0 days before the record clock"), note.message
    assert note.figures["arrival_minus_stamp_s"] == pytest.approx(behind / NS_PER_S, abs=0.005)  # + its delay


def test_a_clock_far_ahead_is_future_with_the_advice_to_sync_clocks() -> None:
    ahead = recording(healthy(ekf=ekf(stamp=lambda t: t + 3600 * NS_PER_S)))
    finding = only(check(ahead).findings, "future")
    assert "500 of 500 transforms stamped up to 60.0 min after they arrived" in finding.message
    assert "chrony" in finding.hint


def test_a_robot_whose_clock_runs_ahead_is_said_from_its_first_stamp_not_before_the_tf_data() -> None:
    """A real Raspberry Pi Mouse whose clock ran 79.8 s ahead of the recorder's (corpus ros1_raspimouse_teleop_wifi_
    bursts_clock_ahead_2019): every tf stamp ahead, so the first arrival was said '(79.4 s before the first tf
    stamp)'. Said on the stamps' clock, as the finding's times are."""
    ahead = recording(ekf(stamp=lambda t: t + 80 * NS_PER_S))
    finding = only(check(ahead).findings, "future")
    assert f"the first stamped {(START + 80 * NS_PER_S) / NS_PER_S:.3f} (+0.0 s)" in finding.message, finding.message
    assert "before the first tf stamp" not in finding.message
    assert finding.first_time == START + 80 * NS_PER_S


@pytest.mark.parametrize(("length", "severity"), [(1.0001, Severity.info), (1.002, Severity.warning)])
def test_a_slightly_long_rotation_tf2_accepts_is_a_warning_or_a_note(length: float, severity: Severity) -> None:
    def long_rotation(stamp: int) -> list[Transform]:
        return [Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, length), stamp, "odom", "base_link")]

    findings = check(recording(healthy(ekf=periodic("/ekf", 50, long_rotation)))).findings
    finding = only(findings, "invalid_values")
    assert finding.severity is severity and finding.count == 500
    assert f"{length - 1:.2g}" in finding.message and "tf2 accepts them" in finding.message


def test_a_rotation_ros2s_tf2_normalises_is_not_called_refused() -> None:
    """wtf reads the buffer's verdicts: ROS 1's tf2 refuses a rotation of length 2, ROS 2's takes it
    (its matrix normalises it), and a ROS 2 recording's rows of it are used by the other checks."""

    def long_rotation(stamp: int) -> list[Transform]:
        return [Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 2.0), stamp, "odom", "base_link")]

    messages = healthy(ekf=periodic("/ekf", 50, long_rotation))
    refused = only(check(recording(messages)).findings, "invalid_values")
    assert refused.severity is Severity.error and "refused by tf2 (a rotation of length 2 in 500)" in refused.message
    taken = recording(messages, ros1=False)
    finding = only(check(taken).findings, "invalid_values")
    assert finding.severity is Severity.warning and "ROS 2's tf2 accepts them and normalises each" in finding.message
    assert "ROS 1's roswtf flags" in finding.hint  # a ROS 1 tool, said as one on ROS 2 data (issue 39)
    rows = rows_of(taken)
    assert rows.usable.all() and not rows.refused_for(*RejectionCode).any()


def test_rows_carry_every_code_the_buffer_refused_them_for() -> None:
    def rogue(stamp: int) -> list[Transform]:
        return [Transform((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "/base_link", "base_link")]

    taken = recording(with_extra(periodic("/rogue", 5, rogue)))
    rows = rows_of(taken)
    nan, self_tf = rows.refused_for(RejectionCode.NAN_INPUT), rows.refused_for(RejectionCode.SELF_TRANSFORM)
    assert nan.sum() == 50 and (nan == self_tf).all() and (~rows.usable == nan).all() and (~rows.named == nan).all()
    assert int((rows.refusals.whole() != 0).sum()) == len({r.sequence for r in taken.buffer.rejections})
    assert {f.code for f in loud(check(taken).findings)} == {"self_transform", "invalid_values", "leading_slash"}


def test_an_edge_whose_last_transforms_are_all_nan_is_stale_beneath_their_refusal() -> None:
    """e-Yantra's Krishi Bot (a scout's, KB_1759.bag): a fruit detection's last 33 transforms NaN, their stamps going
    on: said 'stopped advancing at 50.489, re-sent to the end' with a stalled localizer's hint. tf2 holds nothing
    newer than its last valid one because it refused the rest: said so, beneath the refusal."""

    def odom_then_nan(stamp: int) -> list[Transform]:
        (t,) = odom_base(stamp)
        return [Transform((math.nan, 0.0, 0.0), t.rotation, stamp, "odom", "base_link")] if _s(stamp) >= 6.0 else [t]

    findings = check(recording(healthy(ekf=periodic("/ekf", 50, odom_then_nan)))).findings
    (refused,) = [f for f in findings if f.code == "invalid_values"]
    (stale,) = [f for f in findings if f.code == "stale"]
    assert "odom -> base_link by /ekf holds nothing newer than" in stale.message, stale.message
    assert "were refused by tf2 for their values (invalid_values)" in stale.message and "re-sent" not in stale.message
    assert "stalled localizer" not in stale.hint and "send no transform where its value is unknown" in stale.hint
    assert stale.cause == refused.key and stale.key != refused.key, (stale.cause, refused.key)


def test_infinity_is_refused_like_nan() -> None:
    def infinite(stamp: int) -> list[Transform]:
        if 2.0 <= _s(stamp) < 2.1:
            return [Transform((float("inf"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "odom", "base_link")]
        return odom_base(stamp)

    finding = only(check(recording(healthy(ekf=periodic("/ekf", 50, infinite)))).findings, "invalid_values")
    assert "infinity in 5" in finding.message and finding.severity is Severity.error


def test_a_self_transform_spelt_with_a_slash_says_it_is_one_frame() -> None:
    messages = with_extra(periodic("/rogue", 5, lambda t: [_t("/base_link", "base_link", t)]))
    findings = check(recording(messages)).findings
    finding = only(findings, "self_transform")
    assert "sent as /base_link -> base_link" in finding.message
    assert {f.code for f in loud(findings)} == {"self_transform", "leading_slash"}


def test_empty_child_frame_id_is_named_as_such() -> None:
    messages = with_extra(periodic("/rogue", 5, lambda t: [_t("base_link", "", t)]))
    finding = only(check(recording(messages)).findings, "empty_frame_id")
    assert "empty child_frame_id (frame_id base_link)" in finding.message and "TF_NO_CHILD_FRAME_ID" in finding.message


def test_both_frame_ids_empty_is_one_finding_received_when_stamped_zero() -> None:
    """foxglove-wizard 0.3.0's drone.mcap: 17 default-made TransformStampeds (no frames, stamp 0) before the
    flight's world -> drone. One fault, one finding (not one per empty field), and when they arrived, not
    'at 0.000'."""
    messages = with_extra(periodic("/rogue", 5, lambda t: [_t("", "", 0)]))
    finding = only(check(recording(messages)).findings, "empty_frame_id")
    assert "with both frame_id and child_frame_id empty, first received at" in finding.message
    assert "TF_NO_CHILD_FRAME_ID, TF_NO_FRAME_ID" in finding.message and finding.count == 50
    assert "self_transform" not in {f.code for f in check(recording(messages)).findings}


def test_stamps_jumping_back_beyond_tf2s_cache_suggest_a_time_jump() -> None:
    def looped(t: int) -> int:  # a bag played with -l: stamps restart after 6 s
        return t - 6 * NS_PER_S if t >= START + 6 * NS_PER_S else t

    finding = only(check(recording(healthy(ekf=ekf(stamp=looped)))).findings, "time_backwards")
    assert "went back 1 time, by up to 6.0 s" in finding.message
    assert "200 transforms stamped before one already sent" in finding.message
    assert "time jumped back" in finding.hint
    # under tf2's 10 s cache the samples are stored, so no advice about TF_OLD_DATA
    assert "TF_OLD_DATA" not in finding.hint


def test_repeated_stamps_with_new_values_are_an_error() -> None:
    def stuck(stamp: int) -> int:  # the stamp advances every 0.1 s only, the values every 0.02 s
        return START + (stamp - START) // (100 * MS) * 100 * MS

    messages = healthy(ekf=periodic("/ekf", 50, lambda t: [_t("odom", "base_link", stuck(t), _s(t))]))
    finding = only(check(recording(messages)).findings, "time_backwards")
    assert finding.severity is Severity.error and finding.count == 400
    assert "other values" in finding.message


def test_mixed_static_first_on_tf_says_the_static_one_counts_at_its_stamp_only() -> None:
    late_static = TfMessage("/tf_static", START + 5 * NS_PER_S, [_t("odom", "base_link", START)], "/rsp")
    finding = only(check(recording(with_extra([late_static]))).findings, "mixed_static")
    assert "first transform came on /tf)" in finding.message


def test_only_static_transforms_is_a_note() -> None:
    findings = check(recording([statics()])).findings
    assert loud(findings) == []
    assert only(findings, "no_tf").severity is Severity.info


def test_no_transforms_at_all_runs_no_other_check() -> None:
    findings = check(recording(PROBLEMS["no_tf"].make())).findings
    assert [f.code for f in findings] == ["no_tf"]


def test_amcl_post_dating_below_a_second_is_no_future_error() -> None:
    assert check(recording(healthy(amcl=amcl(stamp=lambda t: t + 900 * MS)))).findings == []


def test_a_publisher_that_stutters_is_irregular_but_one_pause_is_a_gap() -> None:
    dropped = np.random.default_rng(7).random(100) < 0.3  # about one 0.1 s slot in three, at random
    messages = [m for m in amcl() if not dropped[round((m.record_time - START) / NS_PER_S * 10) % 100]]
    finding = only(check(recording(healthy(amcl=messages))).findings, "rate")
    assert "publishes irregularly" in finding.message and finding.frames == ("map", "odom")
    gap = only(check(recording(PROBLEMS["rate"].make())).findings, "rate")
    assert "went silent 1 time" in gap.message and "3.1 s" in gap.message


def test_edges_of_one_stuttering_publisher_in_messages_of_their_own_are_one_rate_cause() -> None:
    """A real Neato's driver (corpus ros2-neato-real-teleop-pulses-2025-db3) sends odom -> base_footprint and
    each wheel in a message of its own, at the same stamps, microseconds apart: one irregular rhythm, said
    once with the others beneath (their arrivals differ, their stamps do not)."""
    dropped = np.random.default_rng(7).random(100) < 0.3
    messages = [m for m in amcl() if not dropped[round((m.record_time - START) / NS_PER_S * 10) % 100]]
    beside = [
        TfMessage(m.topic, m.record_time + 50_000, [_t("odom", "beacon", t.stamp, 1.0)], m.publisher)
        for m in messages
        for t in m.transforms
    ]
    found = [f for f in check(recording(healthy(amcl=sorted(messages + beside, key=lambda m: m.record_time)))).findings]
    rates = [f for f in found if f.code == "rate"]
    assert len(rates) == 2 and all("publishes irregularly" in f.message for f in rates)
    assert [f.frames for f in causes(rates)] == [("map", "odom")] and rates[1].cause == rates[0].key


def test_a_robot_standing_still_is_healthy_though_odom_is_constant() -> None:
    parked = periodic("/ekf", 50, lambda t: [_t("odom", "base_link", t, 2.0)])
    assert check(recording(healthy(ekf=parked))).findings == []


@pytest.mark.parametrize("name", ["cycle", "multiple_parents", "multiple_authorities"])
def test_a_constant_rogue_transform_is_reported_once_as_what_it_breaks(name: str) -> None:
    rogue = {
        "cycle": periodic("/rogue", 10, lambda t: [_t("base_link", "map", t)], phase=0.05),
        "multiple_parents": periodic("/rogue", 10, lambda t: [_t("map", "base_link", t)], phase=0.01),
        "multiple_authorities": periodic("/rogue", 10, lambda t: [_t("base_link", "wheel", t)], phase=0.01),
    }[name]
    assert [f.code for f in loud(check(recording(with_extra(rogue))).findings)] == [name]


def test_a_few_late_arrivals_are_enough_for_a_delay_warning() -> None:
    messages = ekf()
    late = [
        TfMessage(m.topic, m.record_time + (800 * MS if i % 10 == 0 else 0), m.transforms, m.publisher)
        for i, m in enumerate(messages)
    ]
    finding = only(check(recording(healthy(ekf=late))).findings, "delay")
    assert "50 of 500 transforms more than 0.2 s after their stamp" in finding.message
    # tolerated lateness: what remains is that newer transforms overtook them, which tf2 copes with
    (overtaken,) = check(recording(healthy(ekf=late)), CheckQuery(thresholds=Thresholds(delay=0.9))).findings
    assert overtaken.code == "time_backwards" and overtaken.severity is Severity.warning
    assert "50 transforms arrived out of order" in overtaken.message


def test_the_transform_that_closed_a_loop_late_is_named_in_the_hint() -> None:
    late_rogue = periodic("/rogue", 10, lambda t: [_t("base_link", "map", t, _s(t))], start=3.0, phase=0.05)
    finding = only(check(recording(with_extra(late_rogue))).findings, "cycle")
    assert "since 1700000003.052 (+3.1 s)" in finding.message
    assert finding.hint.endswith("base_link -> map by /rogue closed it, at 1700000003.052 (+3.1 s)")
    early = only(check(recording(PROBLEMS["cycle"].make())).findings, "cycle")  # all began together: no guess
    assert "closed it" not in early.hint


def test_what_cycle_claims_holds_lookups_through_the_loop_fail_with_tf2s_loop_error() -> None:
    looped = recording(PROBLEMS["cycle"].make())
    finding = only(check(looped).findings, "cycle")
    with pytest.raises(TransformError, match="contains a loop"):
        looped.buffer.lookup("laser", "odom")
    assert "contains a loop" in finding.message


def test_what_stale_claims_holds_lookups_after_the_last_stamp_extrapolate_into_the_future() -> None:
    stopped = recording(PROBLEMS["stale"].make())
    finding = only(check(stopped).findings, "stale")
    stopped.buffer.lookup("map", "base_link", finding.first_time)
    with pytest.raises(ExtrapolationError, match="into the future"):
        stopped.buffer.lookup("map", "base_link", finding.first_time + 100 * MS)
    assert "extrapolation into the future" in finding.hint


def test_a_start_up_burst_is_not_said_as_the_rate_the_publisher_keeps_up() -> None:
    """A real Neato's driver (corpus ros2_db3_neato_obstacle_avoider_burst_2023) flushes 44 samples 10 ms apart,
    then sends one every 0.32-0.55 s: its rate finding quoted 'the usual 0.010 s', the burst's interval."""
    gaps = np.random.default_rng(4).uniform(0.32, 0.48, 30)  # under wtf's 0.5 s floor of a pause
    times = [i * 0.01 for i in range(44)] + list(0.43 + np.cumsum(gaps))
    stamps = [START + round(t * NS_PER_S) for t in times]
    odom = [TfMessage("/tf", t + DELAY, [_t("map", "odom", t, 0.01 * i)], "/amcl") for i, t in enumerate(stamps)]
    finding = only(check(recording(healthy(amcl=odom))).findings, "rate")
    intervals = np.diff(stamps)
    burst = np.count_nonzero(intervals < 0.2 * NS_PER_S)
    off = r"(\d+)% of the intervals between its arrivals are more than 50% off the (\d\.\d+) s it keeps"
    said = re.search(off, finding.message)
    assert said, finding.message
    assert 0.32 <= float(said[2]) <= 0.48  # the driver's own rhythm, not the burst's 0.010 s
    assert int(said[1]) == round(100 * burst / len(intervals))  # the burst's intervals are those off it
    assert finding.hint.endswith("publish on a timer at a steady rate")  # amcl's own, no joint's


def test_a_joint_sent_on_two_sources_joint_states_is_told_to_check_who_publishes_them() -> None:
    """e-Yantra's Krishi Bot in Gazebo (atom-robotics-lab/eyrc22_KB_1133 iteration1.bag, a scout's): its arm's
    joints come from robot_state_publisher fed /joint_states by two sources (12 joints at 50 Hz, 16 at 10 Hz);
    told to 'publish on a timer at a steady rate', as if robot_state_publisher were a driver. A joint's rhythm is
    /joint_states', said so, with who publishes them to check; a lone edge keeps the timer's hint."""
    # as the recording's: mostly 0.030 s apart, 3 in 10 intervals split or stretched by the other source's messages
    steps = np.random.default_rng(7).choice([0.03] * 7 + [0.004, 0.012, 0.05], 600)
    times = list(np.cumsum(steps))
    arm = [
        TfMessage(
            "/tf",
            START + round(t * NS_PER_S) + DELAY,
            [
                _t("arm_base", "upper_arm", START + round(t * NS_PER_S), t),
                _t("upper_arm", "forearm", START + round(t * NS_PER_S), t),
            ],
            "/robot_state_publisher",
        )
        for t in times
    ]
    findings = [f for f in check(recording(healthy(arm=arm))).findings if f.code == "rate"]
    assert findings and all(f.frames[0] in ("arm_base", "upper_arm") for f in findings), findings
    for found in findings:
        assert "of the intervals between its arrivals are more than 50% off" in found.message, found.message
        assert found.hint.startswith("robot_state_publisher sends a joint's transform for each /joint_states"), found
        assert "rostopic info /joint_states" in found.hint, found.hint


def _rate_of_odometry(times: list[float]) -> Finding:
    """The rate finding of map -> odom sent at ``times`` (seconds after START)."""
    stamps = [START + round(t * NS_PER_S) for t in times]
    odom = [TfMessage("/tf", t + DELAY, [_t("map", "odom", t, 0.01 * i)], "/amcl") for i, t in enumerate(stamps)]
    return only(check(recording(healthy(amcl=odom))).findings, "rate")


def test_off_intervals_all_in_a_start_up_burst_are_said_as_one_burst() -> None:
    """Issue 39: the avoider Neato's rate finding (71% of its intervals off the 0.410 s) did not say that every
    one of them came in its first 0.5 s, 10 ms apart, and none after. Said, observed then concluded; the same
    short intervals spread among the slow ones are irregular throughout, no stretch said."""
    gaps = list(np.random.default_rng(4).uniform(0.32, 0.48, 30))
    burst = _rate_of_odometry([i * 0.01 for i in range(44)] + list(0.43 + np.cumsum(gaps)))
    said = re.search(r", all (\d+) of them in a row in its first (\d\.\d+) s: a burst at its start", burst.message)
    assert said, burst.message
    assert int(said[1]) == 43 and float(said[2]) == pytest.approx(0.43)  # the 43 intervals of 10 ms
    assert burst.message.endswith("steady after it")
    spread = [0.01] * 43 + gaps
    np.random.default_rng(5).shuffle(spread)
    scattered = _rate_of_odometry(list(np.cumsum([0.0, *spread])))
    assert "publishes irregularly" in scattered.message and "in a row" not in scattered.message


def test_a_rhythm_broken_by_a_pause_once_a_second_is_said_as_runs_and_pauses() -> None:
    """A student's disc-robot simulator (corpus shaheenebrahimi/DDMR out4) sends every 0.100 s but stops for
    0.63-0.70 s once a second while it computes its scan: by time the pauses are most of the stream, and the
    finding said '81% of its intervals are more than 50% off the 0.637 s it keeps up most of the time', the
    pauses named its rhythm. Said now as runs at its interval, broken by pauses, with how often they come; a
    start-up burst (the Neato's) keeps its words."""
    pauses = np.random.default_rng(27).uniform(0.62, 0.70, 10)
    intervals = [x for pause in pauses for x in (pause, 0.02, 0.08, 0.1, 0.1)]  # a catch-up sample after each
    finding = _rate_of_odometry(list(np.cumsum([0.0, *intervals])))
    said = re.search(
        r"every (\d\.\d+) s in runs, broken (\d+) times by pauses of (\d\.\d+) s to (\d\.\d+) s, about one every "
        r"(\d\.\d+) s \((\d+)% of its time\)$",
        finding.message,
    )
    assert said, finding.message
    assert [float(said[1]), int(said[2])] == [0.1, 10]
    assert [float(said[3]), float(said[4])] == [round(pauses.min(), 3), round(pauses.max(), 3)]
    assert float(said[5]) == pytest.approx(0.3 + float(np.median(pauses)), abs=0.02)
    assert int(said[6]) == round(100 * pauses.sum() / sum(intervals))
    assert "keeps up most of the time" not in finding.message and f"{pauses.max():.3f} s" in finding.hint
    gaps = list(np.random.default_rng(4).uniform(0.32, 0.48, 30))
    burst = _rate_of_odometry([i * 0.01 for i in range(44)] + list(0.43 + np.cumsum(gaps)))
    assert "it keeps up most of the time" in burst.message and "in runs" not in burst.message


def test_steady_stamps_received_in_bursts_are_no_irregular_rate() -> None:
    """A real robot's odometry (corpus zaki0929/bagfiles 2019 expt04) stamped exactly 0.100 s apart, received
    over Wi-Fi in bursts (arrival intervals of 0 to 0.86 s): what tf2 holds is steady, so no ``rate``; the same
    bursts with the stamps dropped as they arrive stay irregular."""
    lag = np.random.default_rng(39).uniform(0.0, 0.15, 1000) * NS_PER_S
    bursts = [dataclasses.replace(m, record_time=m.record_time + int(lag[i])) for i, m in enumerate(amcl())]
    bursts.sort(key=lambda m: m.record_time)
    assert not [f for f in check(recording(healthy(amcl=bursts))).findings if f.code == "rate"]
    dropped = np.random.default_rng(7).random(100) < 0.3
    stutter = [m for m in bursts if not dropped[round((m.transforms[0].stamp - START) / NS_PER_S * 10) % 100]]
    assert "publishes irregularly" in only(check(recording(healthy(amcl=stutter))).findings, "rate").message


def test_stamps_off_their_places_now_and_then_are_a_steady_rate() -> None:
    """e-Yantra's Gazebo arms (Sahayak Bot 2020, Krishi Bot 2022): /joint_states every 20 ms, one in five or six
    stamped 13-14 ms early (20, 7, 33, 20 ms apart), received by a recorder reading simulated time in steps (its
    arrivals in batches): 'comes in batches' on twelve edges of one steady source. Samples stamped off their places
    alone keep the count and two periods a pair: steady. A second source's samples among them (more than the period
    gives) are not; nor is a marker seen in irregular bursts (tests/analysis/test_detections.py)."""
    period, samples = 20 * MS, np.arange(1000)
    jittered = START + samples * period - np.where(samples % 6 == 3, 13 * MS, 0)
    assert timing._steady(jittered)
    second = START + np.arange(0, 1000 * period, 7 * period) + 9 * MS  # every 140 ms, 9 ms after a sample
    assert not timing._steady(np.sort(np.concatenate([jittered, second, second + 3 * MS])))
