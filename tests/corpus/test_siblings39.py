"""Issue 39's findings that the bytes explain better (brief siblings39), each on the real recording that showed it:
the GrandTour calibration whose one /tf_static message gives a frame two parents, repaired; CyberShip Voyager's IMU
streams waiting for its motion capture."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus import variants
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_issue39 import _findings
from tests.sinks.test_static_bag import _static_changes
from tftools.analysis.wtf.scene import Scene
from tftools.sources.recording import read_recording

GTBOX_NEW = "grandtour-calibration-2025-bag"


def test_a_repaired_copy_of_gtbox_changes_box_base_models_parent_as_often_as_the_recording(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """ros1_gtbox_tf_static_metadata_new_0.bag: one /tf_static message (its first message) sends box_base_model
    under stim320_imu and then under box_base. Its repaired copy repeated that message ahead of itself: 'it changed
    parent 3 times' where the recording says 1. The copy now says 1, ends under box_base as the recording does,
    and lists the 36 static transforms tf2 holds (the message's 37 less the one it loses)."""
    bag = corpus(BY_ID[GTBOX_NEW])
    copy = tmp_path / "repaired.bag"
    said = tfx("static", "--repair", "-b", bag, "-o", copy)
    assert said.code == 0 and "with its 36 static transforms" in said.stdout, said.stdout
    assert "stim320_imu -> box_base_model" not in said.stdout
    for path in (bag, copy):
        (parents,) = [f for f in _findings(tfx, path)[2] if f["code"] == "multiple_parents"]
        assert parents["count"] == 1 and parents["frames"] == ["box_base_model", "stim320_imu", "box_base"], parents
        assert "it changed parent 1 time" in parents["message"] and "is now under box_base" in parents["message"]


@pytest.mark.parametrize(
    "recording_id", ["ros2-cybership-voyager-mocap-basin-2025-db3", "ros2-cybership-voyager-mocap-basin-2025-mcap"]
)
def test_cyberships_imu_streams_waiting_for_the_motion_capture_are_one_cause(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """CyberShip Voyager: its IMU, raw IMU, magnetometer and temperature (imu_link, ~62 Hz) each waited for the
    motion capture's world -> base_link (10 Hz, recorded ~90 ms after its stamp) in four notes alike, each telling
    a MessageFilter's queue and timeout into world. One cause now, the others beneath it (each still in JSON with
    its own figures), and the hint says first what the bytes show: imu_link is fixed to base_link, so into
    base_link the data transforms at once; only into world does it wait."""
    findings = _findings(tfx, corpus(BY_ID[recording_id]))[2]
    waits = [f for f in findings if f["code"] == "sensor_wait"]
    topics = sorted(f["message"].split(":")[0] for f in waits)
    assert topics == [f"/voyager/measurement/{t}" for t in ("imu", "imu_raw", "mag", "temp")], topics
    (cause,) = [f for f in waits if not f["cause"]]
    assert all(f["cause"] == cause["key"] and f["frames"] == ["world", "base_link"] for f in waits if f is not cause)
    assert cause["hint"].startswith(
        "into base_link (imu_link fixed to it) it transforms at once, with no wait; into world"
    )


UR5 = "ros2-ur5-two-clocks-topic-tf-2023-db3"


def test_the_ur5s_obj_frames_are_detections_by_their_siblings_under_the_camera(corpus: Corpus) -> None:
    """ros2_db3_ur5_topic_tf_two_clocks: base_link -> obj_1/3/49, 4 samples 2 s apart, never unseen, were no
    detection (a name alone is none); each sample is sent 0.13-0.58 ms after one of camera_link -> cam_N, the same
    ArUco marker in the camera's frame. They are detections now, by that sibling; cam_N (named as a camera's frames
    are) is not said one."""
    scene = Scene(read_recording([corpus(BY_ID[UR5])]))
    assert set(scene.detections) == {("base_link", "obj_1"), ("base_link", "obj_3"), ("base_link", "obj_49")}
    why, seen = scene.detections[("base_link", "obj_49")]
    assert seen is None
    assert why == (
        "obj_49 is named as a detector names what it sees, and cam_49, under the camera frame camera_link, is sent "
        "with it at each of its 4 sightings"
    )


def test_the_ur5s_trees_apart_are_joined_by_the_camera_mount_its_markers_show(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The UR5's camera_link tree (cam_1/3/49) and base_link's were two trees with a hint that /tf_static was not
    recorded. The ArUco node sent each marker in both, at the same instants, and all 12 pairs place camera_link at
    (-0.970, 0, 1.040) m from base_link, pitched 15 deg (obj_3's first sighting 8 mm off): the hint says so and
    gives the static transform to publish."""
    (apart,) = [f for f in _findings(tfx, corpus(BY_ID[UR5]))[2] if f["code"] == "disconnected"]
    assert apart["hint"].startswith(
        "a detector sends each of its markers twice, obj_1, obj_3 and obj_49 under base_link and cam_1, cam_3 and "
        "cam_49 under camera_link, at the same instants: all 12 sightings place camera_link at (-0.970, 0.000, 1.040) "
        "m from base_link, turned roll 0.0, pitch 15.0, yaw 0.0 deg (each within 8 mm): the camera's mount"
    ), apart["hint"]
    assert "--frame-id base_link --child-frame-id camera_link" in apart["hint"]


#: Recordings whose /tf_static messages disagree, each with the changes of parent and of value tf2 sees on it, which
#: its repaired copy had many more of (the recording's messages replayed at each 5 s repeat): 441 changes of value
#: in the create3's copy, 23 in the Neato's, 16 in Allison's (both URDF and driver repeated), 2 of parent in gtbox's
#: (its message giving box_base_model two parents, had it not come at the first instant).
DISAGREEING = {
    "ros2-create3-real-two-urdfs-2022-db3": (0, 21),
    "ros2-neato-real-two-static-publishers-2023-db3": (0, 1),
    "ros2-neato-real-lone-laser-beside-statics-20hz-allison-2022-db3": (0, 2),
    "ros2-neato-real-static-conflict-urdf-first-2025-db3": (0, 1),
    GTBOX_NEW: (1, 0),
}
#: The transforms of an overridden /tf_static message that tf2 still holds, which the copy repeats in the message that
#: overrode it: the create3's first URDF's 12 beside the second's 23, the URDF-first Neato's 9 links beside its lone
#: laser.
REPEATED_IN_THE_OVERRIDER = {
    "ros2-create3-real-two-urdfs-2022-db3": 12,
    "ros2-neato-real-static-conflict-urdf-first-2025-db3": 9,
}


@pytest.mark.parametrize("recording_id", list(DISAGREEING))
def test_a_repaired_copy_changes_no_static_parent_or_value_more_than_its_recording(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The repair repeats what tf2 holds at each instant, not the recording's messages: its copy's changes of parent
    and of value on /tf_static are the recording's, and wtf tells the same publishers apart, each first heard when
    the recording first has it but the first, which the copy's start holds (the create3's second URDF was said at
    the copy's start, 0.6 s early). What tf2 still holds of an overridden message is repeated in its overrider's
    (``HeldStatics.at``): there the two publishers agree on those transforms too, and no more differ."""
    bag = corpus(BY_ID[recording_id])
    copy = tmp_path / ("repaired.bag" if bag.suffix == ".bag" else "repaired")
    assert tfx("static", "--repair", "-b", bag, "-o", copy).code == 0
    assert _static_changes(bag) == _static_changes(copy) == DISAGREEING[recording_id]
    was, now = (
        [
            {k: v for k, v in f["figures"].items() if k != "publisher_1_at_s"}  # the copy's start has publisher 1's
            for f in _findings(tfx, path)[2]
            if f["code"] == "static_conflict"
        ]
        for path in (bag, copy)
    )
    for conflict in now:
        conflict["transforms_agreeing"] -= REPEATED_IN_THE_OVERRIDER.get(recording_id, 0)
    assert now == was


@pytest.mark.parametrize("recording_id", list(REPEATED_IN_THE_OVERRIDER))
def test_a_split_of_a_repaired_copy_after_a_partial_override_has_every_static_frame(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The create3's second URDF overrides 21 of the first's 33 transforms 0.6 s after it; the URDF-first Neato's lone
    laser one of robot_state_publisher's 10. The copies repeated only the overriding message: a split from +15 s had
    26 frames of the create3's 38 (sensor_frame: /scan's rplidar_link named by no transform), of the Neato's 14 only
    6 (two trees, disconnected). The rest of the overridden message is repeated in the overrider's: a split has every
    frame, and wtf says of it nothing the recording does not."""
    recording = BY_ID[recording_id]
    bag = corpus(recording)
    copy = tmp_path / "repaired"
    assert tfx("static", "--repair", "-b", bag, "-o", copy).code == 0
    contents = variants.read(copy)
    start = min(t for _, t, _ in contents.messages) + 15 * 10**9
    kept = [m for m in contents.messages if m[1] >= start]
    split = variants.write_ros2(tmp_path / "split", variants.Contents(False, contents.connections, kept))
    _, report, found = _findings(tfx, split)
    assert report["frames"] == recording.meta["frames"]
    assert {f["code"] for f in found} <= {f["code"] for f in _findings(tfx, bag)[2]}, found
