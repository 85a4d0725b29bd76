"""``tfx echo --format static|urdf|yaml``: lines to paste, which give back the same transform when fed back
(to ``tfx static``, to ROS 1's tf.transformations), and ``tfx static --deg``."""

from __future__ import annotations

import json
import math
import shlex
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tftools.core.transform import Transform

#: A chain of static edges only, and one through moving edges (looked up 3 s in).
LOOKUPS = [("base_link", "camera_optical_frame", []), ("map", "gripper", ["--at", "+3"])]


def _echoed(tfx: Tfx, bag: Path, parent: str, child: str, at: list[str]) -> Transform:
    result = tfx("echo", parent, child, "-b", bag, "--format", "json", *(at or ["--at", "0"]))
    record = json.loads(result.stdout)
    return Transform(tuple(record["translation"]), tuple(record["rotation"]))


def _pasted(tfx: Tfx, tmp_path: Path, parent: str, *args: str | Path) -> Transform:
    """``tfx static ARGS`` into a copy of the sample bag, then the transform it added, as tfx reads it."""
    out = tmp_path / f"pasted_{len(list(tmp_path.iterdir()))}.bag"
    made = tfx("static", *args, "-b", SAMPLE_BAGS["ros1"], "-o", out)
    assert made.code == 0, made.stderr
    return _echoed(tfx, out, parent, "pasted", [])


def _same(a: Transform, b: Transform, tolerance: float = 1e-12) -> None:
    assert np.allclose(a.translation, b.translation, rtol=0, atol=tolerance)
    sign = 1.0 if np.dot(a.rotation, b.rotation) >= 0 else -1.0
    assert np.allclose(a.rotation, sign * np.asarray(b.rotation), rtol=0, atol=tolerance)


def _within_ulps(printed: list[float], exact: list[float]) -> bool:
    """The printed numbers are the exact ones but for rounding noise: 2 units in the last place, or 1e-15."""
    return all(abs(p - e) <= max(2 * math.ulp(e), 1e-15) for p, e in zip(printed, exact, strict=True))


def test_rounding_noise_is_not_printed(tfx: Tfx, tmp_path: Path) -> None:
    """0.5 m along a frame turned by 90 degrees: tf2's arithmetic gives (1.1e-16, 0.4999999999999999) or
    the like; the lines to paste say 0.0 and 0.5."""
    turned, moved = tmp_path / "turned.bag", tmp_path / "moved.bag"
    made = tfx(
        "static", "0", "0", "0", repr(math.pi / 2), "0", "0", "world", "a", "-b", SAMPLE_BAGS["ros1"], "-o", turned
    )
    assert (
        made.code == 0 and tfx("static", "0.5", "0", "0", "0", "0", "0", "a", "b", "-b", turned, "-o", moved).code == 0
    )
    echoed = _echoed(tfx, moved, "world", "b", [])
    ros1 = tfx("echo", "world", "b", "-b", moved, "--format", "static").stdout.splitlines()[0].split()
    assert ros1[3:6] == ["0.0", "0.5", "0.0"] and _within_ulps([float(w) for w in ros1[3:10]], [
        *echoed.translation, *echoed.rotation])  # fmt: skip


@pytest.mark.parametrize("bag", list(SAMPLE_BAGS))
@pytest.mark.parametrize(("parent", "child", "at"), LOOKUPS)
def test_static_line_carries_the_exact_numbers_and_gives_back_the_transform(
    tfx: Tfx, tmp_path: Path, bag: str, parent: str, child: str, at: list[str]
) -> None:
    """One line, in the recording's own ROS: ROS 1's positional form for a .bag, ROS 2's flags for the others."""
    echoed = _echoed(tfx, SAMPLE_BAGS[bag], parent, child, at)
    result = tfx("echo", parent, child, "-b", SAMPLE_BAGS[bag], "--format", "static", *at)
    assert result.code == 0, result.stderr
    (line,) = result.stdout.splitlines()
    if bag == "ros1":
        words = shlex.split(line)
        assert words[:3] == ["rosrun", "tf2_ros", "static_transform_publisher"] and words[-2:] == [parent, child]
        assert _within_ulps([float(w) for w in words[3:10]], [*echoed.translation, *echoed.rotation])
        _same(_pasted(tfx, tmp_path, parent, *words[3:-1], "pasted"), echoed)
        return
    flags = shlex.split(line)
    assert flags[:3] == ["ros2", "run", "tf2_ros"] and flags[-4:] == ["--frame-id", parent, "--child-frame-id", child]
    values = dict(zip(flags[4:-4:2], flags[5:-4:2], strict=True))
    assert _within_ulps(
        [float(values[f"--{k}"]) for k in ("x", "y", "z", "qx", "qy", "qz", "qw")],
        [*echoed.translation, *echoed.rotation],
    )
    _same(_pasted(tfx, tmp_path, parent, *flags[4:-1], "pasted"), echoed)


@pytest.mark.parametrize(("bag", "tf2", "command"), [("ros1", "ros2", "ros2 run"), ("db3", "ros1", "rosrun")])
def test_static_line_follows_the_tf2_asked_for(tfx: Tfx, bag: str, tf2: str, command: str) -> None:
    """--tf2 answers as the other ROS: the line is that ROS's, as wtf's hints are."""
    bag_path = SAMPLE_BAGS[bag]
    result = tfx("echo", "base_link", "camera_optical_frame", "-b", bag_path, "--format", "static", "--tf2", tf2)
    assert result.code == 0, result.stderr
    (line,) = result.stdout.splitlines()
    assert line.startswith(f"{command} tf2_ros static_transform_publisher ")


