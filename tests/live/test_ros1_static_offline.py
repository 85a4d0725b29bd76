"""``tfx static`` without a master: its argument forms, YAML files, and copies of bags."""

from __future__ import annotations

import hashlib
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tests.live.conftest import ROS_PYTHON
from tftools.core.rotation import Quat
from tftools.core.transform import Transform
from tftools.sources import read_recording
from tftools.sources.live.static_file import StaticFileError, read_static_transforms

ROSTOPIC_ECHO = """\
transforms:
  -
    header:
      seq: 0
      stamp:
        secs: 1700000000
        nsecs:         0
      frame_id: "base_link"
    child_frame_id: "laser"
    transform:
      translation:
        x: 0.2
        y: 0.0
        z: 0.1
      rotation:
        x: 0.0
        y: 0.0
        z: 0.7071067811865476
        w: 0.7071067811865476
---
"""


def test_reads_what_rostopic_echo_prints(tmp_path: Path) -> None:
    path = tmp_path / "static.yaml"
    path.write_text(ROSTOPIC_ECHO)
    (t,) = read_static_transforms(path)
    assert (t.frame_id, t.child_frame_id) == ("base_link", "laser")
    assert t.translation == (0.2, 0.0, 0.1)
    assert t.rotation == pytest.approx((0, 0, math.sqrt(0.5), math.sqrt(0.5)))


def test_reads_flat_entries_with_rpy_or_quaternions(tmp_path: Path) -> None:
    path = tmp_path / "flat.yaml"
    path.write_text(
        "- {frame_id: base_link, child_frame_id: laser, x: 0.2, z: 0.1, yaw: 1.5}\n"
        "- {frame_id: base_link, child_frame_id: camera, translation: [0.1, 0, 0.3], rotation: [0, 0, 1, 0]}\n"
        "- {frame_id: camera, child_frame_id: optical, rpy: [-1.5707963, 0, -1.5707963]}\n"
    )
    laser, camera, optical = read_static_transforms(path)
    assert laser.translation == (0.2, 0.0, 0.1)
    assert laser.rotation == pytest.approx(Transform.from_rpy((0, 0, 0), (0, 0, 1.5)).rotation)
    assert camera.rotation == (0.0, 0.0, 1.0, 0.0)
    assert optical.rotation == pytest.approx(Transform.from_rpy((0, 0, 0), (-1.5707963, 0, -1.5707963)).rotation)


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("- {child_frame_id: b}\n", "has no frame_id"),
        ("- {frame_id: a, child_frame_id: b, x: nope}\n", "'nope' is not a number"),
        ("- {frame_id: a, child_frame_id: b, yaw: 1, qw: 1}\n", "both a quaternion and roll/pitch/yaw"),
        ("[unclosed\n", "not valid YAML .expected ',' or ']', but got '<stream end>' at line 2"),
        ("", "lists no transforms"),
    ],
)
def test_bad_files_say_which_entry_and_why(tmp_path: Path, text: str, problem: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(StaticFileError, match=problem):
        read_static_transforms(path)


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["1", "2", "3", "a", "b"], "5 arguments: expected 8"),
        (["0", "0", "0", "0", "0", "0", "a", "a"], "the frame and the child frame are the same"),
        (["0", "0", "x", "0", "0", "0", "a", "b"], "'x' is not a number"),
        (["0", "0", "0", "0", "0", "0", "0", "a", "b"], "the quaternion is zero"),
        (["--x", "1", "--frame-id", "a"], "--frame-id and --child-frame-id are both needed"),
        (["--qx", "1", "--roll", "1", "--frame-id", "a", "--child-frame-id", "b"], "a quaternion or roll/pitch/yaw"),
        (["1", "2", "3", "0", "0", "0", "a", "b", "--x", "1"], "not both"),
        (["0", "0", "0", "0", "0", "0", "a", "b", "-b", "in.bag"], "-b BAG and -o OUTPUT go together"),
        ([], "no transform given"),
    ],
)
def test_bad_arguments_are_one_line_errors(tfx: Tfx, arguments: list[str], message: str) -> None:
    result = tfx("static", *arguments)
    assert result.code == 2
    assert message in result.stderr
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr


def _digest(path: Path) -> str:
    files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
    return hashlib.sha256(b"".join(f.read_bytes() for f in files)).hexdigest()


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap"])
def test_bag_copy_adds_the_transforms_at_the_start(tfx: Tfx, tmp_path: Path, fmt: str) -> None:
    source = SAMPLE_BAGS[fmt]
    before = _digest(source)
    output = tmp_path / ("out.bag" if fmt == "ros1" else "out")
    result = tfx("static", "0.5", "0", "0.25", "1.0", "0", "0", "base_link", "tool_x", "-b", source, "-o", output)
    assert result.code == 0, result.stderr
    assert _digest(source) == before  # the input is never modified
    ours, theirs = read_recording([output]), read_recording([source])
    assert ours.contents.files[0].message_count == theirs.contents.files[0].message_count + 1
    assert ours.start == theirs.start - 1  # recorded just before the recording's first message (not at its instant)
    added = ours.buffer.lookup("base_link", "tool_x")
    expected = Transform.from_rpy((0.5, 0, 0.25), (0, 0, 1.0))
    np.testing.assert_allclose(added.rotation, expected.rotation, atol=1e-12)
    assert added.translation == (0.5, 0.0, 0.25)
    history = ours.buffer.history("tool_x")
    assert history is not None and history.static
    # every transform of the input is still there, in the same order
    rows = ours.transforms
    mask = np.array([rows.frame_names[c] != "tool_x" for c in rows.child])
    np.testing.assert_array_equal(rows.stamp[mask], theirs.transforms.stamp)


