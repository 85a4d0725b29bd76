"""Static transforms on replay (and their repair), jumps, and broadcasters inferred where bags name no publisher."""

from __future__ import annotations

import contextlib
import hashlib
import sqlite3
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tests.cli.conftest import Result, Tfx, tfx  # noqa: F401 (the fixture)
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.broadcasters import FLOOR_M, sent_before
from tftools.analysis.wtf.fleet import check
from tftools.analysis.wtf.jumps import JUMP_FACTOR, jumps
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sinks.static_bag import REPAIR_EVERY_S, repair_static_transforms
from tftools.sources.recording import read_recording

ROS2_FORMATS = [f for f in scenes.FORMATS if f is not BagFormat.ros1]
MS = scenes.MS


def loud(findings: list[Finding]) -> list[Finding]:
    return [f for f in findings if f.severity is not Severity.info]


def _volatile(bag: Path) -> Path:
    """``bag``'s metadata.yaml offering /tf_static volatile, as a recording of a volatile publisher says."""
    metadata = bag / "metadata.yaml"
    text = metadata.read_text()
    assert text.count("durability: transient_local") == 1
    metadata.write_text(text.replace("durability: transient_local", "durability: volatile"))
    return bag


def _without_static_qos(bag: Path) -> Path:
    """``bag``'s metadata.yaml keeping no QoS for /tf_static (``offered_qos_profiles: ''``, as a converted bag's)."""
    metadata = bag / "metadata.yaml"
    document = yaml.safe_load(metadata.read_text())
    for entry in document["rosbag2_bagfile_information"]["topics_with_message_count"]:
        if entry["topic_metadata"]["name"] == "/tf_static":
            entry["topic_metadata"]["offered_qos_profiles"] = ""
    metadata.write_text(yaml.safe_dump(document))
    return bag


def _digest(path: Path) -> str:
    files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
    return hashlib.sha256(b"".join(f.read_bytes() for f in files)).hexdigest()


# --- static transforms on replay -------------------------------------------------------------


@pytest.mark.parametrize("fmt", ROS2_FORMATS)
def test_tf_static_offered_volatile_is_a_warning_and_transient_local_is_quiet(tmp_path: Path, fmt: BagFormat) -> None:
    durable = scenes.write(tmp_path, "durable", fmt, scenes.healthy())
    assert check(read_recording([durable])).findings == []
    volatile = _volatile(scenes.write(tmp_path, "volatile", fmt, scenes.healthy()))
    (finding,) = check(read_recording([volatile])).findings
    assert (finding.code, finding.severity) == ("static_volatile", Severity.warning)
    assert "volatile" in finding.message and "--repair" in finding.hint
    assert "transient local" in finding.hint and "latched" not in finding.hint  # ROS 2's words (issue 39)
    assert {"base_link", "laser", "camera"} <= set(finding.frames)


