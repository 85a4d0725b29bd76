"""Publishers told apart where a ROS 2 bag names none: from stamps, values, arrival times, message shapes
and metadata.yaml's count of publishers; first on designed recordings, then on the real ones that showed
each case (../shared/corpus)."""

from __future__ import annotations

import contextlib
import math
import shutil
import sqlite3
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import yaml

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tests.corpus import data
from tests.corpus.fetch import shared_dir
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.recording import read_recording

MS = scenes.MS
START = scenes.START


def loud(findings: list[Finding]) -> list[Finding]:
    return [f for f in findings if f.severity is not Severity.info]


def coded(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code]


def _ros2_bag(tmp_path: Path, messages: list[TfMessage], listed: dict[str, int]) -> Path:
    """``messages`` as a rosbag2 recording whose metadata.yaml lists ``listed[topic]`` publishers of a topic
    (as ros2 bag record does: one offered QoS profile per publisher it found when it began)."""
    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_sqlite3, sorted(messages, key=lambda m: m.record_time))
    metadata = bag / "metadata.yaml"
    document = yaml.safe_load(metadata.read_text())
    for entry in document["rosbag2_bagfile_information"]["topics_with_message_count"]:
        topic = entry["topic_metadata"]
        if topic["name"] in listed:
            profile = {"history": "keep_last", "depth": 1, "reliability": "reliable", "durability": "volatile"}
            if topic["name"].endswith("tf_static"):
                profile["durability"] = "transient_local"
            topic["offered_qos_profiles"] = [dict(profile) for _ in range(listed[topic["name"]])]
    metadata.write_text(yaml.safe_dump(document))
    return bag


def _findings(tmp_path: Path, messages: list[TfMessage], listed: dict[str, int]) -> list[Finding]:
    return check(read_recording([_ros2_bag(tmp_path, messages, listed)])).findings


# --- (a) one publisher re-sending its last value ----------------------------------------------------


def _webots_odometry() -> list[TfMessage]:
    """Webots' diff-drive controller: a steady ~49 Hz wall-clock timer sending the odometry of a simulation
    that steps 20 ms at a time, each step done a little sooner or later in wall time; when no step was done
    between two ticks, the tick sends the last stamp and value again."""
    done = np.maximum.accumulate(np.arange(520) * 20 * MS + np.random.default_rng(39).uniform(-8 * MS, 8 * MS, 520))
    messages = []
    for tick in range(490):
        wall = round(tick * 20.4 * MS)
        step = int(np.searchsorted(done, wall, side="right")) - 1  # the last step done by this tick
        messages.append(TfMessage("/tf", START + wall + scenes.DELAY, scenes.odom_base(START + step * 20 * MS), ""))
    return messages


def _slam_corrections() -> list[TfMessage]:
    """slam_toolbox: map -> odom sent on every 20 ms loop, stamped with the scan it was computed from: a
    new correction every 4 to 8 loops, the last one sent again in between."""
    messages, loop = [], 0
    for scan, loops in enumerate([4, 6, 8, 5, 7] * 16):
        stamp = START + loop * 20 * MS - 3 * MS  # the scan came just before
        correction = [scenes._t("map", "odom", stamp, 1.0 + 0.01 * scan, 0.002 * scan)]
        for _ in range(loops):
            messages.append(TfMessage("/tf", START + loop * 20 * MS + scenes.DELAY, correction, ""))
            loop += 1
    return messages


@pytest.mark.parametrize(
    ("part", "make", "frames", "times"),
    [
        ("ekf", _webots_odometry, ("odom", "base_link"), "2 times each"),
        ("amcl", _slam_corrections, ("map", "odom"), "4 to 8 times each"),
    ],
    ids=["webots", "slam_toolbox"],
)
def test_one_publisher_re_sending_its_last_value_is_a_note_saying_so(
    tmp_path: Path, part: str, make: Callable[[], list[TfMessage]], frames: tuple[str, str], times: str
) -> None:
    sent = make()
    findings = _findings(tmp_path, scenes.healthy(**{part: sent}), {"/tf": 1})
    assert loud(findings) == [], findings
    assert coded(findings, "multiple_authorities") == []
    (note,) = coded(findings, "resent")
    assert note.severity is Severity.info and note.frames == frames
    stamps = np.array([m.transforms[0].stamp for m in sent])
    distinct, counts = np.unique(stamps, return_counts=True)
    said = f"{(counts > 1).sum()} of its {len(distinct)} stamps arrived again ({times}), with identical values"
    assert said in note.message, note.message
    assert "each time the newest stamp sent so far" in note.message
    assert "metadata.yaml lists 1 publisher of /tf" in note.message
    assert note.message.endswith("one publisher re-sending its last value, not two")
    assert note.figures["stamps_sent_again"] == (counts > 1).sum() and note.figures["publishers_listed"] == 1
    assert not [f for f in findings if "taking turns" in f.message]


