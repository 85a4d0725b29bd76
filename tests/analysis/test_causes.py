"""One root cause, one finding: what follows from a cause is linked to it (``Finding.cause``), said beneath it
in text, JSON, JUnit, view-frames and the report, and counted with it; designed scenes and two real recordings."""

from __future__ import annotations

import dataclasses
import io
import json
import math
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from rich.console import Console

from tests.analysis import wtf_scenes as scenes
from tests.analysis.robot_scenes import MOVED, Recorded, Setup, recorded, write_robot_bag
from tests.analysis.test_description import _on_tf
from tests.bags import BagFormat, TfMessage
from tests.corpus.fetch import shared_dir
from tftools.analysis.findings import Finding, Severity, causes, explained
from tftools.analysis.graph import frame_graph
from tftools.analysis.report import report
from tftools.analysis.wtf import Scene, Thresholds
from tftools.analysis.wtf.causes import Rule, explain
from tftools.analysis.wtf.fleet import BagReport, check, check_fleet, exit_code
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render import graph as graph_render
from tftools.render import wtf as render
from tftools.render.report import recording_section
from tftools.render.wtf_lines import read_report, write_recording
from tftools.sources.recording import read_recording

STALL = scenes.PROBLEMS["stall"]


def checked_bag(path: str | Path) -> BagReport:
    """``tfx wtf BAG``'s report of the recording at ``path``."""
    (checked,) = check_fleet([[str(path)]])
    return checked


def _stalled(ros1: bool = True) -> list[Finding]:
    return check(scenes.recording(STALL.make(), ros1=ros1)).findings


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_every_edge_pausing_at_once_is_one_stall_with_each_edges_pause_beneath(ros1: bool) -> None:
    findings = _stalled(ros1)
    assert [(f.code, f.cause) for f in findings] == [("stall", ""), *[("rate", "stall:1")] * 3], findings
    stall = findings[0]
    assert stall.key == "stall:1" and stall.severity is Severity.warning and stall.count == 3
    assert stall.hint.startswith("nothing reached the recorder")
    assert {("map", "odom"), ("odom", "base_link"), ("base_link", "wheel")} == {
        (stall.frames[i], stall.frames[i + 1]) for i in range(0, len(stall.frames), 2)
    }
    assert [f.frames for f in explained(findings, stall)] == [f.frames for f in findings[1:]]
    assert causes(findings) == [stall]


def test_pauses_far_apart_are_each_edges_own() -> None:
    messages = scenes.healthy(amcl=scenes.amcl(skip=(2.0, 4.0)), ekf=scenes.ekf(skip=(6.0, 8.0)))
    findings = check(scenes.recording(messages)).findings
    assert [(f.code, f.cause, f.key) for f in findings] == [("rate", "", "")] * 2, findings


def _stall_meanwhile(still: bool) -> Finding:
    """The stall scene (3 edges silent from +2.9 s to +5.0 s) with transforms arriving inside it: each edge's last
    sample sent again and again (its clock stood still), or its last second's samples delivered 1.2 s late."""
    late = 1200 * scenes.MS

    def part(make: Callable[..., list[TfMessage]], stop: float, hz: float) -> list[TfMessage]:
        if still:
            last = scenes.START + round((stop - 1 / hz) * NS_PER_S)
            meanwhile = make(start=stop, end=5.0, stamp=lambda t: last)
            return [*make(end=stop), *meanwhile, *make(start=5.0)]
        return [*make(end=stop - 1.0), *make(start=stop - 1.0, end=stop, delay=late), *make(start=5.0)]

    parts = {
        "amcl": part(scenes.amcl, 3.0, 10),
        "ekf": part(scenes.ekf, 3.2, 50),
        "wheels": part(scenes.wheels, 3.4, 20),
    }
    (stall,) = [f for f in check(scenes.recording(scenes.healthy(**parts))).findings if f.code == "stall"]
    return stall


def test_a_stall_that_new_samples_arrive_in_late_is_the_link_not_a_clock_that_stood_still() -> None:
    """A real JetAcker over WiFi (ros2_db3_jetacker_real_two_odometries): its 3 edges silent for 2.2-2.9 s from
    +145.1 s while 45 transforms arrived, each a sample not received before, stamped outside the stall (25 before
    it: delivered late). wtf said 'stamped no later than before: the clock they are stamped with stood still (a
    paused simulation, a driver's clock)': no clock stood still on that robot. Samples sent again with one stamp
    still say so. Either way transforms kept coming: the edges stopped ('they'), not everything on /tf."""
    late = _stall_meanwhile(still=False)
    assert late.message.endswith("new samples but none stamped inside it: they stopped at once"), late.message
    assert late.hint.startswith("transforms kept coming, new samples") and "not a clock that stood still" in late.hint
    still = _stall_meanwhile(still=True)
    assert still.message.endswith("stamped no later than before: they stopped at once"), still.message
    assert "stood still (a paused simulation" in still.hint