@pytest.mark.parametrize("every_s", [0.05, 5.0])
def test_statics_re_sent_through_the_recording_reach_a_late_subscriber_however_offered(
    tmp_path: Path, every_s: float
) -> None:
    """CompRobo's Neato driver in 2022 re-sent its 10 statics at 20 Hz through the recording (corpus
    ``ros2-neato-wall-follower-statics-20hz-2022-db3``), and its metadata.yaml records no QoS for /tf_static
    (played volatile): a node subscribing at any time gets them at the next message, so there is nothing to
    say; sent every 5 s (as ``tfx static --repair`` repeats them) neither. Sent once, or stopped before the end,
    the finding stays."""
    every = round(every_s * NS_PER_S)
    times = range(scenes.START + scenes.DELAY, scenes.START + round(scenes.SECONDS * NS_PER_S) + every, every)
    repeated = _volatile(
        scenes.write(
            tmp_path, "repeated", BagFormat.rosbag2_sqlite3, scenes.healthy(statics=[scenes.statics(t) for t in times])
        )
    )
    assert check(read_recording([repeated])).findings == []
    cut = [scenes.statics(t) for t in times][: max(1, len(times) // 4)]  # stopped a quarter in, or sent once
    stopped = _volatile(scenes.write(tmp_path, "stopped", BagFormat.rosbag2_sqlite3, scenes.healthy(statics=cut)))
    assert [f.code for f in check(read_recording([stopped])).findings] == ["static_volatile"]


def test_a_bare_db3_without_qos_records_none_as_a_folder_without_qos_does(tmp_path: Path) -> None:
    """A .db3 given alone whose topics table keeps no QoS for /tf_static: the same absence as a metadata.yaml's
    ``offered_qos_profiles: ''``, said the same way ("records no QoS for it", a note: ros2 bag play plays it
    volatile), where it was "not checked" (the check had run, and found that)."""
    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_sqlite3, scenes.healthy())
    (inside,) = bag.glob("*.db3")
    assert (
        check(read_recording([inside])).findings == []
    )  # issue 39: given inside its folder, the metadata.yaml beside it
    alone = tmp_path / "alone"
    alone.mkdir()
    (alone / inside.name).write_bytes(inside.read_bytes())
    assert check(read_recording([alone / inside.name])).findings == []  # its topics table says transient local
    _set_topics_qos(alone / inside.name, lambda text: "")  # a table without QoS (recorded with no publisher)
    (finding,) = check(read_recording([alone / inside.name])).findings
    assert not finding.skipped and finding.code == "static_volatile" and finding.severity is Severity.info
    assert "records no QoS for it (/tf_static, the .db3's topics table's offered_qos_profiles)" in finding.message
    assert "not checked" not in finding.message
    none = _without_static_qos(scenes.write(tmp_path, "none", BagFormat.rosbag2_sqlite3, scenes.healthy()))
    (folder,) = check(read_recording([none])).findings
    words = finding.message.replace(str(alone / inside.name), str(none))
    assert folder.message == words.replace("the .db3's topics table", "metadata.yaml"), folder.message
    assert (folder.code, folder.severity, folder.skipped, folder.hint) == (
        finding.code,
        finding.severity,
        finding.skipped,
        finding.hint,
    )
    volatile = _volatile(bag)  # what the metadata.yaml beside it says is what is judged
    (said,) = check(read_recording([next(volatile.glob("*.db3"))])).findings
    assert (said.code, said.severity) == ("static_volatile", Severity.warning)


def test_a_bare_mcap_is_judged_by_its_channels_qos(tmp_path: Path) -> None:
    """A rosbag2 .mcap given alone (ros2 bag play plays it with the QoS its channels' metadata keeps, as
    metadata.yaml says beside it): judged as its folder is. It was not checked at all, so the corpus's
    ros2_db3_evo_tf_example written as one .mcap lost its static_volatile note."""
    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_mcap, scenes.healthy())
    (inside,) = bag.glob("*.mcap")
    alone = tmp_path / "alone.mcap"
    _rewrite_channels(inside, alone, lambda text: text)
    assert check(read_recording([alone])).findings == []  # its channels say transient local
    _rewrite_channels(inside, alone, lambda text: text.replace("durability: transient_local", "durability: volatile"))
    (finding,) = check(read_recording([alone])).findings
    assert (finding.code, finding.severity) == ("static_volatile", Severity.warning)
    folder = check(read_recording([_volatile(bag)])).findings
    assert [(f.code, f.severity, f.frames) for f in folder] == [(finding.code, finding.severity, finding.frames)]


def _rewrite_channels(source: Path, target: Path, change: Callable[[str], str]) -> None:
    """``source``'s records written again to ``target``, each channel's offered QoS profiles rewritten by ``change``."""
    from tests.corpus.variants import rewrite_mcap

    def changed(metadata: dict[str, str]) -> dict[str, str]:
        return {k: change(v) if k == "offered_qos_profiles" else v for k, v in metadata.items()}

    rewrite_mcap(source, target, changed)


def _set_topics_qos(db3: Path, change: Callable[[str], str]) -> None:
    """The offered QoS profiles in ``db3``'s topics table (this test's own copy) rewritten by ``change``."""
    with contextlib.closing(sqlite3.connect(db3)) as db, db:
        for topic_id, text in db.execute("SELECT id, offered_qos_profiles FROM topics").fetchall():
            db.execute("UPDATE topics SET offered_qos_profiles = ? WHERE id = ?", (change(text), topic_id))


