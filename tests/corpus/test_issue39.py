"""Issue 39's defects, each on the real recording that showed it, in every output form it appears in (terminal,
``--format json``, ``--format junit``, view-frames, report, filter, echo): what a user of that recording reads.

Each test is judged by the recording's bytes and manifest entry; it skips while the recording awaits placement,
as the rest of the corpus tests do. ``/work/notes/issue39_audit.md`` lists which defect each test pins."""

from __future__ import annotations

import html
import itertools
import json
import re
import shutil
import xml.etree.ElementTree as ElementTree
from pathlib import Path
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording
from tests.corpus.recordings import BY_ID, WITH_TF, Corpus
from tftools.analysis.findings import Severity
from tftools.analysis.wtf.registry import CHECKS

EPUCK = "ros2-webots-epuck-resends-2025-db3"
CREATE3 = "ros2-create3-real-two-urdfs-2022-db3"
NEATOS = [
    "ros2-neato-real-two-static-publishers-2023-db3",
    "ros2-neato-real-two-static-publishers-2024-db3",
    "ros2-neato-real-two-static-publishers-2023b-db3",
]
UR5 = "ros2-ur5-two-clocks-topic-tf-2023-db3"
SLAM_TOOLBOX = "ros2-jetacker-gazebo-slam-toolbox-static-map-2025-db3"
FRANKA_JSON = "json-mcap-franka-teleop-2025"
BOAT = "ros2-stinger-boat-gps-into-odom-2025-db3"
WALKER_AT_SIM_START = "ros2-turtlebot3-gazebo-roomba-walker-clock-at-sim-start-2023-db3"
LAP = "ros2-turtlebot3-real-wifi-outage-2025-db3"
WAFFLE_NO_TF = "turtlebot3-waffle-odom-statics-2017-bag"
EMPTY_TF_STATIC = "ros2-turtlebot3-gazebo-amcl-empty-tf-static-2023-db3"
CALIBRATION_2025 = "grandtour-calibration-2025-bag"
AGV = "ros1-agv-two-lasers-mounts-on-tf-and-tf-static-replayed-2018-bag"
NEATO_BESIDE_URDF = "ros1-neato-urdf-beside-driver-2018-bag"
FOXY_WALKER = "ros2-turtlebot3-walker-foxy-2022-db3"

#: Commands and words of ROS 1 only: never said of a ROS 2 recording (and ROS 2's never of a ROS 1 one).
ROS1_ONLY = re.compile(r"\brosrun\b|\brosbag (?:play|record|info)\b|\brostopic\b|\brosparam\b|\broslaunch\b|latched")
ROS2_ONLY = re.compile(r"\bros2 (?:run|bag|topic|param|launch)\b|transient local")


def _recording(corpus: Corpus, recording_id: str) -> tuple[Recording, Path]:
    recording = BY_ID[recording_id]
    return recording, corpus(recording)


def _findings(tfx: Tfx, *args: str | Path) -> tuple[int, dict[str, Any], list[dict[str, Any]]]:  # noqa: F811
    result = tfx("wtf", *args, "--format", "json")
    assert result.stdout.strip(), result.stderr
    report = json.loads(result.stdout)
    (bag,) = report["bags"]
    return result.code, bag, bag["findings"]


def _words(text: str) -> str:
    """Terminal text with its wrapping undone: one space between words."""
    return " ".join(text.split())


def _junit_failures(tfx: Tfx, *paths: Path) -> list[tuple[str, str]]:  # noqa: F811
    """(code, message) of each JUnit failure or error of ``tfx wtf -b PATH ... --format junit`` (one recording)."""
    result = tfx("wtf", *(a for p in paths for a in ("-b", p)), "--format", "junit")
    root = ElementTree.fromstring(result.stdout)
    failed = []
    for case in root.iter("testcase"):
        for kind in ("failure", "error"):
            for element in case.findall(kind):
                failed.append((case.attrib["name"], element.attrib.get("message", "")))
    return failed


def _view_frames_legend(tfx: Tfx, path: Path) -> tuple[int, list[str]]:  # noqa: F811
    """view-frames' exit code and its legend's rows, as text."""
    result = tfx("view-frames", "-b", path, "-o", "-", "-f", "dot")
    legend = result.stdout[result.stdout.find("legend") :]
    rows = [html.unescape(re.sub(r"<[^>]+>", "", row)) for row in re.findall(r"<TD[^>]*>(.*?)</TD>", legend)]
    return result.code, [_words(row) for row in rows]


# --- one publisher taken for two ---------------------------------------------------------------