def test_edges_sent_in_one_message_pausing_together_are_that_publishers_pause_not_a_stall() -> None:
    """create3's odometry sends odom -> base_link and odom -> base_footprint in one message: they pause together."""

    def both(stamp: int) -> list[Transform]:
        return [*scenes.odom_base(stamp), scenes._t("odom", "base_footprint", stamp, 0.4 * scenes._s(stamp))]

    messages = scenes.healthy(amcl=[], wheels=[], ekf=scenes.periodic("/ekf", 50, both, skip=(3.0, 5.0)))
    findings = check(scenes.recording(messages)).findings
    assert [(f.code, f.frames[1], f.cause) for f in findings] == [
        ("rate", "base_link", ""),
        ("rate", "base_footprint", "rate:1"),  # the same pause, said once
    ], findings


def test_an_edge_that_also_paused_elsewhere_follows_the_stall_and_still_says_how_often() -> None:
    """Nav2's map -> odom: one pause in the stall, one 45 s later; the line beneath the stall says both."""
    amcl = [m for m in scenes.amcl(skip=(3.0, 5.0)) if not 8.0 <= (m.record_time - scenes.START) / NS_PER_S < 9.5]
    messages = scenes.healthy(amcl=amcl, ekf=scenes.ekf(skip=(3.2, 5.0)), wheels=scenes.wheels(skip=(3.4, 5.0)))
    findings = check(scenes.recording(messages)).findings
    (rate,) = [f for f in findings if f.frames == ("map", "odom")]
    assert rate.cause == "stall:1" and "went silent 2 times" in rate.message


def _ahead(seconds: float) -> Callable[[int], int]:
    return lambda t: t + round(seconds * NS_PER_S)


def test_edges_stamped_ahead_by_one_clock_are_one_future_with_the_others_beneath() -> None:
    """A real TurtleBot3 (ros2-turtlebot3-real-wifi-outage-2025-db3): its clock 3.4 s ahead of the laptop
    that recorded it, odometry and robot_state_publisher's wheels alike: one clock, said once (was 3 errors)."""
    messages = scenes.healthy(amcl=[], ekf=scenes.ekf(stamp=_ahead(3.4)), wheels=scenes.wheels(stamp=_ahead(3.41)))
    future = [f for f in check(scenes.recording(messages, ros1=False)).findings if f.code == "future"]
    assert [(f.frames, f.cause) for f in future] == [
        (("odom", "base_link"), ""),
        (("base_link", "wheel"), "future:1"),
    ], future
    assert future[0].figures["ahead_s_median"] == pytest.approx(3.4, abs=0.01)


def test_a_post_dating_publisher_beside_a_clock_ahead_is_its_own_future() -> None:
    """amcl post-dating map -> odom by 1.5 s (its transform_tolerance) on a robot whose clock is 3.4 s ahead:
    two causes, neither beneath the other."""
    messages = scenes.healthy(amcl=scenes.amcl(stamp=_ahead(1.5)), ekf=scenes.ekf(stamp=_ahead(3.4)), wheels=[])
    future = [f for f in check(scenes.recording(messages, ros1=False)).findings if f.code == "future"]
    assert sorted((f.frames, f.cause) for f in future) == [(("map", "odom"), ""), (("odom", "base_link"), "")]


def _fixed_joint(stamp: int) -> list[Transform]:
    return [scenes._t("base_link", "imu_link", stamp, 0.1)]  # one value throughout: a fixed joint on /tf


@pytest.mark.parametrize(("joint", "beneath"), [(_fixed_joint, True), (scenes.wheel, False)])
def test_ros1_rsp_s_fixed_joints_half_a_second_further_ahead_are_the_same_clock(
    joint: Callable[[int], list[Transform]], beneath: bool
) -> None:
    """A real Robotnik Guardian (ros1-robotnik-guardian-real-tilting-laser-pallet-...-2014-bag): its clock 7.6 s
    ahead, and the fixed joints ROS 1's robot_state_publisher sends on /tf 8.1 s ahead (it stamps them now + 0.5 s):
    two future errors for one clock. A fixed joint 0.5 s further ahead is beneath the clock's; a moving edge
    0.5 s further ahead is another publisher's post-dating, its own."""
    rsp = scenes.periodic("/rsp", 20, joint, stamp=_ahead(3.9))
    messages = scenes.healthy(amcl=[], ekf=scenes.ekf(stamp=_ahead(3.4)), wheels=rsp)
    future = [f for f in check(scenes.recording(messages)).findings if f.code == "future"]
    assert [f.frames[0] for f in future] == ["odom", "base_link"], future
    assert future[1].cause == ("future:1" if beneath else ""), future