def test_a_bag_directory_cut_short_is_judged_by_the_qos_in_its_topics_table(tmp_path: Path) -> None:
    """A recording stopped before rosbag2 wrote metadata.yaml (hurtaditoo/IR2121@5c91492
    rosbag2_2023_10_04-17_00_14: a .db3 and its -wal, no metadata.yaml) still says in its topics table the
    QoS /tf_static was offered with, as ros2 bag reindex reads it: judged by it, not 'not checked'."""
    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_sqlite3, scenes.healthy())
    (bag / "metadata.yaml").unlink()
    assert check(read_recording([bag])).findings == []
    volatile = "durability: volatile"
    _set_topics_qos(next(bag.glob("*.db3")), lambda text: text.replace("durability: transient_local", volatile))
    (finding,) = check(read_recording([bag])).findings
    assert (finding.code, finding.severity) == ("static_volatile", Severity.warning)


@pytest.mark.parametrize("fmt", scenes.FORMATS)
def test_repair_makes_statics_durable_complete_and_repeated_and_leaves_the_input(
    tmp_path: Path, fmt: BagFormat
) -> None:
    bag = scenes.write(tmp_path, "long", fmt, scenes.PROBLEMS["statics_early"].make())
    if fmt is not BagFormat.ros1:
        _volatile(bag)
    before = _digest(bag)
    found = {(f.code, f.severity) for f in check(read_recording([bag])).findings}
    assert found == {("statics_early", Severity.info)} | (
        set() if fmt is BagFormat.ros1 else {("static_volatile", Severity.warning)}
    )
    out = tmp_path / ("fixed.bag" if fmt is BagFormat.ros1 else "fixed")
    written, statics = repair_static_transforms(bag, out)
    assert _digest(bag) == before
    assert {(t.frame_id, t.child_frame_id) for t in statics} == {("base_link", "laser"), ("base_link", "camera")}
    repaired = read_recording([written])
    assert check(repaired).findings == []
    batch = repaired.transforms
    times = np.unique(batch.record_time[batch.static])
    assert len(times) >= scenes.LONG / REPAIR_EVERY_S and np.diff(times).max() <= REPAIR_EVERY_S * NS_PER_S
    if fmt is BagFormat.ros1:
        from rosbags.rosbag1 import Reader

        with Reader(written) as reader:
            exts: list[Any] = [c.ext for c in reader.connections if c.topic == "/tf_static"]
            assert all(ext.latching == 1 for ext in exts) and {ext.callerid for ext in exts} == {"/rsp"}


def test_repair_on_the_command_line_never_writes_over_its_input(tmp_path: Path, tfx: Tfx) -> None:  # noqa: F811
    bag = scenes.write(tmp_path, "in", BagFormat.ros1, scenes.healthy())
    before = _digest(bag)
    refused: Result = tfx("static", "--repair", "-b", bag, "-o", bag)
    assert refused.code == 2 and "input" in refused.stderr and _digest(bag) == before
    done: Result = tfx("static", "--repair", "-b", bag, "-o", tmp_path / "out.bag")
    assert done.code == 0 and "base_link -> laser" in done.stdout
    given: Result = tfx("static", "--repair", "0", "0", "0", "0", "0", "0", "a", "b", "-b", bag, "-o", tmp_path / "x")
    assert given.code == 2 and "--repair takes no transforms" in given.stderr


def test_statics_repeated_through_a_long_recording_are_quiet() -> None:
    statics = scenes.statics().transforms
    repeated = [TfMessage("/tf_static", scenes.START + i * 5 * NS_PER_S + 1, statics, "/rsp") for i in range(14)]
    messages = scenes.healthy(
        statics=repeated,
        amcl=scenes.amcl(end=scenes.LONG),
        ekf=scenes.ekf(end=scenes.LONG),
        wheels=scenes.wheels(end=scenes.LONG),
    )
    assert check(scenes.recording(messages)).findings == []


# --- jumps and REP 105 -----------------------------------------------------------------------


def test_a_jump_on_another_edge_is_a_warning_with_when_and_how_far() -> None:
    def arm(stamp: int) -> list[Transform]:
        return [scenes._t("base_link", "arm", stamp, 0.1 * scenes._s(stamp) + (0.5 if scenes._s(stamp) >= 6 else 0.0))]

    (finding,) = check(
        scenes.recording(scenes.healthy(wheels=[*scenes.wheels(), *scenes.periodic("/arm", 20, arm)]))
    ).findings
    assert (finding.code, finding.severity, finding.frames) == ("jump", Severity.warning, ("base_link", "arm"))
    assert "0.505 m" in finding.message and "+6.0 s" in finding.message


