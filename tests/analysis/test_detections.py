"""A detector's edges (markers a camera sees and loses) said as detections by wtf's stale, jump and rate, and a
robot's own edge that stops still said as a publisher that stopped (issue 39, DIGIT_works' ArUco recording)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.detections import by_siblings, detection
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.fleet import check
from tftools.core.figures import sightings
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

MS = 1_000_000


def _seen(
    child: str, seconds: list[float], x: float = 1.0, flip_at: float | None = None, hop_at: float | None = None
) -> list[TfMessage]:
    """camera -> ``child`` at each of ``seconds`` after the scenes' START, recorded 30 ms later; rotated 30
    degrees about x at ``flip_at`` alone (a planar marker's pose flipping to its other solution and back); 0.2 m
    further at ``hop_at`` alone, its rotation as ever (a depth detector taking another object for it)."""
    messages = []
    for s in seconds:
        stamp = scenes.START + round(s * NS_PER_S)
        roll = 0.52 if flip_at is not None and abs(s - flip_at) < 1e-9 else 0.0
        depth = 0.7 if hop_at is not None and abs(s - hop_at) < 1e-9 else 0.5
        seen = Transform.from_rpy((x, 0.0, depth), (roll, 0.0, 0.0), stamp, "camera", child)
        messages.append(TfMessage("/tf", stamp + 30 * MS, [seen], "/aruco"))
    return messages


def _bursts() -> list[float]:
    """25 Hz while seen, for 0.4 s out of every second over 10 s: a marker the camera keeps losing."""
    return [b + i * 0.04 for b in range(10) for i in range(10)]


def _check(*parts: list[TfMessage]) -> list[Finding]:
    messages = scenes.healthy(**{f"part{i}": p for i, p in enumerate(parts)})
    return check(scenes.recording(messages, ros1=False)).findings


def _of(findings: list[Finding], code: str, child: str) -> Finding:
    (found,) = [f for f in findings if f.code == code and f.frames[-1] == child]
    return found


def test_a_marker_seen_once_is_stale_as_a_detection_not_a_transform_to_publish_statically() -> None:
    """A warning, not an error: what a detector sees comes and goes; nothing stopped (DIGIT_works' marker_367)."""
    stale = _of(_check(_seen("marker_367", [3.0])), "stale", "marker_367")
    assert stale.severity is Severity.warning, stale
    assert "a detection" in stale.message and "was seen once, at" in stale.message, stale.message
    assert "static_transform_publisher" not in stale.hint and "keep publishing" not in stale.hint, stale.hint
    assert "only as fresh as its last sighting" in stale.hint and "timeout" in stale.hint, stale.hint


def test_a_robots_own_edge_that_stops_is_still_a_publisher_that_stopped() -> None:
    findings = check(scenes.recording(scenes.healthy(amcl=scenes.amcl(end=6.0)), ros1=False)).findings
    stale = _of(findings, "stale", "odom")
    assert stale.severity is Severity.error, stale
    assert "a detection" not in stale.message and "its publisher stopped" in stale.hint, stale


def test_a_marker_lost_before_the_end_says_how_it_was_seen_and_when_last() -> None:
    stale = _of(_check(_seen("tag_3", [b + i * 0.04 for b in range(4) for i in range(10)])), "stale", "tag_3")
    assert "was seen 40 times, seen in 4 bursts, at 25.0 Hz within them" in stale.message, stale.message
    assert "last at" in stale.message, stale.message


def test_a_markers_pose_flip_is_a_detectors_ambiguity_not_a_localization_correction() -> None:
    flips = _of(_check(_seen("marker_0", [i * 0.04 for i in range(250)], flip_at=5.0)), "jump", "marker_0")
    assert "a detection" in flips.message, flips.message
    assert "ambiguous" in flips.hint and "map -> odom" not in flips.hint, flips.hint


def test_a_detections_position_step_with_its_rotation_never_changing_is_no_markers_flip() -> None:
    """e-Yantra's Krishi Bot in Gazebo (atom-robotics-lab/eyrc22_KB_1133's KB_1133.bag, a scout's): fruits found
    by depth, their rotation identity throughout, one hopping 0.2 m between two fruits; told a planar marker's
    pose is ambiguous and to use a larger marker. Said as the position's step it is."""
    seen = _seen("fruit_red_1", _bursts(), hop_at=_bursts()[55])  # comes and goes, as the fruits did
    hops = _of(_check(seen), "jump", "fruit_red_1")
    assert "a detection" in hops.message and "0.0°" in hops.message, hops.message
    assert hops.hint.startswith("a detector's position estimate steps") and "marker" not in hops.hint, hops.hint


def test_map_to_odom_and_a_robots_jump_keep_the_localization_hint() -> None:
    findings = check(scenes.recording(scenes.PROBLEMS["jump"].make(), ros1=False)).findings
    jumped = [f for f in findings if f.code == "jump"]
    assert jumped and all("map -> odom" in f.hint and "a detection" not in f.message for f in jumped), jumped


def test_a_marker_seen_in_short_bursts_says_its_rate_within_them_not_a_period_few_intervals_keep() -> None:
    """2 to 5 sightings 40 ms apart, then 0.12 to 0.3 s unseen (no pause: under ``max_gap``), to the end: the
    real marker_222's flicker, most intervals off any one period."""
    flickers, t = [], 0.0
    for b in range(35):
        flickers += [t + i * 0.04 for i in range((3, 2, 4, 3, 5, 2)[b % 6])]
        t = flickers[-1] + (0.2, 0.12, 0.3, 0.16, 0.24)[b % 5]
    rate = _of(_check(_seen("marker_222", flickers)), "rate", "marker_222")
    assert rate.message.endswith(
        "is seen in 35 bursts, at 25.0 Hz within them, 31% of the time from its first sighting to its last "
        "(unseen for up to 0.300 s)"
    ), rate.message
    assert "it keeps up most of the time" not in rate.message and "timeout" in rate.hint, rate


def test_a_marker_lost_for_seconds_says_its_longest_time_unseen_and_how_it_was_seen() -> None:
    rate = _of(_check(_seen("marker_111", _bursts())), "rate", "marker_111")
    assert "went unseen 9 times" in rate.message and "the longest for 0.640 s" in rate.message, rate.message
    assert rate.message.endswith(
        "seen in 10 bursts, at 25.0 Hz within them, 38% of the time from its first sighting to its last"
    ), rate.message
    assert "check the publisher's load" not in rate.hint, rate.hint


def test_a_markers_missed_frames_and_its_pauses_are_both_counted() -> None:
    """Seen at 25 Hz in bursts 0.2 s apart (a frame or four missed: unseen, no pause) and twice lost for 2 s: 'went
    unseen 2 times' beside 'seen in 13 bursts' read as a contradiction (the DIGIT_works ArUco's marker_111)."""
    seconds, t = [], 0.0
    for b in range(13):
        seconds += [t + i * 0.04 for i in range(10)]
        t = seconds[-1] + (2.0 if b in (4, 8) else 0.2)
    rate = _of(_check(_seen("marker_111", seconds)), "rate", "marker_111")
    assert "went unseen 12 times, 2 of them for longer than its rhythm" in rate.message, rate.message
    assert "seen in 13 bursts" in rate.message, rate.message


def test_sightings_are_bursts_parted_by_a_missed_frame() -> None:
    stamps = np.array([b * 1000 + i * 40 for b in range(10) for i in range(10)], np.int64) * MS
    seen = sightings(stamps)
    assert seen is not None
    assert (seen.bursts, round(seen.rate_hz, 3), round(seen.seen, 3)) == (10, 25.0, round(3.6 / 9.36, 3))
    assert (seen.longest_unseen, seen.longest_unseen_start) == (640 * MS, 360 * MS)
    assert sightings((np.arange(50) * 40 * MS).astype(np.int64)) is None  # never unseen: one rate, the stream's


@pytest.mark.parametrize(
    ("parent", "child", "count", "expected"),
    [
        ("camera", "marker_367", 1, True),
        ("camera", "tag0", 300, True),
        ("usb_cam", "tag36h11:0", 300, True),
        ("base_link", "obj_49", 1, True),  # a detector's name, seen once
        ("base_link", "obj_12", -300, True),  # a detector's name, lost for 1 s in the middle
        ("base_link", "tag_3", 300, False),  # a robot's own frame so named, published steadily with the robot
        ("base_link", "object_1", 4, False),  # the name alone, never unseen: nothing in the bytes says detected
        ("camera_color_optical_frame", "drone", 1, True),  # a camera's child seen once: it came and went
        ("camera_color_optical_frame", "drone", 300, False),  # seen throughout: nothing says it is detected
        ("camera_color_optical_frame", "drone", -300, True),  # lost for 1 s in the middle: it came and went
        ("odom", "base_link", 1, False),
        ("camera_link", "camera_color_optical_frame", 1, False),  # a camera's own frames
        ("base_link", "tag_link", 1, False),
    ],
)
def test_detections_are_told_by_their_names_or_a_camera_above_a_child_that_comes_and_goes(
    parent: str, child: str, count: int, expected: bool
) -> None:
    """A detector's name counts beside evidence in the bytes (a camera frame above it, seen once or in bursts):
    a robot's own ``tag_3`` published steadily on /tf with the robot is the robot's frame, not a detection."""
    stamps = (np.arange(abs(count)) * 40 * MS).astype(np.int64)
    if count < 0:
        stamps[abs(count) // 2 :] += NS_PER_S
    assert (detection(parent, child, stamps) is not None) is expected


def test_a_detections_reason_says_the_evidence_beside_its_name() -> None:
    steady = (np.arange(300) * 40 * MS).astype(np.int64)
    paused = steady.copy()
    paused[150:] += NS_PER_S
    assert detection("camera", "marker_0", steady) == (
        "marker_0 is named as a detector names what it sees, under the camera frame camera"
    )
    assert (
        detection("base_link", "obj_12", paused)
        == "obj_12 is named as a detector names what it sees, and comes and goes"
    )
    assert detection("base_link", "obj_12", steady) is None


def _ur5(offset_ms: float = 0.2, count: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """corpus ros2_db3_ur5_topic_tf_two_clocks' shape: camera_link -> cam_N sighted every 2 s, and base_link ->
    obj_N (the same marker in the robot's frame) sent ``offset_ms`` after each, ``count`` of them."""
    cam = (np.arange(4) * 2 * NS_PER_S).astype(np.int64)
    return cam, (cam + round(offset_ms * MS))[:count]


def test_a_detectors_name_counts_beside_a_sibling_sent_with_it_under_a_camera_frame() -> None:
    """The UR5's obj_1 under base_link, 4 samples 2 s apart, never unseen: its name alone is no evidence, but
    cam_1 under camera_link is sent with it at each sighting (0.1 to 0.6 ms before): the ArUco node's marker in the
    camera's frame. obj_1 is a detection; cam_1, named as a camera's frames are, is not said one."""
    cam, obj = _ur5()
    found = by_siblings([("camera_link", "cam_1", cam), ("base_link", "obj_1", obj), ("base_link", "obj_3", obj)])
    assert found == {
        ("base_link", "obj_1"): (
            "obj_1 is named as a detector names what it sees, and cam_1, under the camera frame camera_link, "
            "is sent with it at each of its 4 sightings",
            ("camera_link", "cam_1"),
        )
    }


@pytest.mark.parametrize(
    ("camera", "sibling", "offset_ms", "count"),
    [
        ("camera_link", "cam_1", 50.0, 4),  # sent 50 ms apart: not one callback's
        ("camera_link", "cam_1", 0.2, 3),  # a sighting of one without the other
        ("arm_link", "cam_1", 0.2, 4),  # under no camera frame
        ("camera_link", "cam_2", 0.2, 4),  # another marker
    ],
)
def test_no_sibling_without_a_camera_frame_the_same_number_and_the_same_instants(
    camera: str, sibling: str, offset_ms: float, count: int
) -> None:
    cam, obj = _ur5(offset_ms, count)
    assert by_siblings([(camera, sibling, cam), ("base_link", "obj_1", obj)]) == {}


def test_markers_unseen_together_are_no_stall() -> None:
    """e-Yantra Agri Bot's detector (2021) names its tomatoes by their place in a list, obj0 to obj43: whenever the
    camera turned away, 20 of them went unseen within a second of each other, told a stall ('look for what these
    publishers share') 16 times while the detector went on publishing the others. What a detector sends only while
    it sees it is no publisher stopping; the robot's own edges stopping together still are."""
    seen = [s for s in np.arange(0.0, 10.0, 0.04) if not 3.0 <= s < 6.0]
    markers = [_seen(f"obj{n}", [s + n * 0.007 for s in seen], x=1.0 + n) for n in range(4)]
    assert not [f for f in _check(*markers) if f.code == "stall"]


def test_a_detection_sent_at_its_cameras_origin_is_told_so() -> None:
    """Agri Bot's detector (2021) sends (0, 0, 0) where it found no depth: 62% of its transforms put the tomato
    at the camera, hopping 1 m to and from real sightings; the jumps were told as another object taken for it."""
    messages = []
    for i in range(250):
        stamp = scenes.START + i * 40 * MS
        found = (0.0, 0.0, 0.0) if i % 25 == 7 else (1.0, 0.1, 0.5)
        seen = Transform(found, (0.0, 0.0, 0.0, 1.0), stamp, "camera", "obj2")
        messages.append(TfMessage("/tf", stamp + 30 * MS, [seen], "/detector"))
    jump = _of(_check(messages), "jump", "obj2")
    said = "; 10 of its 250 transforms exactly at camera's origin (0, 0, 0), stepping there or back 20 times"
    assert jump.message.endswith(said), jump.message
    assert jump.hint.startswith("a detector sending its camera's origin where it found nothing"), jump.hint


def test_a_detectors_objects_each_told_alike_are_one_finding_per_kind() -> None:
    """Agri Bot's detector (2021) sent 44 tomatoes, each unseen, stale and hopping to the camera's origin alike: 109
    warnings, one per object and kind. Each kind is one finding, the first object's, with the others beneath; a
    second camera's markers are another detector's, and stay apart."""
    seen = [s for s in np.arange(0.0, 8.0, 0.04) if not 3.0 <= s < 6.0]
    markers = [_seen(f"obj{n}", [s + n * 0.007 for s in seen], x=1.0 + n) for n in range(4)]
    its = _seen("obj9", [s + 0.013 for s in seen[:-5]])
    other = [[dataclasses.replace(m, transforms=[_under("camera2", t) for t in m.transforms]) for m in its]]
    found = _check(*markers, *other)
    for code in ("stale", "rate"):
        told = [f for f in found if f.code == code and f.frames[0] == "camera"]
        assert len(told) == 4 and [bool(f.cause) for f in told] == [False, True, True, True], told
        assert {f.cause for f in told[1:]} == {told[0].key}, told
        (apart,) = [f for f in found if f.code == code and f.frames[0] == "camera2"]
        assert not apart.cause and apart.key != told[0].key, apart
        assert all(f.figures.get("detection") == 1 for f in (*told, apart))


def _under(camera: str, seen: Transform) -> Transform:
    return Transform(seen.translation, seen.rotation, seen.stamp, camera, seen.child_frame_id)


def test_a_detection_seen_again_elsewhere_after_time_unseen_did_not_jump() -> None:
    """Agri Bot's task 3.2 (2021): obj0 seen for 0.1 s, then 36.7 s later 0.41 m away, told 'jumped once further than
    its own motion explains' in 36.724 s: where it went while unseen (the robot drove on; a detector naming by a
    list's place gave the name to another tomato) is no step of its estimate. A step within a sighting still is."""
    before = [s for s in np.arange(0.0, 3.0, 0.04)]
    after = [s for s in np.arange(6.0, 10.0, 0.04)]
    seen = _seen("marker_3", before, x=1.0) + _seen("marker_3", after, x=1.4)
    assert not [f for f in _check(seen) if f.code == "jump"]
    hopped = _seen("marker_4", before + after, x=1.0, hop_at=after[40])
    assert [f.code for f in _check(hopped) if f.code == "jump"] == ["jump"]


def test_a_tracked_persons_jump_under_map_is_not_said_to_be_the_robots_localization() -> None:
    """ros4hri's person tracks (2022): map -> person_eloek stepped 0.155 m in 0.1 s, and the hint said to publish it
    as map -> odom. A leaf under map that carries nothing and is named as no base may be something tracked; the
    robot's base stepping in map keeps the localization hint."""

    def walking(child: str) -> list[TfMessage]:
        def pose(stamp: int) -> list[Transform]:
            s = (stamp - scenes.START) / NS_PER_S
            x = 0.1 * s + (0.5 if s >= 5.013 else 0.0)
            return [Transform.from_rpy((x, 1.0, 0.0), (0.0, 0.0, 0.0), stamp, "map", child)]

        return scenes.periodic("/tracker", 10, pose, phase=0.013)

    (person,) = [f for f in _check(walking("person_eloek")) if f.code == "jump"]
    assert "something tracked" in person.hint and person.hint.startswith("person_eloek carries no frame"), person.hint
    (robot,) = [f for f in _check(walking("base_footprint")) if f.code == "jump"]
    assert "something tracked" not in robot.hint, robot.hint