def test_edges_of_one_message_that_stop_together_are_one_stale_with_the_other_beneath() -> None:
    """robot_state_publisher's two wheels (one message) stop 4 s into 10 (the real TurtleBot3's wheels after
    its Wi-Fi outage): one publisher stopped, said once; an edge of another publisher stopping is its own."""

    def two(stamp: int) -> list[Transform]:
        return [*scenes.wheel(stamp), scenes._t("base_link", "wheel_right", stamp)]

    messages = scenes.healthy(amcl=scenes.amcl(end=6.0), wheels=scenes.periodic("/rsp", 20, two, end=4.0))
    stale = [f for f in check(scenes.recording(messages, ros1=False)).findings if f.code == "stale"]
    assert sorted((f.frames, f.cause) for f in stale) == [
        (("base_link", "wheel"), ""),
        (("base_link", "wheel_right"), "stale:1"),
        (("map", "odom"), ""),
    ], stale


def test_one_frame_prefix_on_tf_and_tf_static_is_one_leading_slash_in_ros2_words() -> None:
    """robot_state_publisher with a frame_prefix of '/' (ros2-turtlebot3-gazebo-leading-slash-2025-db3): its
    fixed joints on /tf_static and its wheels on /tf name '/base_link': one naming, said once, and the hint
    names ROS 2's frame_prefix, not ROS 1's tf_prefix."""

    def wheel(stamp: int) -> list[Transform]:
        return [scenes._t("/base_link", "/wheel", stamp, 0.0, 4.0 * scenes._s(stamp))]

    statics = TfMessage("/tf_static", scenes.START, [scenes._t("/base_link", "/laser", scenes.START, 0.2)], "/rsp")
    messages = scenes.healthy(statics=[statics], wheels=scenes.periodic("/rsp", 20, wheel))
    slashes = [f for f in check(scenes.recording(messages, ros1=False)).findings if f.code == "leading_slash"]
    assert [f.cause for f in slashes] == ["", "leading_slash:1"], slashes
    assert "frame_prefix" in slashes[0].hint and "tf_prefix" not in slashes[0].hint


def test_a_leading_slash_in_ros1_keeps_ros1_words() -> None:
    (finding,) = [
        f
        for f in check(scenes.recording(scenes.PROBLEMS["leading_slash"].make())).findings
        if f.code == "leading_slash"
    ]
    assert "tf_prefix is gone since ROS Hydro" in finding.hint


def _sensor(name: str, skip: tuple[float, float] | None = None) -> list[TfMessage]:
    """base_link -> ``name`` at 20 Hz from its own driver (``/name``), silent over ``skip``."""

    def make(stamp: int) -> list[Transform]:
        return [scenes._t("base_link", name, stamp, 0.1)]

    return scenes.periodic(f"/{name}", 20, make, skip=skip)


def test_the_same_edges_stalling_again_and_again_are_one_stall() -> None:
    """A real Neato over wifi (ros2_db3_neato_real_checkpoint_joloujo_2023): all three moving edges silent at once
    5 times for 5.4-12.0 s, said as 5 stall warnings with one hint, while each edge's rate said 'went silent 5
    times' once: one link dropping out again and again is one problem. Twice here, 2 s and 3 s."""
    gaps = ((2.0, 4.0), (6.0, 9.0))
    messages = [
        m
        for m in scenes.healthy()
        if m.topic == "/tf_static" or not any(a <= (m.record_time - scenes.START) / NS_PER_S < b for a, b in gaps)
    ]
    findings = check(scenes.recording(messages)).findings
    (stall,) = [f for f in findings if f.code == "stall"]
    assert stall.message.startswith("all 3 moving edges went silent at once 2 times"), stall.message
    assert "the first from 1700000001." in stall.message and "the longest from 1700000005." in stall.message
    assert "the recorder received no transform on /tf for up to 3.0 s" in stall.message, stall.message
    assert stall.count == 6 and [f.cause for f in findings if f.code == "rate"] == ["stall:1"] * 3


def test_a_stall_of_few_of_many_edges_says_how_many_of_them() -> None:
    quiet = {name: _sensor(name) for name in "cd"}
    paused = {name: _sensor(name, (4, 6)) for name in "ab"}
    messages = scenes.with_extra(quiet["c"], quiet["d"], paused["a"], paused["b"], amcl=scenes.amcl(skip=(4.0, 6.0)))
    stall = next(f for f in check(scenes.recording(messages)).findings if f.code == "stall")
    assert stall.message.startswith("3 of 7 moving edges went silent within 0.050 s of each other"), stall.message
    assert stall.message.endswith(
        "(map -> odom, base_link -> a, base_link -> b); the other moving edges went on: they stopped at once"
    )
    assert stall.hint.startswith("the other edges went on: look for what these publishers share")