def test_a_map_hung_under_odom_stepping_is_told_a_correction_not_odometry_that_must_not_jump() -> None:
    """A real AGV's laser localizer (the Jarvis, ros1-jarvis-tricycle-agv-...-2014-bag) hangs its map
    ``map_contours_nav`` under odom, a leaf that steps with each correction: its jump's hint said REP 105 wants
    odom -> base continuous, of a frame that is no base. The robot's own odom -> base_link keeps that hint. Where it
    moves sample after sample (not held between corrections: tests/analysis/test_map_under_odom.py) it still jumps,
    and as map -> odom is sent already, the hint no longer asks for it (rules46)."""

    def contours(stamp: int) -> list[Transform]:
        return [
            scenes._t(
                "odom", "map_contours_nav", stamp, 0.01 * scenes._s(stamp) + (0.3 if scenes._s(stamp) >= 6 else 0)
            )
        ]

    leaf = check(scenes.recording(scenes.healthy(wheels=[*scenes.wheels(), *scenes.periodic("/nav", 20, contours)])))
    (finding,) = leaf.findings
    assert (finding.code, finding.frames) == ("jump", ("odom", "map_contours_nav")), finding
    assert "odom -> base continuous" not in finding.hint and "publish it as map -> odom" not in finding.hint
    assert "map -> odom is sent already, so if it corrects where map_contours_nav lies" in finding.hint, finding.hint
    reset = [f for f in check(scenes.recording(scenes.PROBLEMS["jump"].make())).findings if f.code == "jump"]
    assert reset and all("odom -> base continuous" in f.hint for f in reset), reset


def test_motion_from_rest_fast_turns_and_a_gap_are_explained_by_the_edge_s_own_motion() -> None:
    seconds = np.arange(0, 20, 0.02)
    speed = np.where(seconds < 5, 0.0, 2.0)  # standing still, then off at 2 m/s
    x = np.cumsum(speed * 0.02)
    yaw = np.where(seconds < 10, 0.0, 3.0 * (seconds - 10))  # then turning at 3 rad/s
    keep = (seconds < 12) | (seconds > 13)  # and a second lost
    values = np.zeros((len(seconds), 7))
    values[:, 0] = x
    values[:, 5], values[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)
    stamps = (seconds * NS_PER_S).astype(np.int64)
    assert len(jumps(stamps[keep], values[keep])) == 0
    values[600:, 0] += JUMP_FACTOR * 0.04 + FLOOR_M  # beyond what 4 cm a sample explains, by a hair
    assert jumps(stamps, values).at.tolist() == [600]


def _wheel(angles_deg: np.ndarray) -> np.ndarray:
    """A wheel's samples: turning about y by ``angles_deg``, never moving."""
    values = np.zeros((len(angles_deg), 7))
    half = np.radians(angles_deg) / 2
    values[:, 4], values[:, 6] = np.sin(half), np.cos(half)
    return values


def test_steps_at_the_edge_s_usual_speed_are_its_own_motion_and_a_flip_and_back_is_not() -> None:
    """Real Neatos at 5.5 Hz (corpus ros2-neato-real-person-marker-2025-db3 and unseen CompRobo 2025 bags): a
    wheel turning ~30° a sample stopped, then restarted with 3.3°; odometry turned in a teleop pulse (6.5,
    10.4, 28.9, 11.8° a sample against a usual 3°): both were 'jumps', as their neighbours' median is ~0."""
    every = (np.arange(47) * 0.18 * NS_PER_S).astype(np.int64)
    restart = np.r_[np.full(40, 29.5), 1.6, 0.0, 1.6, 0.0, 0.0, 3.3]
    assert len(jumps(every, _wheel(np.r_[0.0, np.cumsum(restart)]))) == 0
    pulse = np.r_[np.full(30, 3.0), 6.5, 10.4, 28.9, 11.8, 0.9, np.full(11, 3.0)]
    assert len(jumps(every, _wheel(np.r_[0.0, np.cumsum(pulse)]))) == 0
    turning = np.r_[0.0, np.cumsum(np.full(46, 10.0))]
    turning[20] += 60.0  # one sample flipped away and back onto its path: two sources taking turns
    assert jumps(every, _wheel(turning)).at.tolist() == [20]  # the flip (its way back is at the usual pace)
    flips = np.r_[np.zeros(20), np.full(5, 180.0), np.zeros(20), np.full(5, 180.0), np.zeros(20)]  # its only motion
    found = jumps(np.arange(len(flips), dtype=np.int64) * 100_000_000, _wheel(flips))
    assert found.at.tolist() == [20, 25, 45, 50]  # each flip and each return: too few steps to be its usual speed


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_the_healthy_robots_jumps_and_rep105_stay_quiet(ros1: bool) -> None:
    assert not [
        f
        for f in check(scenes.recording(scenes.healthy(), ros1=ros1)).findings
        if f.code in {"jump", "map_corrections", "rep105"}
    ]