def test_one_publisher_re_valuing_its_newest_stamp_is_one_note_and_the_stamp_where_it_matters(tmp_path: Path) -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map: slam_toolbox sent identity twice at one stamp, then its first
    correction at the same stamp 77 times; the re-sends got no note (one stamp re-valued) and the re-valued stamp
    was said without what ROS 2's tf2 does with it."""
    sent = _slam_corrections()
    stamp = sent[10].transforms[0].stamp
    at = [i for i, m in enumerate(sent) if m.transforms[0].stamp == stamp]
    for i in at[:2]:  # the first two sends of that stamp: identity
        sent[i] = TfMessage("/tf", sent[i].record_time, [scenes._t("map", "odom", stamp, 0.0)], "")
    findings = _findings(tmp_path, scenes.healthy(amcl=sent), {"/tf": 1})
    assert coded(findings, "multiple_authorities") == []
    (note,) = coded(findings, "resent")
    assert "with identical values but 1 stamp that came again with another value" in note.message
    assert note.message.endswith("one publisher re-sending its last value, not two")
    assert note.figures["stamps_revalued"] == 1 and "time_backwards" in note.hint
    (backwards,) = [f for f in loud(findings) if f.frames == ("map", "odom")]
    assert (backwards.code, backwards.severity) == ("time_backwards", Severity.warning)
    assert f"1 stamp it had already sent came again with other values ({len(at) - 2} transforms)" in backwards.message
    assert "lookups at the stamp and up to the next one answer from the one received last" in backwards.message


# --- (b) a stepped simulation clock -----------------------------------------------------------------


def test_intervals_alternating_on_a_stepped_clock_are_one_publisher_and_no_finding(tmp_path: Path) -> None:
    """A TurtleBot 4 in Ignition: one publisher whose samples come 15 then 82 ms apart (the simulation's
    steps), stamps rising, motion smooth: it was "two steady 10.3 Hz streams taking turns"."""
    arrivals = np.cumsum([0] + [15 * MS if i % 2 == 0 else 82 * MS for i in range(199)])
    odometry = [TfMessage("/tf", START + int(t) + scenes.DELAY, scenes.odom_base(START + int(t)), "") for t in arrivals]
    findings = _findings(tmp_path, scenes.healthy(ekf=odometry), {"/tf": 1})
    assert coded(findings, "multiple_authorities") == [] and loud(findings) == [], findings


# --- (c) two identical publishers -------------------------------------------------------------------


def _two_wheels(stamp: int) -> list[Transform]:
    (left,) = scenes.wheel(stamp)
    right = Transform((0.0, -0.2, 0.0), left.rotation, stamp, "base_link", "wheel_right")
    return [left, right]


def _two_robot_state_publishers() -> list[TfMessage]:
    """Two robot_state_publishers fed the same joint states: each sends every wheel sample, 50 us apart."""
    first = scenes.periodic("", 20, _two_wheels)
    return first + [TfMessage("/tf", m.record_time + 50_000, m.transforms, "") for m in first]


@pytest.mark.parametrize(("listed", "conclusion"), [(2, "two identical publishers"), (1, "sending each sample twice")])
def test_two_identical_publishers_are_one_warning_for_all_their_edges(
    tmp_path: Path, listed: int, conclusion: str
) -> None:
    findings = _findings(tmp_path, scenes.healthy(wheels=_two_robot_state_publishers()), {"/tf": listed})
    (finding,) = loud(findings)
    assert (finding.code, finding.severity) == ("multiple_authorities", Severity.warning)
    assert finding.frames == ("base_link", "wheel", "base_link", "wheel_right")
    assert finding.message.startswith(
        "base_link -> wheel and base_link -> wheel_right on /tf arrive twice: 400 of their 400 stamps arrived "
        "again (2 times each), 50 us after the sample before them (new samples come every 50.0 ms); at the same "
        f"times their values are the same, over 800 samples compared; metadata.yaml lists {listed} publisher"
    ), finding.message
    assert conclusion in finding.message and finding.figures["edges"] == 2