def test_edges_that_stop_at_the_same_instant_are_said_so_never_within_0_000_s() -> None:
    """A real Neato's driver stamps its three edges alike (ros2_db3_neato_real_checkpoint_joloujo_2023): they went
    silent 'each time within 0.000 s of each other', a figure that reads as a rounding. Here two drivers and amcl,
    in step, all silent after their samples stamped 3.9 s, while two other drivers go on."""

    def driver(name: str, delay: int) -> list[TfMessage]:  # its own messages, stamps alike, arrivals apart
        return scenes.periodic(
            f"/{name}", 20, lambda t: [scenes._t("base_link", name, t, 0.1)], skip=(3.91, 6), delay=delay
        )

    paused = [driver("a", 3 * scenes.MS), driver("b", 7 * scenes.MS)]
    messages = scenes.with_extra(*paused, _sensor("c"), _sensor("d"), amcl=scenes.amcl(skip=(3.91, 6.0)))
    stall = next(f for f in check(scenes.recording(messages)).findings if f.code == "stall")
    assert stall.message.startswith("3 of 7 moving edges went silent at the same instant, from "), stall.message
    assert "0.000 s" not in stall.message, stall.message


# --- the rule of a robot description under disputed statics ------------------------------------


def _robot_with_second_statics(tmp_path: Path, publisher: str, fmt: BagFormat = BagFormat.ros1) -> Path:
    """The rover with its /robot_description, then a second /tf_static message (0.6 s later, from ``publisher``)
    putting the laser 2 cm further forward: the description agrees with the first one, tf2 keeps the second."""
    messages = recorded(Setup(description=True))
    first = next(m for m in messages if m.topic == "/tf_static")
    laser = next(t for t in first.value if t.child_frame_id == "laser")
    moved = Transform(MOVED[0], laser.rotation, laser.stamp, laser.frame_id, laser.child_frame_id)
    second = [moved if t.child_frame_id == "laser" else t for t in first.value]
    messages.append(Recorded("/tf_static", first.record_time + 600_000_000, second, publisher))
    return write_robot_bag(tmp_path / ("rover.bag" if fmt is BagFormat.ros1 else "rover"), messages, fmt)


@pytest.mark.parametrize(
    ("publisher", "fmt", "code"),
    [
        ("/calibration", BagFormat.ros1, "static_conflict"),  # ROS 1 names two publishers
        ("/robot_state_publisher", BagFormat.ros1, "dynamic_on_static"),  # one publisher changing its own
        ("", BagFormat.rosbag2_sqlite3, "dynamic_on_static"),  # ROS 2 names none (static_conflict once inferred)
    ],
)
def test_a_moved_joint_on_disputed_statics_follows_the_dispute(
    tmp_path: Path, publisher: str, fmt: BagFormat, code: str
) -> None:
    report = checked_bag(_robot_with_second_statics(tmp_path, publisher, fmt))
    loud = [f for f in report.findings if f.severity is not Severity.info]
    dispute = next(f for f in loud if f.code in ("static_conflict", "dynamic_on_static"))
    assert dispute.code == code, loud
    (moved,) = [f for f in loud if f.code == "urdf_moved"]
    assert moved.cause == dispute.key != "" and moved.frames == ("base_link", "laser")
    assert causes(loud) == [dispute] and report.count(Severity.error) == 1
    assert report.findings.index(moved) == report.findings.index(dispute) + 1  # beneath it


def test_a_moved_joint_without_a_dispute_stands_on_its_own(tmp_path: Path) -> None:
    bag = write_robot_bag(
        tmp_path / "rover.bag", recorded(Setup(description=True, real_origins={"laser_joint": MOVED}))
    )
    (moved,) = [f for f in checked_bag(bag).findings if f.code == "urdf_moved"]
    assert moved.cause == "" and moved.key == ""


def test_links_under_another_parent_skipping_one_link_are_one_layout_with_its_missing_joint_beneath() -> None:
    """tf puts the laser, the camera and the wheels straight under base_footprint; the URDF has base_link between:
    one finding naming every link (none explaining another: ros2_db3_ias0220_gazebo_diff_cont_2025's two wheels
    read "right_wheel ... which explains 1 more finding: left_wheel"), the skipped joint beneath it."""
    laser = ("/tf_static", "base_footprint", "laser", (0.2, 0, 0.25), (0, 0, 0))
    camera = ("/tf_static", "base_footprint", "camera_link", (0.1, 0, 0.4), (0, 0.2, 0))
    left = ("/tf", "base_footprint", "wheel_left_link", (0, 0.15, 0.1), (-math.pi / 2, 0, 0))
    right = ("/tf", "base_footprint", "wheel_right_link", (0, -0.15, 0.1), (-math.pi / 2, 0, 0))
    findings = _on_tf(laser, camera, left, right)
    assert [(f.code, f.frames[1], f.cause) for f in findings] == [
        ("urdf_parent", "laser", ""),
        ("urdf_missing", "base_link", "urdf_parent:1"),
    ], findings
    links = ("laser", "camera_link", "wheel_left_link", "wheel_right_link")
    assert findings[0].frames == ("base_footprint", *links, "base_link")
    assert findings[0].message.startswith(
        "links laser, camera_link, wheel_left_link and wheel_right_link are children of base_footprint on tf, of "
        "base_link in"
    ), findings[0].message