def test_epuck_one_publisher_re_sending_is_said_so_in_every_form(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Webots' diff-drive controller re-sends its last odometry when the simulation did not advance (182 of 598
    stamps twice, identical values): was 'two steady 17.1 Hz streams taking turns'. A note, said as observed."""
    _, path = _recording(corpus, EPUCK)
    code, _, findings = _findings(tfx, path)
    assert code == 0
    (resent,) = [f for f in findings if f["code"] == "resent"]
    assert resent["severity"] == "info" and resent["frames"][:2] == ["odom", "base_link"]
    assert "182 of its 598 stamps arrived again" in resent["message"]
    assert "one publisher re-sending its last value, not two" in resent["message"]
    text = _words(tfx("wtf", path).stdout)
    assert "taking turns" not in text and "two identical publishers" not in text
    assert "182 of its 598 stamps arrived again" in text
    assert _junit_failures(tfx, path) == []
    assert _view_frames_legend(tfx, path)[0] == 0


def test_slam_toolbox_re_sending_map_to_odom_is_not_two_publishers(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """slam_toolbox re-sends its map -> odom correction every 20 ms (3,142 messages, 44 stamps): one node, not
    'two identical publishers' nor turn-taking, and not stale (its stamp is the newest of the recording)."""
    _, path = _recording(corpus, SLAM_TOOLBOX)
    _, _, findings = _findings(tfx, path)
    about = [f for f in findings if f["frames"][:2] == ["map", "odom"]]
    assert not [f for f in about if f["code"] in ("multiple_authorities", "stale")], about
    assert not [f for f in about if "taking turns" in f["message"] or "two identical" in f["message"]]
    (resent,) = [f for f in about if f["code"] == "resent"]  # one account of the re-sends, the re-valued stamp in it
    assert "42 of its 43 stamps arrived again (46 to 100 times each)" in resent["message"]
    assert "but 1 stamp that came again with another value, first at 15.020" in resent["message"]
    (backwards,) = [f for f in about if f["code"] == "time_backwards"]  # where it matters: what tf2 answers
    assert "answer from the one received last" in backwards["message"]


def test_slam_toolbox_jump_says_the_second_a_replay_plays_it_where_it_is_not_its_stamps(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The JetAcker's simulation ran at 0.067x real time, recorded on wall time without /clock: its wheel's jump,
    stamped +1.3 s, plays 21.2 s into the replay, which ``monitor --start`` counts. wtf said "first at 15.840
    (+1.3 s)", a window no replay finds it in; and monitor refused +21.1 as outside the recording (the stamps')."""
    from tftools.analysis.monitor import MonitorQuery, monitor
    from tftools.analysis.times import Offset
    from tftools.sources.recording import read_recording

    _, path = _recording(corpus, SLAM_TOOLBOX)
    jumps = [f for f in _findings(tfx, path)[2] if f["code"] == "jump" and f["frames"][1] == "bottom_wheel_base_link"]
    (jump,) = jumps
    assert "the first at 15.840 (+1.3 s; heard 21.2 s into the replay)" in jump["message"], jump["message"]
    recording = read_recording([path])
    edge = ("top_wheel_base_link", "bottom_wheel_base_link")
    heard = monitor(recording, MonitorQuery(start=Offset(21.1), end=Offset(21.3))).edges
    assert [e.count for e in heard if e.key == edge] == [1]
    stamped = monitor(recording, MonitorQuery(start=Offset(1.2), end=Offset(1.4))).edges
    assert not [e for e in stamped if e.key == edge]


# --- static_conflict in ROS 2, one cause -------------------------------------------------------