def test_two_publishers_of_the_same_stamps_that_disagree_are_one_warning_for_every_edge(tmp_path: Path) -> None:
    """A second robot_state_publisher whose URDF puts both wheels 5 cm further out: one finding for both
    edges, which no other check reports again (their stamps come twice, with other values)."""
    first = scenes.periodic("", 20, _two_wheels)
    shifted = [TfMessage("/tf", m.record_time + 50_000, [_moved(t, 0.05) for t in m.transforms], "") for m in first]
    findings = _findings(tmp_path, scenes.healthy(wheels=first + shifted), {"/tf": 2})
    (finding,) = loud(findings)
    assert finding.code == "multiple_authorities"
    assert finding.frames == ("base_link", "wheel", "base_link", "wheel_right")
    # the wording and figures of every multiple_authorities finding (the Stage bag's named publishers too)
    assert "at the same times their values are up to 50.0 mm (at +0.0 s) apart, over 800 samples" in finding.message
    assert finding.figures["apart_m_max"] == pytest.approx(0.05) and finding.figures["samples_compared"] == 800
    assert "mix" in finding.hint


def _ground_truth_on_a_coarse_clock() -> list[TfMessage]:
    """One publisher of the ground truth at 500 Hz, each sample a little further (0.1 mm), stamped from a
    simulation clock that ticks every 2 to 24 of its samples, arriving within the same ms: a stamp repeated
    2 to 24 times with other values (the Guardian's Gazebo model in the ship interior, 2014)."""
    messages, stamp, left = [], START, 2
    for i in range(1000):
        if left == 0:
            stamp, left = START + i * 2 * MS, (2, 24, 5, 11)[i % 4]
        left -= 1
        truth = Transform((0.0001 * i, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "base_footprint", "ground_truth")
        messages.append(TfMessage("/tf", START + (i * 2 // 10) * 10 * MS, [truth], ""))
    return messages


def test_a_stamp_one_publisher_repeats_2_to_24_times_is_no_pair_of_identical_publishers(tmp_path: Path) -> None:
    """Two identical publishers send each stamp twice; a stamp sent 2 to 24 times, each with another value, is one
    publisher whose clock does not advance: tf2 drops the repeats (time_backwards), no second publisher to stop."""
    findings = _findings(tmp_path, scenes.healthy() + _ground_truth_on_a_coarse_clock(), {"/tf": 1})
    assert not [f for f in coded(findings, "multiple_authorities") if "ground_truth" in f.frames], findings
    (repeated,) = [f for f in coded(findings, "time_backwards") if "ground_truth" in f.frames]
    assert "already sent came again with other values" in repeated.message, repeated.message


def _moved(t: Transform, y: float) -> Transform:
    x, y0, z = t.translation
    return Transform((x, y0 + (y if y0 > 0 else -y), z), t.rotation, t.stamp, t.frame_id, t.child_frame_id)


# --- (d) publishers taking turns with different values ----------------------------------------------


def test_two_odometries_taking_turns_far_apart_are_an_error_with_what_was_seen(tmp_path: Path) -> None:
    """Two odometries 0.3 m apart taking turns, each moving millimetres a sample (the real JetAcker's: 0.13-0.14 m
    and 5-6° apart at every common time): they contradict each other, an error, said after what was seen."""
    second = scenes.periodic(
        "", 50, lambda t: [scenes._t("odom", "base_link", t, 0.4 * scenes._s(t) + 0.3)], phase=0.01
    )
    findings = _findings(tmp_path, scenes.healthy(ekf=scenes.ekf() + second), {"/tf": 2})
    (finding,) = loud(findings)
    assert (finding.code, finding.severity) == ("multiple_authorities", Severity.error)
    assert "its value alternated between two places" in finding.message
    assert "metadata.yaml lists 2 publishers of /tf" in finding.message
    said = finding.message
    assert said.index("alternated") < said.index("taking turns") < said.index("they contradict each other")
    assert finding.figures["contradict"] == 1
    assert int(finding.figures["values_alternating"]) >= 900


def test_two_odometries_taking_turns_say_how_far_apart_they_are_as_two_named_publishers_do(tmp_path: Path) -> None:
    """Issue 39: told apart from the data alone (no publisher names), the two odometries of one edge are
    compared at the same times as two named publishers are (``figures.disagreement``): 0.3 m apart in x,
    their headings 0.1 rad a second apart (one turns, the other does not)."""
    second = scenes.periodic(
        "", 50, lambda t: [scenes._t("odom", "base_link", t, 0.4 * scenes._s(t) + 0.3)], phase=0.01
    )
    findings = _findings(tmp_path, scenes.healthy(ekf=scenes.ekf() + second), {"/tf": 2})
    (finding,) = loud(findings)
    assert finding.code == "multiple_authorities"
    assert "at the same times their values are up to 300.0 mm" in finding.message, finding.message
    assert finding.figures["apart_m_max"] == pytest.approx(0.3, abs=1e-9)
    turned = np.degrees(0.1 * scenes.SECONDS)  # the one odometry's heading at the end; the other's is 0
    assert finding.figures["apart_deg_max"] == pytest.approx(turned, abs=0.2)
    assert int(finding.figures["samples_compared"]) > 900
    said = finding.message
    assert said.index("alternated") < said.index("apart") < said.index("taking turns")


def _wheel_half_turns(stamp: int) -> list[Transform]:
    """A real Neato's wheel sent at 2.4 Hz while the robot drives: 165 degrees between samples."""
    angle = math.radians(165.0) * 2.4 * scenes._s(stamp)
    return [Transform.from_rpy((0.0, 0.2, 0.0), (0.0, angle % (2 * math.pi), 0.0), stamp, "base_link", "wheel")]


def test_a_wheel_turning_nearly_half_a_turn_between_samples_is_one_publisher(tmp_path: Path) -> None:
    """ros2_db3_neato_obstacle_avoider_burst_2023: one publisher (metadata.yaml) whose wheel turns 150-177
    degrees between samples 0.4 s apart comes back within 30 degrees of where it was two samples before,
    each time further on: it was "alternated between two places 10 times in 64 new samples"."""
    wheel = scenes.periodic("", 2.4, _wheel_half_turns)
    findings = _findings(tmp_path, scenes.healthy(wheels=wheel), {"/tf": 1})
    assert coded(findings, "multiple_authorities") == [], findings
    assert not [f for f in findings if "taking turns" in f.message]


def test_a_wheel_turning_half_turns_beside_a_second_publisher_still_tells_the_odometries_apart(tmp_path: Path) -> None:
    """The wheel's half turns do not hide two odometries taking turns on another edge of the same recording."""
    second = scenes.periodic(
        "", 50, lambda t: [scenes._t("odom", "base_link", t, 0.4 * scenes._s(t) + 0.3)], phase=0.01
    )
    messages = scenes.healthy(ekf=scenes.ekf() + second, wheels=scenes.periodic("", 2.4, _wheel_half_turns))
    (finding,) = coded(_findings(tmp_path, messages, {"/tf": 2}), "multiple_authorities")
    assert finding.frames == ("odom", "base_link") and "alternated between two places" in finding.message


def test_two_odometries_of_a_fast_robot_taking_turns_are_still_two_though_no_track_can_be_followed(
    tmp_path: Path,
) -> None:
    """At 0.5 m/s and 5 Hz each, either odometry moves 0.1 m between its own samples: too far for a track to be
    followed (``_tracks_apart``), but the values still go 0.6 m over and back, sample after sample: the
    half-turning wheel's leniency (a value turning as far as it comes back) is for rotations only."""
    first = scenes.periodic("/ekf", 5, lambda t: [scenes._t("odom", "base_link", t, 0.5 * scenes._s(t))])
    second = scenes.periodic("", 5, lambda t: [scenes._t("odom", "base_link", t, 0.5 * scenes._s(t) + 0.6)], phase=0.1)
    findings = _findings(tmp_path, scenes.healthy(ekf=sorted(first + second, key=lambda m: m.record_time)), {"/tf": 2})
    (finding,) = coded(findings, "multiple_authorities")
    assert finding.frames == ("odom", "base_link") and "alternated between two places" in finding.message


# --- /tf_static publishers that disagree, in ROS 2 --------------------------------------------------


def _static(record: int, transforms: list[tuple[str, float, float]]) -> TfMessage:
    return TfMessage("/tf_static", record, [scenes._t("base_link", c, START, x, yaw) for c, x, yaw in transforms], "")


def test_a_static_message_lacking_an_earlier_ones_transforms_is_another_publisher(tmp_path: Path) -> None:
    """Create 3: the robot's own 5 static transforms, then robot_state_publisher's 3, 0.6 s later, with other
    values for them: two publishers (a StaticTransformBroadcaster re-sends all of its transforms in every
    message), though metadata.yaml lists one (the second started after recording began)."""
    robot = _static(START + 100 * MS, [("bump", 0.175, 0.0), ("cliff", 0.16, 1.0), ("mouse", 0.1, 3.14), *_OWN])
    description = _static(START + 700 * MS, [("bump", 0.0, 0.0), ("cliff", 0.146, 0.0), ("mouse", 0.1, 0.0)])
    findings = _findings(tmp_path, [*scenes.healthy(statics=[]), robot, description], {"/tf_static": 1})
    (conflict,) = loud(findings)
    assert (conflict.code, conflict.severity, conflict.count) == ("static_conflict", Severity.error, 3)
    assert set(conflict.frames) == {"base_link", "bump", "cliff", "mouse"}
    message = conflict.message
    assert "/tf_static came from 2 publishers, told apart by their messages" in message
    assert (
        "publisher 1: 7 transforms at 1700000000.100 (+0.1 s); publisher 2: 3 transforms at 1700000000.700 (+0.7 s), "
        "which lacks 4 of publisher 1's 7 transforms (C++'s StaticTransformBroadcaster, robot_state_publisher's and "
        "static_transform_publisher's, re-sends all of its transforms in every message). They send different values "
        "for 3 static transforms"
    ) in message
    assert "base_link -> bump (175.0 mm and 0.00° apart)" in message
    assert message.endswith("tf2 keeps the values last received for every time: publisher 2's")
    assert conflict.figures["transforms_differing"] == 3 and conflict.figures["apart_m_max"] == pytest.approx(0.175)
    assert "ros2 topic info /tf_static --verbose" in conflict.hint


_OWN = [("imu", 0.0, 0.0), ("ir", 0.05, 0.0), ("button", 0.02, 0.0), ("omni", 0.01, 0.0)]


def _neato(listed: int, tmp_path: Path, sent: int = START, apart: int = 4 * MS) -> list[Finding]:
    """A Neato: a static_transform_publisher of the laser at (-0.1016, 0, 0.0889), then ``apart`` later
    robot_state_publisher's 10 fixed joints, the laser among them at (-0.084, 0, 0.166); both stamped ``sent``
    (the second 4 ms later)."""
    return _findings(tmp_path, _neato_messages(sent, apart), {"/tf_static": listed})


def _neato_messages(sent: int = START, apart: int = 4 * MS) -> list[TfMessage]:
    laser = TfMessage(
        "/tf_static", START + DELAY, [Transform((-0.1016, 0, 0.0889), (0, 0, 0, 1), sent, "base_link", "laser")]
    )
    later = sent + 4 * MS
    joints = [Transform((0.01 * i, 0, 0), (0, 0, 0, 1), later, "base_link", f"part{i}") for i in range(9)]
    urdf_laser = Transform((-0.084, 0, 0.166), (0, 0, 0, 1), later, "base_link", "laser")
    description = TfMessage("/tf_static", START + DELAY + apart, [*joints, urdf_laser])
    return sorted([*scenes.healthy(statics=[]), laser, description], key=lambda m: m.record_time)


DELAY = scenes.DELAY


def test_two_static_publishers_listed_in_the_metadata_that_disagree_are_a_static_conflict(tmp_path: Path) -> None:
    (conflict,) = loud(_neato(2, tmp_path))
    assert (conflict.code, conflict.count, conflict.frames) == ("static_conflict", 1, ("base_link", "laser"))
    assert (
        "publisher 1: 1 transform at 1700000000.002 (+0.0 s); publisher 2: 10 transforms at 1700000000.006 (+0.0 s), "
        "which differs in value from publisher 1's while metadata.yaml lists 2 publishers of /tf_static"
    ) in conflict.message
    assert "base_link -> laser (79.1 mm and 0.00° apart)" in conflict.message
    assert "up to" not in conflict.message  # one transform: its figures once (the real Neatos said them twice)


@pytest.mark.parametrize("listed", [1, 2])
def test_a_db3_given_alone_counts_publishers_by_its_topics_table(tmp_path: Path, listed: int) -> None:
    """The .db3 of a bag without its metadata.yaml (copied alone): its topics table holds the same offered QoS
    profiles, one per publisher, and the publishers are counted by it as by metadata.yaml. Counted by nothing,
    the corpus's two Neatos with two /tf_static publishers (ros2_db3_neato_real_drive_square_earljr_2023,
    ros2_db3_neato_obstacle_avoider_burst_2023) given as their .db3 alone, or as one .mcap, said
    dynamic_on_static where their folders say static_conflict."""
    _neato(listed, tmp_path)
    (db3,) = (tmp_path / "bag_rosbag2-sqlite3").glob("*.db3")
    alone = tmp_path / "alone" / db3.name
    alone.parent.mkdir()
    shutil.copyfile(db3, alone)
    profile = "- {history: keep_last, depth: 1, reliability: reliable, durability: transient_local}\n"
    with contextlib.closing(sqlite3.connect(alone)) as db, db:
        db.execute("UPDATE topics SET offered_qos_profiles = ? WHERE name = '/tf_static'", (profile * listed,))
    (finding,) = loud(check(read_recording([alone])).findings)
    assert finding.code == ("static_conflict" if listed == 2 else "dynamic_on_static"), finding.message
    assert finding.frames == ("base_link", "laser")
    _count_said_by(finding, "the .db3's topics table", listed)


def _count_said_by(finding: Finding, source: str, listed: int) -> None:
    """The finding names where the count it gives came from: the file's own, never a metadata.yaml it lacks (a bare
    file said "metadata.yaml lists 2 publishers")."""
    said = f"while {source} lists 2 publishers of /tf_static" if listed == 2 else f"; {source} lists 1 publisher of it"
    assert said in finding.message and "metadata.yaml" not in finding.message, finding.message


@pytest.mark.parametrize("listed", [1, 2])
def test_an_mcap_given_alone_counts_publishers_by_its_channels_and_says_so(tmp_path: Path, listed: int) -> None:
    """A rosbag2 .mcap given alone: its /tf_static channel's metadata holds the offered QoS profiles, one per
    publisher; the finding counts by them and names them (the real Neato's .mcap alone said "metadata.yaml
    lists 2 publishers")."""
    from tests.corpus.variants import rewrite_mcap

    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_mcap, _neato_messages())
    (mcap,) = bag.glob("*.mcap")
    profile = "- {history: keep_last, depth: 1, reliability: reliable, durability: transient_local}\n"

    def listing(metadata: dict[str, str]) -> dict[str, str]:
        static = "transient_local" in metadata.get("offered_qos_profiles", "")  # /tf_static's, as scenes write it
        return {**metadata, "offered_qos_profiles": profile * listed} if static else metadata

    alone = rewrite_mcap(mcap, tmp_path / "alone.mcap", listing)
    (finding,) = loud(check(read_recording([alone])).findings)
    assert finding.code == ("static_conflict" if listed == 2 else "dynamic_on_static"), finding.message
    _count_said_by(finding, "the MCAP's channel metadata", listed)


def test_statics_recorded_a_hair_before_the_first_tf_stamp_are_at_plus_zero_not_minus_zero(tmp_path: Path) -> None:
    """A real Neato (ros2-neato-real-two-static-publishers-2023b-db3): both /tf_static messages recorded in the
    recording's first millisecond, a hair before the first /tf stamp: "(-0.0 s)" was said of publisher 1."""
    laser = TfMessage(
        "/tf_static", START - MS, [Transform((-0.1016, 0, 0.0889), (0, 0, 0, 1), START, "base_link", "laser")]
    )
    urdf = TfMessage("/tf_static", START, [Transform((-0.084, 0, 0.166), (0, 0, 0, 1), START, "base_link", "laser")])
    (conflict,) = loud(_findings(tmp_path, [*scenes.healthy(statics=[]), laser, urdf], {"/tf_static": 2}))
    assert "publisher 1: 1 transform at 1699999999.999 (+0.0 s); publisher 2: 1 transform at" in conflict.message
    assert "-0.0" not in conflict.message


def test_one_static_publisher_that_changed_a_value_is_still_dynamic_on_static(tmp_path: Path) -> None:
    """The same messages from the one publisher metadata.yaml lists: its next message holds all of its
    transforms, one with another value: it changed its mind."""
    (finding,) = loud(_neato(1, tmp_path))
    assert (finding.code, finding.frames) == ("dynamic_on_static", ("base_link", "laser"))
    assert "holds every transform of the one before it" in finding.message
    assert "metadata.yaml lists 1 publisher of it: one publisher, it seems" in finding.message


def test_two_static_messages_both_sent_long_before_the_recording_are_two_publishers(tmp_path: Path) -> None:
    """A real Neato (ros2_db3_neato_real_person_follower_moampane_2023): the same two messages, received 1.06 s
    apart, both stamped 562 s before the recording began, metadata.yaml listing one publisher: tfx said
    dynamic_on_static ('one publisher, it seems'). A late subscriber gets only the latest message of each static
    broadcaster (its history holds one), so two received that were sent before recording began are two
    publishers': a static_conflict."""
    findings = _neato(1, tmp_path, sent=START - 562 * NS_PER_S, apart=1064 * MS)
    (conflict,) = loud(findings)
    assert (conflict.code, conflict.frames) == ("static_conflict", ("base_link", "laser")), conflict.message
    assert "differs in value from publisher 1's, both sent before the recording began" in conflict.message


def test_a_frame_two_static_publishers_give_different_parents_is_not_an_object_picked_up(tmp_path: Path) -> None:
    first = TfMessage("/tf_static", START + DELAY, [scenes._t("base_link", "laser", START, 0.2), *_more("base_link")])
    second = TfMessage("/tf_static", START + 600 * MS, [scenes._t("base_footprint", "laser", START, 0.2)])
    findings = _findings(tmp_path, [*scenes.healthy(), first, second], {"/tf_static": 1})
    (finding,) = coded(findings, "multiple_parents")
    assert "picked up" not in finding.hint
    assert "tf2 keeps the last static transform received for every time: laser is under base_footprint" in finding.hint
    assert "publish it from one of them" in finding.hint


def _more(parent: str) -> list[Transform]:
    return [scenes._t(parent, "camera", START, 0.1), scenes._t(parent, "sonar", START, 0.3)]


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_mixed_static_explains_the_rule_of_the_recordings_tf2(ros1: bool) -> None:
    """ROS 1's tf2 keeps the cache the first sample made; ROS 2's replaces it at each switch of topic."""
    late_static = TfMessage("/tf_static", START + 5 * NS_PER_S, [scenes._t("odom", "base_link", START)], "/rsp")
    (finding,) = coded(check(scenes.recording(scenes.with_extra([late_static]), ros1=ros1)).findings, "mixed_static")
    if ros1:
        assert "tf2 made it a moving frame (its first transform came on /tf)" in finding.message
    else:
        assert "ROS 2's tf2 replaces a frame's cache when it switches between /tf_static and /tf" in finding.message
        assert "it switched 2 times, the last at 1700000005.0" in finding.message
        assert "to /tf, so tf2 holds only the /tf transforms since then" in finding.message
    assert "(500 transforms, from 1700000000.002 (+0.0 s))" in finding.message, finding.message


def test_mixed_static_says_a_first_tf_transform_stamped_0_is_unset() -> None:
    """json_mcap_lbx_franka.mcap's first /tf transforms are stamped 0 and logged at 0 (no time of arrival): said
    "(5 transforms, from 0.000)", a moment that never was (issue 39)."""
    unset = TfMessage("/tf", 0, [scenes._t("odom", "base_link", 0)], "/ekf")
    late_static = TfMessage("/tf_static", START + 5 * NS_PER_S, [scenes._t("odom", "base_link", START)], "/rsp")
    messages = [unset, *scenes.with_extra([late_static])]
    (finding,) = coded(check(scenes.recording(messages, ros1=False)).findings, "mixed_static")
    assert "(501 transforms, the first stamped 0 (unset))" in finding.message, finding.message


# --- the real recordings that showed each case ------------------------------------------------------


def _corpus(name: str) -> Path:
    path = shared_dir() / "corpus" / name
    if not path.exists():
        pytest.skip(f"{name} is not in {path.parent}")
    return path


def test_webots_epuck_re_sending_its_odometry_is_one_publisher() -> None:
    """182 of 598 stamps of odom -> base_link arrive twice, ~21 ms apart, identical values: one publisher."""
    path = _corpus("ros2_db3_webots_epuck")
    samples = data.read_contents(path).edges[("odom", "base_link")]
    distinct, counts = np.unique(samples.stamps, return_counts=True)
    findings = check(read_recording([path])).findings
    assert not coded(findings, "multiple_authorities") and not [f for f in findings if "taking turns" in f.message]
    (note,) = coded(findings, "resent")
    assert f"{(counts > 1).sum()} of its {len(distinct)} stamps arrived again (2 times each)" in note.message
    assert "one publisher re-sending its last value" in note.message


def test_create3_two_robot_descriptions_are_one_static_conflict() -> None:
    path = _corpus("ros2_db3_create3_real_two_urdfs")
    statics = {e: s for e, s in data.read_contents(path).edges.items() if s.static}
    differ = {e for e, s in statics.items() if len(s.values) > 1 and s.values[0] != s.values[-1]}
    findings = check(read_recording([path])).findings
    assert not coded(findings, "dynamic_on_static")
    (conflict,) = coded(findings, "static_conflict")
    assert conflict.count == len(differ) == 21 and set(conflict.frames) == {f for e in differ for f in e}
    assert "33 transforms at" in conflict.message and "23 transforms at" in conflict.message
    assert "which lacks 12 of publisher 1's 33 transforms" in conflict.message
    assert "up to 339.1 mm (base_link -> button_1) and 179.68° (base_link -> mouse)" in conflict.message


def test_the_jetackers_two_odometries_are_said_as_far_apart_as_they_are() -> None:
    """Issue 39: odom -> base_footprint alternates between two poses about 0.13 m and 6 degrees apart (e.g.
    (0.171, 0.990, 113.4 deg) and (0.041, 0.993, 119.0 deg) at +36.5 s): said with the distance, as the
    Stage bag's two named publishers are, not only 'taking turns'."""
    path = _corpus("ros2_db3_jetacker_real_two_odometries")
    findings = check(read_recording([path])).findings
    (finding,) = coded(findings, "multiple_authorities")
    assert finding.frames == ("odom", "base_footprint")
    assert 0.12 <= float(finding.figures["apart_m_max"]) <= 0.15, finding.figures
    assert 5.0 <= float(finding.figures["apart_deg_max"]) <= 7.0, finding.figures
    assert "at the same times their values are up to 1" in finding.message
    assert finding.message.index("alternated") < finding.message.index("apart") < finding.message.index("turns")


def test_the_oko_odometries_that_part_at_a_turn_say_at_how_many_times_they_contradict() -> None:
    """Issue 39: on the moving OKO bag the odometry bridge and cartographer agree within noise until cartographer's
    21.8 deg turn at +2.98 s, then are up to 24.5 deg apart: 358 of the 995 common times beyond the edge's own
    step plus noise (its manifest entry, from the data). The error says so, not only the largest figure."""
    path = _corpus("ros1_okoslam_cartographer_2019-05-12-18-44-11.bag")
    (finding,) = coded(check(read_recording([path])).findings, "multiple_authorities")
    assert finding.severity is Severity.error
    assert (finding.figures["samples_contradicting"], finding.figures["samples_compared"]) == (358, 995)
    assert "; at 358 of the 995 further apart than that plus noise (5 cm, 3°), they contradict" in finding.message


def test_two_robot_state_publishers_are_one_warning_for_both_wheels() -> None:
    path = _corpus("ros2_db3_tb3_gazebo_two_rsp")
    edges = data.read_contents(path).edges
    wheels = [("base_link", "wheel_left_link"), ("base_link", "wheel_right_link")]
    stamps = [np.unique(edges[w].stamps, return_counts=True) for w in wheels]
    findings = check(read_recording([path])).findings
    (finding,) = loud(findings)
    assert (finding.code, finding.frames) == ("multiple_authorities", (*wheels[0], *wheels[1]))
    again, total = sum(int((c > 1).sum()) for _, c in stamps), sum(len(s) for s, _ in stamps)
    assert f"arrive twice: {again} of their {total} stamps arrived again (2 times each)" in finding.message
    assert f"at the same times their values are the same, over {2 * again} samples compared" in finding.message
    assert (
        "metadata.yaml lists 2 publishers of /tf" in finding.message and "two identical publishers" in finding.message
    )