def test_a_link_placed_by_the_kept_message_of_a_dispute_follows_it() -> None:
    """create3's second description puts left_wheel under base_link in the message tf2 keeps: it follows the
    dispute though the two messages do not disagree on it; its skipped joint follows it too."""
    dispute = _f("dynamic_on_static", Severity.error, ("base_link", "bump"), 50, 50)
    elsewhere = _f("urdf_parent", Severity.error, ("base_link", "caster", "mount"), 40, 40)
    wheel = _f("urdf_parent", Severity.error, ("base_link", "left_wheel", "wheel_drop_left"), 50, 50)
    drop = _f("urdf_missing", Severity.error, ("base_link", "wheel_drop_left"))
    found = explain([drop, wheel, elsewhere, dispute])
    assert [(f.code, f.frames[1], f.cause) for f in found] == [
        ("urdf_parent", "caster", ""),
        ("dynamic_on_static", "bump", ""),
        ("urdf_missing", "wheel_drop_left", "dynamic_on_static:1"),  # through the wheel, to the root cause
        ("urdf_parent", "left_wheel", "dynamic_on_static:1"),
    ]


# --- the grouping itself --------------------------------------------------------------------------


def _f(code: str, severity: Severity, frames: tuple[str, ...] = ("a", "b"), first: int = 0, last: int = 0) -> Finding:
    return Finding(severity, code, f"{code} message", f"{code} hint", frames, first_time=first, last_time=last)


LOUD = Rule(frozenset({"cause"}), frozenset({"effect"}), lambda c, f: f.frames == c.frames, "a test's rule")


def test_a_cause_is_as_severe_as_what_follows_from_it_and_comes_first_with_it_beneath() -> None:
    found = explain(
        [_f("other", Severity.error, ("x", "y")), _f("effect", Severity.error), _f("cause", Severity.warning)],
        [LOUD],
    )
    assert [(f.code, f.severity, f.key, f.cause) for f in found] == [
        ("other", Severity.error, "", ""),
        ("cause", Severity.error, "cause:1", ""),
        ("effect", Severity.error, "", "cause:1"),
    ]
    bag = BagReport(("x.bag",), findings=found, start=1, end=2)
    assert bag.count(Severity.error) == 2 and bag.count(Severity.warning) == 0
    assert exit_code([bag]) == 1
    assert explain(found, [LOUD]) == found  # linking again, with nothing added, changes nothing


def test_an_effect_follows_the_first_cause_that_explains_it_and_is_numbered_per_code() -> None:
    found = explain(
        [_f("cause", Severity.error, ("c", "d")), _f("cause", Severity.error), _f("effect", Severity.warning)], [LOUD]
    )
    assert [(f.code, f.key, f.cause) for f in found] == [
        ("cause", "", ""),
        ("cause", "cause:1", ""),
        ("effect", "", "cause:1"),
    ]


def test_a_stall_explains_a_pause_of_its_edges_during_it_only() -> None:
    stall = _f("stall", Severity.warning, ("a", "b", "c", "d"), 10, 20)
    during = _f("rate", Severity.warning, ("c", "d"), 5, 12)
    after = _f("rate", Severity.warning, ("c", "d"), 21, 30)
    elsewhere = _f("rate", Severity.warning, ("b", "c"), 10, 20)
    found = explain([stall, during, after, elsewhere])
    assert [(f.code, f.frames, f.cause) for f in found] == [
        ("stall", stall.frames, ""),
        ("rate", ("c", "d"), "stall:1"),
        ("rate", ("c", "d"), ""),
        ("rate", ("b", "c"), ""),
    ]


# --- renderings ----------------------------------------------------------------------------------


def _report() -> BagReport:
    findings = _stalled()
    return BagReport(
        ("stalled.bag",), findings=findings, formats=("rosbag1",), start=scenes.START, end=scenes.START + 1
    )


def test_text_says_the_cause_once_with_what_follows_beneath_and_counts_causes() -> None:
    out = io.StringIO()
    render.write_text([_report()], Console(file=out, width=400, no_color=True), strict=False)
    text = out.getvalue()
    lines = text.splitlines()
    assert "WARNINGS (1, explaining 3 more)" in lines
    assert sum(line.lstrip().startswith("! stall:") for line in lines) == 1
    beneath = lines.index("      which explains 3 more findings:")
    assert [line.split(":")[0] for line in lines[beneath + 1 : beneath + 4]] == ["      ! rate"] * 3
    assert text.count("hint:") == 1  # what follows has its cause's hint
    assert lines[-1] == "0 errors, 1 warning (explaining 3 more), 0 notes: PASSED"