# --- several broadcasters where the bag names none -------------------------------------------


def _fighting(stamp: int) -> list[Transform]:
    """A second odometry, 0.3 m off the first."""
    return [scenes._t("odom", "base_link", stamp, 0.4 * scenes._s(stamp) + 0.3, 0.1 * scenes._s(stamp))]


def _late_twin(stamp: int) -> list[Transform]:
    """A second broadcaster of the same motion whose stamps lag 35 ms behind (off the first's 20 ms grid:
    30 ms would send the first's stamps and values again, two identical publishers)."""
    return scenes.odom_base(stamp - 35_000_000)


@pytest.mark.parametrize("fmt", ROS2_FORMATS)
@pytest.mark.parametrize(
    ("second", "sign"), [(_fighting, "alternated between two places"), (_late_twin, "stamps went back")]
)
def test_two_broadcasters_taking_turns_are_inferred_in_ros2_bags(
    tmp_path: Path, fmt: BagFormat, second: object, sign: str
) -> None:
    other = scenes.periodic("/ekf2", 50, second, phase=0.01)  # type: ignore[arg-type]  # a parametrised edge function
    bag = scenes.write(
        tmp_path, "two", fmt, scenes.healthy(ekf=sorted(scenes.ekf() + other, key=lambda m: m.record_time))
    )
    findings = loud(check(read_recording([bag])).findings)
    assert [f.code for f in findings] == ["multiple_authorities"], findings
    assert sign in findings[0].message and findings[0].frames == ("odom", "base_link")


def _other_wheel(stamp: int) -> list[Transform]:
    """A second robot_state_publisher whose URDF puts the wheel 5 cm further out."""
    (t,) = scenes.wheel(stamp)
    x, _, z = t.translation
    return [Transform((x, 0.25, z), t.rotation, stamp, "base_link", "wheel")]


def _ros2_findings(messages: list[TfMessage]) -> list[Finding]:
    return loud(check(scenes.recording(messages, ros1=False)).findings)