@pytest.mark.parametrize(("parent", "child", "at"), LOOKUPS)
def test_yaml_entry_is_read_back_by_tfx_static_from(
    tfx: Tfx, tmp_path: Path, parent: str, child: str, at: list[str]
) -> None:
    bag = SAMPLE_BAGS["mcap"]
    result = tfx("echo", parent, child, "-b", bag, "--format", "yaml", *at)
    entry = tmp_path / "entry.yaml"
    entry.write_text(result.stdout.replace(f'"{child}"', '"pasted"'))
    _same(_pasted(tfx, tmp_path, parent, "--from", entry), _echoed(tfx, bag, parent, child, at))


@pytest.mark.parametrize(("parent", "child", "at"), LOOKUPS)
def test_urdf_origin_is_fixed_axis_roll_pitch_yaw(tfx: Tfx, parent: str, child: str, at: list[str]) -> None:
    bag = SAMPLE_BAGS["db3"]
    joint = ET.fromstring(tfx("echo", parent, child, "-b", bag, "--format", "urdf", *at).stdout)
    assert joint.get("type") == "fixed"
    named = joint.find("parent"), joint.find("child")
    assert named[0] is not None and named[1] is not None
    assert named[0].get("link") == parent and named[1].get("link") == child
    origin = joint.find("origin")
    assert origin is not None
    xyz = [float(v) for v in origin.get("xyz", "").split()]
    rpy = [float(v) for v in origin.get("rpy", "").split()]
    echoed = _echoed(tfx, bag, parent, child, at)
    assert _within_ulps(xyz, list(echoed.translation))
    _same(Transform.from_rpy(tuple(xyz), tuple(rpy)), echoed, 1e-9)  # type: ignore[arg-type]  # lists of 3


def test_urdf_origin_at_a_pitch_of_90_degrees_is_the_rotation(tfx: Tfx, tmp_path: Path) -> None:
    """A UR flange's (-0.5, -0.5, -0.5, 0.5): tf_echo's angles (0, -90, 0) are a rotation 90 degrees away; the
    joint pasted into a URDF must make the transform again."""
    added = _pasted(tfx, tmp_path, "base_link", "0", "0", "0", "-0.5", "-0.5", "-0.5", "0.5", "base_link", "pasted")
    joint = tfx("echo", "base_link", "pasted", "-b", tmp_path / "pasted_0.bag", "--format", "urdf").stdout
    found = ET.fromstring(joint).find("origin")
    assert found is not None
    rpy = [float(v) for v in found.get("rpy", "").split()]
    _same(Transform.from_rpy((0.0, 0.0, 0.0), (rpy[0], rpy[1], rpy[2])), added, 1e-9)


def test_urdf_rpy_is_what_ros_makes_of_it(tfx: Tfx, tf2_available: None) -> None:
    """ROS 1's own tf.transformations reads the rpy with static axes x, y, z, as URDF defines it."""
    bag = SAMPLE_BAGS["ros1"]
    origin = ET.fromstring(tfx("echo", "map", "gripper", "-b", bag, "--format", "urdf", "--at", "+3").stdout).find(
        "origin"
    )
    assert origin is not None
    roll, pitch, yaw = (float(v) for v in origin.get("rpy", "").split())
    code = f"import tf.transformations as t; print(list(t.quaternion_from_euler({roll!r}, {pitch!r}, {yaw!r}, 'sxyz')))"
    ros = json.loads(
        subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True, check=True).stdout
    )
    echoed = _echoed(tfx, bag, "map", "gripper", ["--at", "+3"])
    _same(Transform(echoed.translation, tuple(ros)), echoed, 1e-9)


def test_paste_formats_escape_names_for_their_language(tfx: Tfx, tmp_path: Path) -> None:
    out = tmp_path / "odd.bag"
    assert (
        tfx(
            "static",
            "0",
            "0",
            "1",
            "0",
            "0",
            "0",
            "base_link",
            'it\'s <a> "frame"',
            "-b",
            SAMPLE_BAGS["ros1"],
            "-o",
            out,
        ).code
        == 0
    )
    odd = 'it\'s <a> "frame"'
    static = tfx("echo", "base_link", odd, "-b", out, "--format", "static").stdout.splitlines()[0]
    assert shlex.split(static)[-1] == odd
    urdf_child = ET.fromstring(tfx("echo", "base_link", odd, "-b", out, "--format", "urdf").stdout).find("child")
    assert urdf_child is not None and urdf_child.get("link") == odd
    entry = tmp_path / "odd.yaml"
    entry.write_text(tfx("echo", "base_link", odd, "-b", out, "--format", "yaml").stdout)
    from tftools.sources.live.static_file import read_static_transforms

    assert read_static_transforms(entry)[0].child_frame_id == odd


def test_static_deg_takes_degrees_in_both_forms(tfx: Tfx, tmp_path: Path) -> None:
    radians = _pasted(
        tfx, tmp_path, "base_link", "0.1", "0", "0.2", str(math.pi / 2), "0", "-0.3", "base_link", "pasted"
    )
    degrees = _pasted(
        tfx,
        tmp_path,
        "base_link",
        "0.1",
        "0",
        "0.2",
        "90",
        "0",
        str(math.degrees(-0.3)),
        "base_link",
        "pasted",
        "--deg",
    )
    _same(degrees, radians)
    flags = ["--x", "0.1", "--z", "0.2", "--yaw", "90", "--roll", str(math.degrees(-0.3)), "--deg"]
    _same(_pasted(tfx, tmp_path, "base_link", *flags, "--frame-id", "base_link", "--child-frame-id", "pasted"), radians)
    quaternion = tfx("static", "0", "0", "0", "0", "0", "0", "1", "a", "b", "--deg")
    assert quaternion.code == 2 and "--deg is for yaw, pitch and roll" in quaternion.stderr