def test_text_shows_a_few_of_each_code_beneath_a_cause_and_says_how_many_more() -> None:
    cause = _f("cause", Severity.error)
    found = explain([cause, *[_f("effect", Severity.error) for _ in range(8)]], [LOUD])
    out = io.StringIO()
    bag = BagReport(("x.bag",), findings=found, formats=("rosbag1",), start=1, end=2)
    render.write_text([bag], Console(file=out, width=200, no_color=True))
    assert out.getvalue().count("✗ effect: effect message") == render.SHOWN_PER_CODE
    assert "✗ and 3 more effect (--format json lists each)" in out.getvalue()


def test_text_heads_findings_of_the_causes_own_code_as_its_like_not_its_effects() -> None:
    alike = Rule(frozenset({"same"}), frozenset({"same"}), lambda c, f: f.frames != c.frames, "a test's rule")
    found = explain([_f("same", Severity.warning, ("a", "b")), _f("same", Severity.warning, ("c", "d"))], [alike])
    out = io.StringIO()
    bag = BagReport(("x.bag",), findings=found, formats=("rosbag1",), start=1, end=2)
    render.write_text([bag], Console(file=out, width=200, no_color=True))
    assert "      and 1 more finding of the same cause:" in out.getvalue().splitlines()
    assert "which explains" not in out.getvalue()


def test_json_keeps_every_finding_with_its_link_and_counts_causes() -> None:
    document = render.as_dict([_report()], False, Thresholds(), 0)
    bag = document["bags"][0]
    assert [(f["code"], f["key"], f["cause"]) for f in bag["findings"]] == [
        ("stall", "stall:1", ""),
        *[("rate", "", "stall:1")] * 3,
    ]
    assert bag["summary"] == {"errors": 0, "warnings": 1, "notes": 0, "explained": 3}
    assert document["summary"]["explained"] == 3


def test_json_lines_read_back_keep_the_links() -> None:
    out = io.StringIO()
    write_recording(_report(), out, strict=False)
    (back,) = read_report(io.BytesIO(out.getvalue().encode()), "report.jsonl").reports
    assert [(f.code, f.key, f.cause) for f in back.findings] == [(f.code, f.key, f.cause) for f in _report().findings]


def test_junit_fails_the_causes_case_with_what_follows_and_leaves_the_others_passing() -> None:
    root = render.junit([_report()], strict=True)
    cases = {case.get("name"): case for case in root.iter("testcase")}
    failure = cases["stall"].find("failure")
    assert failure is not None and failure.text is not None
    assert "explains 3 more findings (stall:1):" in failure.text and failure.text.count("\n  warning: rate:") == 3
    assert cases["rate"].find("failure") is None
    out = cases["rate"].find("system-out")
    assert out is not None and out.text is not None and out.text.count("follows from stall:1") == 3
    assert root.get("failures") == "1"
    ET.fromstring(ET.tostring(root))


def test_view_frames_counts_causes_and_puts_what_follows_beneath() -> None:
    recording = scenes.recording(STALL.make())
    graph = frame_graph(Scene(recording))
    assert graph_render.problem_summary(graph.findings) == "1 warning (explaining 3 more)"
    source = graph_render.to_digraph(graph, ["stalled"]).source
    assert source.count("follows from [1]") == 3


# --- real recordings ------------------------------------------------------------------------------

CORPUS = shared_dir() / "corpus"
NAV2 = CORPUS / "ros2_mcap_nav2_turtlebot4.mcap"
CREATE3 = CORPUS / "ros2_db3_create3_real_two_urdfs"


@pytest.mark.skipif(not NAV2.exists(), reason=f"{NAV2} is not placed")
def test_nav2_turtlebot4_one_stall_of_every_edge_at_41_s_not_four_warnings() -> None:
    report = checked_bag(NAV2)
    loud = [f for f in causes(report.findings) if f.severity is not Severity.info]
    assert [f.code for f in loud] == ["stall"], report.findings
    (stall,) = loud
    assert stall.message.startswith(
        "all 4 moving edges went silent within 0.778 s of each other, from 969.624 (+40.8 s)"
    )
    assert "the recorder received no transform on /tf for 1.9 s" in stall.message
    assert sorted(f.frames for f in explained(report.findings, stall)) == [
        ("base_link", "left_wheel"),
        ("base_link", "right_wheel"),
        ("map", "odom"),
        ("odom", "base_link"),
    ]
    assert exit_code([report]) == 0