def test_create3_two_descriptions_are_one_cause_in_every_form(corpus: Corpus, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """Two /tf_static messages (33 and 23 transforms) of two descriptions: one static_conflict, with the urdf
    findings that follow from it beneath it (was 21 dynamic_on_static + 21 urdf_moved + 4 more errors)."""
    _, path = _recording(corpus, CREATE3)
    code, bag, findings = _findings(tfx, path)
    assert code == 1
    causes = [f for f in findings if f["severity"] == "error" and not f["cause"]]
    assert [f["code"] for f in causes] == ["static_conflict"]
    (conflict,) = causes
    assert conflict["figures"]["publisher_1_transforms"] == 33 and conflict["figures"]["publisher_2_transforms"] == 23
    assert conflict["count"] == 21 and "up to 339.1 mm" in conflict["message"]
    assert "tf2 keeps the values last received for every time: publisher 2's" in conflict["message"]
    urdf = [f for f in findings if f["code"].startswith("urdf_") and f["severity"] == "error"]
    assert len(urdf) == 25 and all(f["cause"] == conflict["key"] for f in urdf)
    assert not [f for f in findings if f["code"] == "dynamic_on_static"]
    assert bag["summary"]["errors"] == 1
    assert "1 error (explaining 25 more)" in _words(tfx("wtf", path).stdout)
    assert [code for code, _ in _junit_failures(tfx, path)] == ["static_conflict"]
    exit_code, legend = _view_frames_legend(tfx, path)
    assert exit_code == 1 and any(row.startswith("Problems: 1 error") for row in legend), legend
    page = tmp_path / "create3.html"
    assert tfx("report", "-b", path, "-o", page).code == 1
    assert "1 error (explaining 25 more)" in html.unescape(page.read_text())


@pytest.mark.parametrize("recording_id", NEATOS)
def test_neato_two_static_publishers_are_one_static_conflict_in_every_form(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """metadata.yaml lists 2 publishers of /tf_static; the laser at (-0.1016, 0, 0.0889) in one, (-0.084, 0, 0.166)
    in robot_state_publisher's: one static_conflict (was dynamic_on_static "it changed 1 time"), given as the bag
    directory or as the .db3 inside it (whose metadata.yaml beside it is read)."""
    _, path = _recording(corpus, recording_id)
    (db3,) = path.glob("*.db3")
    for given in (path, db3):
        code, _, findings = _findings(tfx, given)
        assert code == 1 and [f["code"] for f in findings] == ["static_conflict"], findings
        message = findings[0]["message"]
        assert "metadata.yaml lists 2 publishers" in message and "base_link -> base_laser_link (79.1 mm" in message
        assert "tf2 keeps the values last received for every time: publisher 2's" in message
    assert [code for code, _ in _junit_failures(tfx, path)] == ["static_conflict"]
    exit_code, legend = _view_frames_legend(tfx, path)
    assert exit_code == 1 and "Problems: 1 error" in legend, legend


@pytest.mark.parametrize("recording_id", NEATOS[:2])
def test_neato_given_alone_says_its_own_file_counts_the_publishers(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The same Neatos' .db3 copied alone, and the recording written as one .mcap given alone: the publishers are
    counted by the file's topics table or channel metadata (a QoS profile each), and the finding said "metadata.yaml
    lists 2 publishers" of a recording without one. It names what it counted."""
    from tests.corpus.variants import read, write_ros2

    _, path = _recording(corpus, recording_id)
    copy = tmp_path / "bag"
    shutil.copytree(path, copy)  # read by rosbags' sqlite3 reader: a copy, never the recording
    (db3,) = copy.glob("*.db3")
    (tmp_path / "alone").mkdir()
    alone_db3 = shutil.copyfile(db3, tmp_path / "alone" / db3.name)
    (mcap,) = write_ros2(tmp_path / "as_mcap", read(copy), "mcap").glob("*.mcap")
    alone_mcap = shutil.copyfile(mcap, tmp_path / "alone.mcap")
    for given, source in ((alone_db3, "the .db3's topics table"), (alone_mcap, "the MCAP's channel metadata")):
        code, _, findings = _findings(tfx, given)
        assert code == 1 and [f["code"] for f in findings] == ["static_conflict"], findings
        message = findings[0]["message"]
        said = f"which differs in value from publisher 1's while {source} lists 2 publishers of /tf_static"
        assert said in message, message
        assert "metadata.yaml" not in message and "base_link -> base_laser_link (79.1 mm" in message


def test_a_db3_alone_keeping_no_qos_for_tf_static_says_what_its_folder_says(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """evo's tf_example as rosbag2 keeps no QoS profile for /tf_static, in its metadata.yaml as in its .db3's topics
    table: the folder said "records no QoS for it", the .db3 alone "not checked: ... has no metadata.yaml ... and
    its topics table no QoS profiles", one absence said two ways. Both now say what was observed, a note (the
    JSON's ``skipped`` false: it was checked), each naming where it looked."""
    _, path = _recording(corpus, "evo-tf-example-db3")
    (db3,) = path.glob("*.db3")
    alone = shutil.copyfile(db3, tmp_path / db3.name)
    for given, source in ((path, "metadata.yaml"), (alone, "the .db3's topics table")):
        code, _, findings = _findings(tfx, given)
        (note,) = findings
        assert (code, note["code"], note["severity"], note["skipped"]) == (0, "static_volatile", "info", False), note
        assert note["message"].startswith(f"{given} records no QoS for it (/tf_static, {source}'s offered_qos"), note
        assert "not checked" not in tfx("wtf", given).stdout


# --- one time base per question ----------------------------------------------------------------


def test_ur5_echo_at_plus_one_counts_on_the_arms_own_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``tfx echo base_link wrist_3_link --topic tf --at +1``, the issue's command: the arm is on simulated time
    (1907-1914 s) beside detections on wall time; +1 was counted on the wall-clock base and failed."""
    _, path = _recording(corpus, UR5)
    result = tfx("echo", "base_link", "wrist_3_link", "--topic", "tf", "--at", "+1", "-b", path, "-f", "json")
    assert result.code == 0, result.stderr
    assert 1907.0 < json.loads(result.stdout)["stamp_ns"] / 1e9 < 1910.0


# --- each ROS's words --------------------------------------------------------------------------


@pytest.mark.parametrize("recording", WITH_TF, ids=[r.id for r in WITH_TF])
def test_each_recording_is_told_in_its_own_ros_words(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """No ROS 1 command (or 'latched') in what is said of a ROS 2 recording, no ROS 2 command of a ROS 1 one; a
    source said twice ('on /tf on /tf', an edge sent 800 times said 'sent once on /tf on /tf') nowhere."""
    _, _, findings = _findings(tfx, corpus(recording))
    alien = ROS1_ONLY if recording.meta["format"] != "ros1" else ROS2_ONLY
    for f in findings:
        said = f"{f['message']} {f['hint']}"
        assert not alien.search(said), (f["code"], said)
        assert not re.search(r"on (/tf(?:_static)?) on \1\b", said), (f["code"], said)


@pytest.mark.parametrize("recording_id", [SLAM_TOOLBOX, FRANKA_JSON])
def test_mixed_static_on_ros2_data_explains_ros2s_rule(recording_id: str, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """ROS 2's tf2 replaces a frame's cache when it switches between /tf_static and /tf (ROS 1's made it a static
    frame for every time: the words the ROS 2 recordings were told)."""
    _, path = _recording(corpus, recording_id)
    _, _, findings = _findings(tfx, path)
    mixed = [f for f in findings if f["code"] == "mixed_static"]
    assert mixed
    for f in mixed:
        assert "ROS 2's tf2 replaces a frame's cache when it switches between /tf_static and /tf" in f["message"]
        assert "static frame" not in f["message"] and "for every time" not in f["message"]


def test_a_stale_edge_sent_many_times_is_not_said_sent_once(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The real TurtleBot3's wheels stop after a Wi-Fi outage (hundreds of transforms before): 'stopped at',
    never 'was sent once on /tf on /tf'."""
    _, path = _recording(corpus, LAP)
    _, _, findings = _findings(tfx, path)
    stale = [f for f in findings if f["code"] == "stale"]
    assert stale and all("stopped at" in f["message"] and "sent once" not in f["message"] for f in stale)


# --- severities as documented ------------------------------------------------------------------


@pytest.mark.parametrize("recording", WITH_TF, ids=[r.id for r in WITH_TF])
def test_no_finding_is_louder_than_list_checks_says(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``--list-checks`` gives each check's severity as the most it reports (the boat's GPS steps were raised to
    an error that --list-checks lists as a warning), but for a root cause: as severe as the worst finding said
    beneath it, as --list-checks says too."""
    _, _, findings = _findings(tfx, corpus(recording))
    for f in findings:
        beneath = [Severity(g["severity"]) for g in findings if f["key"] and g["cause"] == f["key"]]
        most = min([CHECKS[f["code"]].severity, *beneath], key=lambda s: s.rank)
        assert Severity(f["severity"]).rank >= most.rank, (f["code"], f["severity"])


def test_boat_gps_steps_are_a_warning_and_every_output_passes(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A GPS fix fused into odom steps 0.197 m at +23.5 s: jump, a warning (--list-checks' severity); wtf and
    view-frames exit 0 (every lookup works)."""
    _, path = _recording(corpus, BOAT)
    code, _, findings = _findings(tfx, path)
    assert code == 0
    assert [(f["code"], f["severity"]) for f in findings if f["severity"] != "info"] == [("jump", "warning")]
    assert "the largest 0.197 m" in findings[0]["message"]
    assert _junit_failures(tfx, path) == []
    assert _view_frames_legend(tfx, path)[0] == 0


# --- hints that point the right way ------------------------------------------------------------


@pytest.mark.parametrize(
    ("recording_id", "missing"),
    [
        (WAFFLE_NO_TF, "this recording holds no /tf (no such topic in it): the moving transforms"),
        (EMPTY_TF_STATIC, "/tf_static was recorded but holds no transform"),
    ],
)
def test_sensor_frame_without_the_tf_that_names_it_says_what_is_missing(
    recording_id: str,
    missing: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Sensor data in a frame no transform names because tf was not recorded (or recorded empty): the hint says
    that, not to set the driver's frame_id."""
    _, path = _recording(corpus, recording_id)
    _, _, findings = _findings(tfx, path)
    (sensor,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert missing in sensor["hint"] and "frame_id" not in sensor["hint"], sensor["hint"]
    assert missing in _words(tfx("wtf", path).stdout)
    if recording_id == WAFFLE_NO_TF:  # its /tf cut away, or never published: the bag cannot tell, so both remedies
        assert "were not recorded, or nothing published them" in sensor["hint"]
        assert "rosbag record /tf /tf_static" in sensor["hint"] and "run their publisher if none ran" in sensor["hint"]


PIONEER_NO_LASER_TF = "ros1-pioneer3dx-real-hokuyo-scans-without-laser-tf-2023-bag"


def test_a_mount_nothing_published_is_not_said_to_be_unrecorded(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real Pioneer 3-DX: /scan in 'laser', no /tf_static in the bag. Its recorder subscribed to every topic (its
    /rosout: 'Subscribing to /initialpose', '/clicked_point', ..., never /tf_static) and the authors' launch file
    publishes base_link -> laser when they replay it ('the transform that is missing in the pioneer'). The hint said
    the mount "was not recorded" (record /tf_static); a bag without the topic cannot tell: both, with both remedies."""
    _, path = _recording(corpus, PIONEER_NO_LASER_TF)
    code, _, findings = _findings(tfx, path)
    (missing,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert missing["frames"] == ["laser"] and "311 of 311 messages" in missing["message"]
    assert "were not recorded, or nothing published them" in missing["hint"]
    assert "rosbag record /tf /tf_static" in missing["hint"] and "run their publisher if none ran" in missing["hint"]
    assert code == 1


TILT_LASER_TF1 = "ros1-tilting-laser-xsens-imu-tf1-messages-imu-frame-unjoined-2012-bag"


def test_a_tf1_recording_s_unnamed_imu_frame_is_a_mount_never_sent(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real tilting laser and Xsens IMU of 2012: /tf is tf1's tf/tfMessage, its two mounts sent on it at 10 Hz by
    tf's static_transform_publisher, the Xsens topics in /base_imu, which no transform names. The hint said the
    mounts 'were not recorded' and to record /tf_static, a topic tf1 did not have (corpus25)."""
    _, path = _recording(corpus, TILT_LASER_TF1)
    code, _, findings = _findings(tfx, path)
    (missing,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert missing["hint"].startswith("this recording's /tf is tf1's (tf/tfMessage), from before /tf_static")
    assert "nothing published the missing ones" in missing["hint"]
    assert "rosbag record" not in missing["hint"] and "not recorded" not in missing["hint"]
    assert code == 1


def test_spans_and_rates_a_user_compares_say_what_they_count(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The Pioneer 3-DX: monitor's header gave its stamps' span (31.712 s), wtf's the record span (31.3 s), and
    monitor's /p2os a message rate on arrival (10.08) beside its one edge's stamp rate (9.96), each a bare "s" or
    "Hz": each label now says what it counts, the figures unchanged."""
    _, path = _recording(corpus, PIONEER_NO_LASER_TF)
    monitor = tfx("monitor", "-b", path).stdout
    assert monitor.splitlines()[0].endswith(": tf stamped over 31.712 s from 1684338971.264 to 1684339002.976")
    assert "ros1, 31.3 s recorded, 317 transforms" in tfx("wtf", path).stdout.splitlines()[0]
    edge = next(line.split() for line in monitor.splitlines() if "base_link" in line and "/p2os" in line)
    node = next(line.split() for line in monitor.splitlines() if line.split()[:1] == ["/p2os"])
    assert "Rate (stamps/s)" in monitor and "Rate (msgs/s)" in monitor
    assert edge[4] == "9.96" and node[2] == "10.08", (edge, node)


LOGISTIC = "ros2-logistic-cobot-pymoveit2-no-record-clock-2024-db3"


def test_wtfs_header_of_record_times_that_are_no_clock_gives_the_stamps_span(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The Logistic coBot's record times span 28 ns (a rosbag2_py writer's): wtf's header said "0.0 s recorded".
    It gives the span its tf is stamped over, as monitor's header does (27.667 s from 46.230 to 73.897), and says
    it is the stamps'; the JSON has it as ``stamped``."""
    _, path = _recording(corpus, LOGISTIC)
    header = tfx("wtf", path).stdout.splitlines()[0]
    assert header.endswith(
        "rosbag2-sqlite3, tf stamped over 27.7 s (the record times are no clock), 11669 transforms, 18 frames"
    ), header
    monitor = tfx("monitor", "-b", path).stdout.splitlines()[0]
    assert monitor.endswith(": tf stamped over 27.667 s from 46.230 to 73.897"), monitor
    _, bag, _ = _findings(tfx, path)
    assert bag["stamped"] == {"start": 46.23, "end": 73.897} and bag["end"] - bag["start"] < 1e-6, bag


def test_view_frames_and_report_of_record_times_that_are_no_clock_give_the_stamps_span(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The Logistic coBot's view-frames legend said "Recorded at time: 0.000 to 0.000 (0.000 s)" and its report's
    "Recorded" "0.000 to 0.000 (0.000 s, record clock)": both now give wtf's span, in monitor's words, said to be
    the stamps'."""
    _, path = _recording(corpus, LOGISTIC)
    over = "tf stamped over 27.667 s from 46.230 to 73.897 (the record times are no clock)"
    _, legend = _view_frames_legend(tfx, path)
    assert legend[0] == over and not [row for row in legend if "Recorded at time" in row], legend
    page = tmp_path / "cobot.html"
    tfx("report", "-b", path, "-o", page)
    facts = html.unescape(re.sub(r"<[^>]+>", "|", page.read_text()))
    assert re.search(r"\|Recorded\|+" + re.escape(over), facts) and "0.000 to 0.000" not in facts


def test_multiple_parents_on_tf_static_is_not_an_object_picked_up(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A calibration's /tf_static message sending box_base_model under two parents: tf2 keeps the last for every
    time; no 'object picked up' (a /tf re-parenting's story)."""
    _, path = _recording(corpus, CALIBRATION_2025)
    _, _, findings = _findings(tfx, path)
    (parents,) = [f for f in findings if f["code"] == "multiple_parents"]
    assert "picked up" not in parents["hint"] and "tf2 keeps the last static transform" in parents["hint"]


# --- filter: what no cache keeps ---------------------------------------------------------------


def test_filter_says_no_cache_keeps_messages_stamped_before_tf(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The boat's first 10 IMU messages are stamped before the recording's odom -> base_link began: no cache
    keeps them (the real MessageFilter drops them with a 15 s cache too), so no cache is suggested for them. They
    arrived 0.04-1.3 s into the recording, before any /tf (1.36 s in, at 10 Hz): lost, before any tf (exit 1)."""
    _, path = _recording(corpus, BOAT)
    result = tfx("filter", "-b", path, "--format", "json")
    assert result.code == 1, result.stderr
    (imu,) = [t for t in json.loads(result.stdout)["topics"] if t["topic"] == "/imu/data"]
    assert imu["before_tf"] == 10 and imu["cache_needed_s"] is None
    assert imu["reasons"] == {"before_any_tf": 10} and imu["undecided"] == {}, imu
    text = _words(tfx("filter", "-b", path).stdout)
    # recorded 1.3 s before the first /tf message arrived, stamped before any tf stamp: the sensor started first
    assert "10 stamped before the first tf anyone published: the sensor started before tf; no cache keeps" in text
    assert not re.search(r"cache \d", text)


def test_two_calibrations_placing_a_frame_apart_is_beneath_their_static_conflict(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """-b both GrandTour calibrations: prism_model is under prism in the 2024 one and under box_base in the 2025
    one: it follows from their static_conflict (said beneath it); box_base_model, sent under two parents by the
    2025 file itself, is that file's own mistake and stands alone."""
    _, first = _recording(corpus, "grandtour-calibration-2024-bag")
    _, second = _recording(corpus, CALIBRATION_2025)
    code, bag, findings = _findings(tfx, "-b", first, "-b", second)
    assert code == 1
    (conflict,) = [f for f in findings if f["code"] == "static_conflict"]
    parents = {f["frames"][0]: f for f in findings if f["code"] == "multiple_parents"}
    assert parents["prism_model"]["cause"] == conflict["key"] != ""
    assert parents["box_base_model"]["cause"] == ""
    assert bag["summary"]["errors"] == 2 and bag["summary"]["explained"] == 1
    assert sorted(code for code, _ in _junit_failures(tfx, first, second)) == ["multiple_parents", "static_conflict"]


RASPIMOUSE_REPLAY = "ros1-raspimouse-replayed-with-its-map-odom-beside-live-gmapping-2018-bag"


def test_echo_of_an_edge_on_two_clocks_prints_no_line_between_them(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The raspimouse replay beside a live gmapping: map -> odom from the replay (stamped 2018-05-09) and from the
    live node (2018-05-16). `tfx echo map odom` printed 603,917 lines, one a second across the week between the
    two clocks, where map -> odom has no sample, taking 38 s: now each clock's stretch alone, one line a second."""
    _, path = _recording(corpus, RASPIMOUSE_REPLAY)
    result = tfx("echo", "map", "odom", "-b", path, "-f", "json")
    assert result.code == 0, result.stderr
    times = [json.loads(line)["time"] for line in result.stdout.splitlines()]
    steps = [b - a for a, b in itertools.pairwise(times)]
    assert 100 < len(times) < 120 and sum(step > 2 for step in steps) == 1  # one jump: from one clock to the other
    monitor = json.loads(tfx("monitor", "-b", path, "-f", "json").stdout)
    (edge,) = [e for e in monitor["edges"] if (e["parent"], e["child"]) == ("map", "odom")]
    assert edge["first_stamp"] <= times[0] and times[-1] <= edge["last_stamp"]


def test_filter_says_imu_messages_before_the_simulations_first_tf_predate_tf(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The walker's first 6 /imu messages are stamped 0.173-0.198 s and recorded before the simulation's first
    tf (stamped 0.202 s) arrived: the recorder was listening, no tf existed yet. 'record tf from before the
    sensor' asked for what never was; the sensor started before tf, and there is nothing earlier to record."""
    _, path = _recording(corpus, WALKER_AT_SIM_START)
    (imu,) = [
        t for t in json.loads(tfx("filter", "-b", path, "--format", "json").stdout)["topics"] if t["topic"] == "/imu"
    ]
    assert imu["before_tf"] == 6 and imu["before_any_tf"] is True, imu
    # the label says what the advice says: lost, before any tf (not 'undecided: before recorded tf')
    assert imu["reasons"] == {"before_any_tf": 6} and "before_recorded_tf" not in imu["undecided"], imu
    text = _words(tfx("filter", "-b", path).stdout)
    assert "6 stamped before the first tf anyone published: the sensor started before tf" in text, text
    assert "6 never: before any tf 6" in text and "before recorded tf" not in text, text
    assert "nothing to record earlier" in text and "record tf from before the sensor" not in text


# --- one figure in every command ------------------------------------------------------------------


def _monitor_whole_and_played(tfx: Tfx, path: Path, *window: str) -> list[dict[str, Any]]:  # noqa: F811
    """``monitor``'s JSON of ``path`` read whole, and replayed (its last table, over all that played)."""
    whole = tfx("monitor", "-b", path, *window, "-f", "json")
    played = tfx("monitor", "-b", path, *window, "--play", "--rate", "200", "--window", "1000", "-f", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    return [json.loads(whole.stdout), json.loads(played.stdout.splitlines()[-1])]


def test_a_stamp_re_sent_in_a_window_is_new_to_a_replay_started_there_not_to_a_whole_read(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """slam_toolbox re-sends its latest map -> odom every 20 ms: in the JetAcker's +1 to +2 s it re-sends a stamp
    first heard before. A whole read holds it since then (1 sample in the window); ``--play --start +1`` starts
    the replay there, as ``ros2 bag play --start-offset``, and its listener hears it new (2). Both stay, said in
    docs/clocks.md; the messages are the same 54."""
    _, path = _recording(corpus, SLAM_TOOLBOX)
    reports = _monitor_whole_and_played(tfx, path, "map", "odom", "--start", "+1", "--end", "+2")
    samples = [{e["child"]: e["count"] for e in r["edges"]}["odom"] for r in reports]
    messages = [{a["authority"]: a["messages"] for a in r["authorities"]}["/tf"] for r in reports]
    assert (samples, messages) == ([1, 2], [54, 54])


@pytest.mark.parametrize(
    ("recording_id", "statics", "publisher"),
    [
        (AGV, {"back_laser_link": 104, "base_link": 104, "front_laser_link": 103}, None),
        (NEATO_BESIDE_URDF, {"base_link": 413, "base_laser_link": 1765}, ("/neato", 0.0007, 0.0055)),
    ],
)
def test_an_edge_ros1s_tf2_holds_static_has_no_delay_in_monitor_either(
    recording_id: str,
    statics: dict[str, int],
    publisher: tuple[str, float, float] | None,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Frames first on /tf_static, then on /tf too: ROS 1's tf2 holds them static for every time, view-frames and
    report show them static without delay; monitor's JSON gave them the /tf samples' (the agv's back laser
    -0.030 s, at most 0.350; the Neato's base_link 0.0007, its laser -0.050), whole and --play. None now; a
    publisher's delay stays how late its messages came (the Neato's driver, 0.7 ms, at most 5.5)."""
    _, path = _recording(corpus, recording_id)
    for report in _monitor_whole_and_played(tfx, path):
        shown = {e["child"]: e for e in report["edges"] if e["count"] > 1}
        assert {child: e["count"] for child, e in shown.items() if e["static"]} == statics, shown
        assert all(shown[child]["delay_mean_s"] is None and shown[child]["delay_max_s"] is None for child in statics)
        if publisher is not None:
            (node,) = (a for a in report["authorities"] if a["authority"] == publisher[0])
            assert (node["delay_mean_s"], node["delay_max_s"]) == pytest.approx(publisher[1:], abs=1e-4), node


@pytest.mark.parametrize(
    ("recording_id", "window", "counts"),
    [
        # stamped over 4.25 s of a simulation at 0.067x real time: 33 samples of odom -> base_footprint stamped in
        # its second second; 2 arrived in the second second of the replay, with the 54 /tf messages recorded 1 to 2 s
        # into the bag (51 and 1 when the replay started 30.7 s before the first stamp: the frames' median offset)
        (SLAM_TOOLBOX, ("+1", "+2"), {("odom", "base_footprint"): 2, "/tf": 54}),
        # at 0.97x: the 163 /tf messages recorded in the bag's first 3.37 s (164 from 0.011 s later, by the frames'
        # median offset)
        (
            FOXY_WALKER,
            ("+0", "+3.37"),
            {("odom", "base_footprint"): 97, ("base_link", "wheel_left_link"): 66, "/tf": 163},
        ),
    ],
)
def test_a_window_of_a_recording_without_clock_holds_one_set_whole_or_replayed(
    recording_id: str,
    window: tuple[str, str],
    counts: dict[tuple[str, str] | str, int],
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Simulations recorded without /clock: --start/--end selected a whole read's edges by stamp, its publishers'
    messages and the replay's edges on the record clock moved onto the stamps. One axis now
    (``Timeline.arrival``): the same samples and messages, whole and --play."""
    _, path = _recording(corpus, recording_id)
    for report in _monitor_whole_and_played(tfx, path, "--start", window[0], "--end", window[1]):
        found: dict[tuple[str, str] | str, int] = {(e["parent"], e["child"]): e["count"] for e in report["edges"]}
        found.update({a["authority"]: a["messages"] for a in report["authorities"]})
        assert {key: found.get(key) for key in counts} == counts, found


# --- corpus27: a Husky, a custom diff-drive robot and a hobby robot of 2013-2016 (ROS 1) ------------------
HUSKY = "ros1-husky-real-gps-imu-tf1-robot-state-publisher-post-dated-half-second-2013-bag"


def test_the_husky_s_odometry_frame_is_told_its_tf_not_a_mount(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real Clearpath Husky of 2013 (tf1's /tf, before /tf_static): /encoder's Odometry is in odom_combined,
    robot_pose_ekf's frame, which did not run. Its own transform is missing, as `tfx filter /encoder` says; wtf
    told it "the sensors' mounts come on /tf ... run their publisher", the words for /fix's GPS mount."""
    result = tfx("wtf", corpus(BY_ID[HUSKY]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    missing = {tuple(f["frames"]): f for f in bag["findings"] if f["code"] == "sensor_frame"}
    assert sorted(missing) == [("/gps",), ("/world",), ("odom_combined",)]
    encoder = missing[("odom_combined",)]["hint"]
    assert "'odom_combined' is the frame of odometry (nav_msgs/Odometry)" in encoder and "mounts" not in encoder
    assert "from before /tf_static: the sensors' mounts come on /tf" in missing[("/gps",)]["hint"]
    assert result.code == 1


DELTA = "ros1-custom-diff-drive-real-hokuyo-scans-in-unnamed-frame-clock-at-2000-tf1-2013-bag"


def test_scans_in_a_frame_tf_never_names_are_told_the_frame_id_remedy_too(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real custom diff-drive robot of 2013 (tf1's /tf): its Hokuyo's scans are in base_laser, its laser mounted
    as 'laser'. wtf told only "run their publisher"; the driver's frame_id is the other remedy, as `tfx filter
    /scan` says ("publish its frame's transform, or fix the frame_id")."""
    result = tfx("wtf", corpus(BY_ID[DELTA]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (missing,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert missing["frames"] == ["base_laser"]
    assert "run their publisher, or set the driver's frame_id parameter" in missing["hint"]
    assert result.code == 1


JOHNNY5 = "ros1-hobby-diff-drive-real-neato-lidar-robot-clock-5.7-s-behind-recorder-2016-bag"


def test_a_robot_clock_behind_the_recorder_s_is_told_as_a_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A hobby robot of 2016: its three publishers' edges all recorded 5.6-6.2 s after their stamps, none sooner.
    wtf said each 'arrives late' and to find a busy publisher or a slow link; the bytes show the robot's clock
    ~5.7 s behind the recorder's, which the delay's hint now says first."""
    result = tfx("wtf", corpus(BY_ID[JOHNNY5]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    late = [f for f in bag["findings"] if f["code"] == "delay"]
    assert len(late) == 6
    for finding in late:
        assert "most likely the publisher's clock runs behind the recorder's" in finding["hint"], finding["hint"]
    assert result.code == 0


POTTED_PLANT = "ros2-potted-plant-agv-real-fastlio-icp-ekf-2026-db3"


def test_an_instant_s_wait_for_the_transform_of_its_own_stamp_is_said_as_one(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The potted-plant AGV's /agv_pose (in map) and map -> odom of the same stamp: read with rosbags, every pose
    is recorded 3 us to 1.8 ms before that transform. sensor_wait said "waiting under 1 ms" and "make the late
    transform come sooner", which no one can: the two are sent together, the pose first. A MessageFilter still
    queues each pose (not transformable when it arrives) and passes it that instant, so the note stays, saying
    that only a lookup as the pose arrives fails, and that sending the transform first is the remedy."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    path = corpus(BY_ID[POTTED_PLANT])
    poses: list[tuple[int, int]] = []
    sent: dict[int, int] = {}
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        chosen = [c for c in reader.connections if c.topic in ("/agv_pose", "/tf")]
        for connection, record, raw in reader.messages(chosen):
            message: Any = reader.deserialize(raw, connection.msgtype)
            if connection.topic == "/agv_pose":
                poses.append((record, message.header.stamp.sec * 10**9 + message.header.stamp.nanosec))
            for t in getattr(message, "transforms", ()):
                if (t.header.frame_id, t.child_frame_id) == ("map", "odom"):
                    sent.setdefault(t.header.stamp.sec * 10**9 + t.header.stamp.nanosec, record)
    gaps = [sent[stamp] - record for record, stamp in poses]
    assert len(gaps) == 1146 and min(gaps) > 0 and max(gaps) < 2_000_000
    found = json.loads(tfx("wtf", "-b", path, "-f", "json").stdout)["bags"][0]["findings"]
    (wait,) = [f for f in found if f["code"] == "sensor_wait"]
    assert wait["severity"] == "info" and wait["message"].startswith("/agv_pose: 1146 of 1146 messages")
    assert "for map -> odom" in wait["message"] and "(sent together, the message first)" in wait["message"]
    assert wait["hint"].endswith("or send the transform before the message (where one node publishes both)")