def test_two_identical_publishers_of_every_sample_are_two_broadcasters_in_a_ros2_bag() -> None:
    """Two robot_state_publishers at once: each wheel sample arrives twice, stamps and values identical
    (536 of 538 in a Gazebo recording): tf2 drops the copies, but two publishers run."""
    twice = [
        m
        for message in scenes.wheels()
        for m in (message, TfMessage("/tf", message.record_time + MS // 2, message.transforms, "/rsp2"))
    ]
    (finding,) = _ros2_findings(scenes.healthy(wheels=twice))
    assert (finding.code, finding.severity, finding.frames) == (
        "multiple_authorities",
        Severity.warning,
        ("base_link", "wheel"),
    )
    assert "arrives twice: 200 of its 200 stamps arrived again (2 times each)" in finding.message
    assert "at the same times their values are the same, over 400 samples compared" in finding.message
    assert "robot_state_publisher" in finding.message and "drops the exact copies" in finding.hint


def test_three_identical_publishers_are_said_three_times_not_twice() -> None:
    """ros2_db3_eyrc_hologlyph_hb_bot_gazebo_planar_move_thrice_no_metadata_2023: a URDF with Gazebo's planar move
    plugin three times sends odom -> base_footprint three times a stamp; wtf said 'arrives twice: 308 of its 308
    stamps arrived again (3 times each)' and 'every sample costs twice'."""
    thrice = [
        m
        for message in scenes.wheels()
        for k in (0, 1, 2)
        for m in [TfMessage("/tf", message.record_time + k * MS // 4, message.transforms, f"/rsp{k}")]
    ]
    (finding,) = _ros2_findings(scenes.healthy(wheels=thrice))
    assert "arrives 3 times: 200 of its 200 stamps arrived again (3 times each)" in finding.message
    assert "twice" not in finding.message + finding.hint and "every sample costs 3 times" in finding.hint


def test_two_publishers_of_the_same_stamps_with_other_values_are_said_to_differ() -> None:
    other = scenes.periodic("/rsp2", 20, _other_wheel, delay=scenes.DELAY + MS // 2)
    (finding,) = _ros2_findings(scenes.healthy(wheels=sorted(scenes.wheels() + other, key=lambda m: m.record_time)))
    assert finding.code == "multiple_authorities" and "arrives twice" in finding.message
    assert "their values are up to 50.0 mm (at +0.0 s) apart" in finding.message and "mix" in finding.hint


def test_one_publisher_sending_one_old_sample_again_is_not_two_broadcasters() -> None:
    """One publisher re-sending one stale sample (same stamp, same value) between its own, 85 times:
    not two streams taking turns (it was reported as "two steady 17.1 Hz streams taking turns")."""
    ekf = scenes.periodic("/ekf", 17.1, scenes.odom_base)
    stale = scenes.odom_base(scenes.START + 5 * MS)
    again = [TfMessage("/tf", m.record_time + 20 * MS, stale, "/ekf") for m in ekf[1::2]]
    findings = _ros2_findings(scenes.healthy(ekf=sorted(ekf + again, key=lambda m: m.record_time)))
    assert not [f for f in findings if f.code == "multiple_authorities"], findings
    assert not [f for f in findings if "taking turns" in f.message], findings


def test_sample_bags_show_no_jump_and_no_inferred_broadcaster() -> None:
    """The shared corpus's recordings are judged each by its own manifest entry (tests/corpus: its
    ``absent`` and ``reported`` codes), so the corpus can grow without a table here."""
    samples = Path(__file__).resolve().parents[2] / "sample_bags"
    for bag in [samples / "robot.bag", samples / "robot_db3", samples / "robot_mcap"]:
        codes = {f.code for f in check(read_recording([bag], allow_empty=True)).findings}
        assert not codes & {"jump", "map_corrections", "rep105", "multiple_authorities"}, (bag, codes)


# --- publishers of /tf_static ----------------------------------------------------------------


def test_two_publishers_of_the_same_statics_are_one_note_not_one_per_edge() -> None:
    twin = TfMessage("/tf_static", scenes.START + 5 * NS_PER_S, scenes.statics().transforms, "/rsp2")
    (finding,) = check(scenes.recording(scenes.with_extra([twin]))).findings
    assert (finding.code, finding.severity) == ("multiple_authorities", Severity.info)
    assert "/rsp and /rsp2 both send 2 static transforms, with the same values" in finding.message
    assert finding.count == 4 and set(finding.frames) == {"base_link", "laser", "camera"}


def test_two_calibrations_that_disagree_are_one_finding_naming_publishers_frames_and_how_far() -> None:
    """A publisher the bag does not name (no callerid: the topic stands in) is called so, not "/tf_static"."""
    other = [
        scenes._t("base_link", "laser", scenes.START, 0.35),
        scenes._t("base_link", "camera", scenes.START, 0.1, yaw=0.5),
        scenes._t("base_link", "sonar", scenes.START, 0.3),
    ]
    unnamed = TfMessage("/tf_static", scenes.START + 5 * NS_PER_S, other, "/tf_static")
    findings = check(scenes.recording(scenes.with_extra([unnamed]))).findings
    (finding,) = [f for f in findings if f.severity is not Severity.info]
    assert (finding.code, finding.severity, finding.count) == ("static_conflict", Severity.error, 2)
    assert finding.message.startswith(
        "/rsp and a publisher on /tf_static (unnamed) send different values for 2 static transforms: "
        "base_link -> laser (150.0 mm and 0.00° apart), base_link -> camera (0.0 mm and 28.65° apart); the largest "
        "base_link -> laser, 150.0 mm and 0.00° apart. tf2 keeps the values last received for every time: a "
        "publisher on /tf_static (unnamed)'s, at 1700000005.000 (+5.0 s)"
    ), finding.message
    assert finding.authorities == ("/rsp", "/tf_static") and finding.frames == ("base_link", "laser", "camera")
    assert not [f for f in findings if f.code in {"dynamic_on_static", "multiple_authorities"}], findings


# --- tf topics that say nothing (rosbag2: metadata.yaml counts messages and publishers) ------


def _quiet_bag(path: Path, empty: int, tf_publishers: int, moving: bool = False) -> Path:
    """A rosbag2 recording of the robot's statics, then ``empty`` /tf_static messages
    without a transform, and a /tf that ``tf_publishers`` offered (as ros2 bag record lists them) but
    that carried nothing (or the robot's odometry, if ``moving``)."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    from tests.bags import TF_TYPE, _typestore, rosbags_tf_message
    from tftools.sinks.static_bag import static_qos

    store = _typestore("ros2")
    with Writer(path, version=Writer.VERSION_LATEST, storage_plugin=StoragePlugin.SQLITE3) as writer:
        statics = writer.add_connection("/tf_static", TF_TYPE, typestore=store, offered_qos_profiles=[static_qos()])
        tf = writer.add_connection("/tf", TF_TYPE, typestore=store, offered_qos_profiles=[static_qos()] * tf_publishers)
        record = scenes.START + scenes.DELAY
        full_message = bytes(store.serialize_cdr(rosbags_tf_message(store, scenes.statics().transforms), TF_TYPE))
        empty_message = bytes(store.serialize_cdr(rosbags_tf_message(store, []), TF_TYPE))
        writer.write(statics, record, full_message)
        for i in range(empty):
            writer.write(statics, record + (i + 1) * MS, empty_message)
        for message in scenes.ekf() if moving else []:
            data = store.serialize_cdr(rosbags_tf_message(store, message.transforms), TF_TYPE)
            writer.write(tf, message.record_time, bytes(data))
    return path


def test_a_tf_whose_publishers_sent_nothing_and_empty_static_messages_are_said_not_fine(tmp_path: Path) -> None:
    """The recording that was called "fine for a fixed setup": /tf had two publishers that sent nothing
    and /tf_static held 2,036 messages without a transform."""
    bag = _quiet_bag(tmp_path / "quiet", empty=2036, tf_publishers=2)
    findings = check(read_recording([bag])).findings
    assert [(f.code, f.severity) for f in findings] == [
        ("silent_tf", Severity.warning),
        ("silent_tf", Severity.warning),
    ]
    said = " | ".join(f.message for f in findings)
    assert "/tf had 2 publishers when recording began" in said and "nothing in this recording moves" in said
    # 2 transforms in one message beside 2,036 empty ones: as read, exactly (metadata.yaml alone says 2,035 at least)
    assert "2,036 of 2,037 messages on /tf_static carry no transform (2 transforms in the others)" in said
    assert not [f for f in findings if "fine for a fixed setup" in f.hint]


def test_a_few_empty_messages_beside_moving_transforms_are_a_note(tmp_path: Path) -> None:
    bag = _quiet_bag(tmp_path / "few", empty=1, tf_publishers=1, moving=True)
    (finding,) = check(read_recording([bag])).findings
    assert (finding.code, finding.severity) == ("silent_tf", Severity.info)
    assert finding.message.endswith(": 1 of 2 messages on /tf_static carry no transform (2 transforms in the others)")
    assert "moves" not in finding.message


def test_a_static_only_rosbag2_recording_without_silent_publishers_is_still_a_note(tmp_path: Path) -> None:
    bag = _quiet_bag(tmp_path / "fixed", empty=0, tf_publishers=0)
    (finding,) = check(read_recording([bag])).findings
    assert (finding.code, finding.severity) == ("no_tf", Severity.info) and "fine for a fixed setup" in finding.hint


def test_a_sample_is_sent_again_by_its_stamp_or_by_its_stamp_and_value() -> None:
    """Twins are told by stamps; the rhythm drops only true copies (a clock reset replays stamps elsewhere)."""
    stamps = np.array([1, 2, 1, 3, 2], np.int64)
    values = np.zeros((5, 7))
    values[4, 0] = 1.0  # stamp 2 again, somewhere else
    assert sent_before(stamps).tolist() == [False, False, True, False, True]
    assert sent_before(stamps, values).tolist() == [False, False, True, False, False]