def test_bag_copy_refuses_to_overwrite_without_force(tfx: Tfx, tmp_path: Path) -> None:
    output = tmp_path / "out_db3"
    output.write_bytes(b"keep me")
    args = ("static", "0", "0", "0", "0", "0", "0", "base_link", "x", "-b", SAMPLE_BAGS["db3"], "-o", output)
    refused = tfx(*args)
    assert refused.code == 2 and "already exists" in refused.stderr and "--force" in refused.stderr
    assert output.read_bytes() == b"keep me"
    assert tfx(*args, "--force").code == 0
    assert read_recording([output]).buffer.has_frame("x")
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".tfx-static-")]


def test_ros1_copy_reads_in_the_real_rosbag(tfx: Tfx, tmp_path: Path, ros1_available: None) -> None:
    output = tmp_path / "out.bag"
    result = tfx("static", "1", "2", "3", "0", "0", "0", "base_link", "tool_y", "-b", SAMPLE_BAGS["ros1"], "-o", output)
    assert result.code == 0, result.stderr
    script = (
        "import json, rosbag, sys\n"
        "bag = rosbag.Bag(sys.argv[1])\n"
        "rows = [(h['callerid'].decode(), h.get('latching', b'').decode(), [(x.header.frame_id, x.child_frame_id,"
        " x.transform.translation.x) for x in m.transforms], t.to_nsec()) for _, m, t, h in"
        " bag.read_messages(topics=['/tf_static'], return_connection_header=True)]\n"
        "first = min(t.to_nsec() for _, _, t in bag.read_messages())\n"
        "print(json.dumps({'rows': rows, 'count': bag.get_message_count(), 'first': first}))\n"
    )
    read = subprocess.run([ROS_PYTHON, "-c", script, str(output)], capture_output=True, text=True, check=True)
    seen = json.loads(read.stdout)
    ours = [row for row in seen["rows"] if row[0] == "/tfx_static"]
    assert len(ours) == 1
    _callerid, latching, transforms, record_time = ours[0]
    assert latching == "1" and transforms == [["base_link", "tool_y", 1.0]]
    original = subprocess.run([ROS_PYTHON, "-c", script, str(SAMPLE_BAGS["ros1"])], capture_output=True, text=True)
    before = json.loads(original.stdout)
    assert seen["count"] == before["count"] + 1
    assert record_time == seen["first"] == before["first"] - 1  # just before the bag's first message


@pytest.mark.parametrize(
    ("rotation_flags", "expected"),
    [
        (["--qx", "0", "--qy", "0.6", "--qz", "0", "--qw", "0.8"], (0.0, 0.6, 0.0, 0.8)),
        (["--roll", "0.1", "--pitch", "0.2", "--yaw", "0.3"], Transform.from_rpy((0, 0, 0), (0.1, 0.2, 0.3)).rotation),
    ],
)
def test_ros2_flag_form_into_a_bag_copy(tfx: Tfx, tmp_path: Path, rotation_flags: list[str], expected: Quat) -> None:
    output = tmp_path / "out"
    args = ["--x", "1", "--y", "-2", "--z", "0.5", *rotation_flags, "--frame-id", "base_link", "--child-frame-id", "f"]
    result = tfx("static", *args, "-b", SAMPLE_BAGS["db3"], "-o", output)
    assert result.code == 0, result.stderr
    added = read_recording([output]).buffer.lookup("base_link", "f")
    assert added.translation == (1.0, -2.0, 0.5)
    np.testing.assert_allclose(added.rotation, expected, atol=1e-12)


@pytest.mark.parametrize("where", ["the bag", "its folder", "its metadata", "a folder of other files"])
def test_the_library_never_replaces_an_input_even_with_force(tmp_path: Path, where: str) -> None:
    """``add_static_transforms`` is callable from Python, past the CLI's checks: it refuses on its own."""
    import shutil

    from tftools.core.transform import Transform
    from tftools.sinks.static_bag import add_static_transforms
    from tftools.sources.errors import BagError

    bag = Path(
        shutil.copytree(Path(__file__).resolve().parents[2] / "sample_bags" / "robot_db3", tmp_path / "in" / "bag")
    )
    other = tmp_path / "notes"
    other.mkdir()
    (other / "todo.txt").write_text("keep me")
    target = {"the bag": bag, "its folder": bag.parent, "its metadata": bag / "metadata.yaml",
              "a folder of other files": other}[where]  # fmt: skip
    before = {p: p.read_bytes() for p in [*bag.iterdir(), other / "todo.txt"]}
    laser = Transform((0.1, 0.0, 0.2), (0.0, 0.0, 0.0, 1.0), 0, "base_link", "laser")
    with pytest.raises(BagError):
        add_static_transforms(bag, target, [laser], force=True)
    assert {p: p.read_bytes() for p in before} == before