@pytest.mark.skipif(not CREATE3.exists(), reason=f"{CREATE3} is not placed")
def test_create3_every_moved_joint_follows_the_disputed_statics() -> None:
    """The recorded /robot_description agrees with the first of two /tf_static messages; tf2 keeps the second:
    each of the 21 joints the second moved is said beneath the one static_conflict (ROS 2's, inferred from the
    messages' shape)."""
    report = checked_bag(CREATE3)
    errors = [f for f in report.findings if f.severity is Severity.error]
    (cause,) = causes(errors)
    assert cause.code == "static_conflict" and cause.last_time == 1663967376153481824  # the message tf2 keeps
    following = explained(report.findings, cause)
    assert len(errors) == 1 + len(following) and report.count(Severity.error) == 1 and exit_code([report]) == 1
    codes = [f.code for f in following]
    assert (codes.count("urdf_moved"), codes.count("urdf_parent"), codes.count("urdf_missing")) == (21, 2, 2)
    assert {f.frames[1] for f in following if f.code == "urdf_parent"} == {"left_wheel", "right_wheel"}
    document = json.loads(json.dumps(render.bag_dict(report, False)))
    assert len(document["findings"]) == len(report.findings)
    assert document["summary"]["errors"] == 1 and document["summary"]["explained"] == len(report.findings) - len(
        causes(report.findings)
    )


def test_a_cause_and_its_consequences_in_a_scene_read_from_a_bag(tmp_path: Path) -> None:
    """The stall scene written as a ROS 2 bag and read back: the same one cause (``read_recording``'s path)."""
    bag = scenes.write(tmp_path, "stalled", BagFormat.rosbag2_sqlite3, STALL.make())
    findings = check(read_recording([bag])).findings
    assert [(f.code, f.cause) for f in findings if f.severity is not Severity.info] == [
        ("stall", ""),
        *[("rate", "stall:1")] * 3,
    ]


def test_the_report_lists_what_follows_beneath_its_cause_and_counts_causes() -> None:
    section = recording_section(0, report(scenes.recording(STALL.make())))
    assert section.summary == "1 warning (explaining 3 more)"
    assert section.html.count('class="finding warning explained"') == 3
    assert section.html.count('<span class="follows">follows from [1]</span>') == 3
    assert section.html.index("<code>stall</code>") < section.html.index("<code>rate</code>")


class _Unread(list[Finding]):
    """Findings that fail a test when scanned."""

    def __iter__(self) -> Iterator[Finding]:
        raise AssertionError("scanned")


def test_a_finding_that_explains_nothing_is_answered_without_a_scan() -> None:
    """Issue 44's floods: asked of each of 40,000 findings (20,000 frames heard once: stale and delay each), a
    scan of all per finding kept wtf --ros2 writing for minutes."""
    lone = Finding(Severity.error, "stale", "stale message", "stale hint", ("a", "b"))
    assert explained(_Unread(), lone) == []


def test_many_findings_each_follow_their_own_cause_in_order() -> None:
    """The findings gathered per cause in one pass come out as the scan per cause gave them."""
    findings = [
        Finding(Severity.error, "stale", "m", "h", (f"f{i}", "root"), key=f"stale:{i + 1}") for i in range(3)
    ] + [Finding(Severity.warning, "delay", "m", "h", (f"f{i % 3}", "x"), cause=f"stale:{i % 3 + 1}") for i in range(9)]
    for cause in findings[:3]:
        assert explained(findings, cause) == [f for f in findings[3:] if f.cause == cause.key]


def test_findings_of_one_flooding_message_are_linked_by_key_not_compared_pairwise() -> None:
    """Issue 44's frame flood (20,000 new frames in one message, each going stale at one stamp) took minutes
    once stale edges of one message were said once: causes are looked up by the rule's keys, so the rule's
    test runs about once per finding, not once per pair."""
    compared = 0

    def same_moment(cause: Finding, finding: Finding) -> bool:
        nonlocal compared
        compared += 1
        return (cause.first_time, cause.last_time) == (finding.first_time, finding.last_time)

    keyed = Rule(
        frozenset({"stale"}),
        frozenset({"stale"}),
        same_moment,
        "a test's keyed rule",
        keys=lambda f: ((f.first_time, f.last_time),),
    )
    # 50 messages of 100 new frames each, each message's edges stopping at its own stamp
    flood = [_f("stale", Severity.error, ("root", f"r{i}"), first=i // 100, last=i // 100) for i in range(5_000)]
    found = explain(flood, [keyed])
    assert len([f for f in found if f.key]) == 50 and sum(f.cause == "stale:1" for f in found) == 99
    assert compared < 2 * len(flood)  # compared pairwise: ~n²/2


@pytest.mark.parametrize(("both_parents_from_one", "beneath"), [(False, True), (True, False)])
def test_a_frame_two_disputing_descriptions_place_apart_follows_their_static_conflict(
    both_parents_from_one: bool, beneath: bool
) -> None:
    """ros1_gtbox_tf_static.bag with its 2025 calibration (-b both): prism_model under prism in one, under
    box_base in the other, was an error of its own beside the static_conflict of the same two descriptions.
    Where one description itself sends the frame under both parents (the 2025 file's box_base_model), that
    is its own mistake: it stands alone."""
    start = scenes.START
    laser = [scenes._t("mount", "laser", start, 0.2)]
    if both_parents_from_one:
        laser.append(scenes._t("base_link", "laser", start, 0.2))
    second = TfMessage(
        "/tf_static",
        start + NS_PER_S,
        [scenes._t("base_link", "camera", start, 0.25), scenes._t("base_link", "mount", start, 0.1), *laser],
        "/calibration",
    )
    found = check(scenes.recording(scenes.with_extra([second]))).findings
    (conflict,) = [f for f in found if f.code == "static_conflict"]
    (parents,) = [f for f in found if f.code == "multiple_parents"]
    assert parents.frames[0] == "laser"
    assert parents.figures["parents_each_from_other_static_publishers"] == int(not both_parents_from_one)
    assert (parents.cause == conflict.key != "") is beneath
    assert causes([f for f in found if f.severity is Severity.error]) == (
        [conflict] if beneath else [conflict, parents]
    )


def _constant(parent: str, child: str, by: str) -> Finding:
    return Finding(
        Severity.warning, "static_on_dynamic", f"{parent} -> {child} never changes", "", (parent, child), (by,)
    )


def test_constant_edges_of_one_node_are_one_finding_with_its_edges_beneath() -> None:
    """Stage's stageros sends each robot's base_footprint -> base_link and base_link -> laser on /tf, constant (the
    Stage bag: 6 warnings of one node); another node's constant edge stays its own, and a ROS 2 bag's findings,
    which name only the topic /tf, are not lumped together."""
    stage = [_constant(f"r{r}/{p}", f"r{r}/{c}", "/stageros") for r in range(3) for p, c in [("a", "b"), ("b", "c")]]
    found = explain([*stage, _constant("r0/c", "map", "/local_map")])
    assert len(causes(found)) == 2 and [f.cause for f in found].count("static_on_dynamic:1") == 5
    ros2 = explain([_constant("a", "b", "/tf"), _constant("c", "d", "/tf")])
    assert not any(f.cause for f in ros2)


def test_edges_of_one_message_in_a_bag_naming_no_node_are_one_finding() -> None:
    """A real JetAcker's ROS 2 bag (ros2_db3_jetacker_real_two_odometries): base_link -> link1 and link1 -> w_link,
    sent in one message, were two static_on_dynamic warnings and two time_backwards warnings alike (the same 570
    transforms, the same 7 out of order at the same stamps); Franka teleop's MCAP sends base and fr3_link0 on
    /tf_static and /tf in the same messages (two mixed_static errors). Seen at the same moments as often, they
    are one finding with the other edge beneath; at other moments, or one edge's two kinds, they stay apart."""
    t0, t1 = 1_757_445_700 * NS_PER_S, 1_757_445_880 * NS_PER_S

    def joint(code: str, parent: str, child: str, first: int = t0, count: int = 570) -> Finding:
        return Finding(Severity.warning, code, f"{parent} -> {child}", "", (parent, child), ("/tf",), first, t1, count)

    for code in ("static_on_dynamic", "time_backwards", "mixed_static"):
        found = explain([joint(code, "base_link", "link1"), joint(code, "link1", "w_link")])
        assert [f.cause for f in found] == ["", f"{code}:1"], found
        elsewhere = explain([joint(code, "base_link", "link1"), joint(code, "link1", "w_link", first=t0 + 1)])
        assert not any(f.cause for f in elsewhere)
    one_edge = explain([joint("time_backwards", "a", "b", count=7), joint("time_backwards", "a", "b", count=7)])
    assert not any(f.cause for f in one_edge)
    named = [dataclasses.replace(joint("static_on_dynamic", "a", "b"), authorities=(node,)) for node in ("/x", "/y")]
    assert not any(f.cause for f in explain(named)), "two named nodes' edges stay apart at the same moments"


def _extra(parent: str, frame: str) -> Finding:
    return Finding(Severity.info, "urdf_extra", f"{frame} is not a link", "", (parent, frame), ("/tf",))


def test_frames_a_description_lacks_under_one_it_lacks_follow_from_the_top_one() -> None:
    """The drone beside a car (ros2_db3_pfms_drone_beside_car_2024): the car's 9 frames, none in the drone's URDF,
    were 9 notes; the car's top frame is one, with the rest beneath. A frame under a described link stays apart."""
    car = [("world", "car/base"), ("car/base", "car/steer"), ("car/steer", "car/wheel"), ("car/base", "car/laser")]
    found = explain([*(_extra(*pair) for pair in car), _extra("drone/base", "drone/camera")])
    assert [f.frames[1] for f in causes(found)] == ["car/base", "drone/camera"]
    assert sum(f.cause == "urdf_extra:1" for f in found) == 3
