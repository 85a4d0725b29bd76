"""Live ``tfx static``: the real tf_echo and rospy hear it, latched, all transforms in one message."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.live.conftest import STATIC_PUBLISHER, Ros, read_line, tf_echo_block, wait_until


@pytest.mark.parametrize(
    "numbers",
    [
        ["0.1", "-0.2", "0.3", "1.2", "-0.4", "0.25"],  # x y z yaw pitch roll
        ["0.1", "-0.2", "0.3", "0.2", "-0.3", "0.1", "0.927"],  # x y z qx qy qz qw (normalized by both)
    ],
    ids=["rpy", "quaternion"],
)
def test_tf_echo_hears_tfx_static_as_it_hears_static_transform_publisher(ros: Ros, numbers: list[str]) -> None:
    form = "q" if len(numbers) == 7 else "r"
    ros.tfx("static", *numbers, f"ours_{form}", f"ours_{form}_child")
    ros.spawn(STATIC_PUBLISHER, *numbers, f"theirs_{form}", f"theirs_{form}_child")
    ours = tf_echo_block(ros, f"ours_{form}", f"ours_{form}_child")
    assert ours == tf_echo_block(ros, f"theirs_{form}", f"theirs_{form}_child")
    assert "Translation: [0.100, -0.200, 0.300]" in ours


def test_ros2_flag_form(ros: Ros) -> None:
    ros.tfx("static", "--x", "-1.5", "--yaw", "0.5", "--frame-id", "flag_parent", "--child-frame-id", "flag_child")
    ros.spawn(STATIC_PUBLISHER, "-1.5", "0", "0", "0.5", "0", "0", "ref_parent", "ref_child")
    assert tf_echo_block(ros, "flag_parent", "flag_child") == tf_echo_block(ros, "ref_parent", "ref_child")


def test_several_from_a_file_go_out_in_one_latched_message(ros: Ros, tmp_path: Path) -> None:
    extrinsics = tmp_path / "extrinsics.yaml"
    extrinsics.write_text(
        "transforms:\n"
        "  - {frame_id: file_base, child_frame_id: file_laser, x: 0.2, z: 0.1, yaw: 3.14159}\n"
        "  - {frame_id: file_base, child_frame_id: file_camera, translation: [0.1, 0, 0.3], rotation: [0, 0, 0, 1]}\n"
        "  - {frame_id: file_camera, child_frame_id: file_optical, roll: -1.5708, yaw: -1.5708}\n"
    )
    static = ros.tfx("static", "--from", str(extrinsics))
    read_line(static, "publishing file_base -> file_laser, file_base -> file_camera", timeout=20, stream="stderr")
    listener = ros.node("static_listener")  # connects after publishing began: latched
    (line,) = read_line(listener, "transforms", timeout=20)
    message = json.loads(line)
    assert message["callerid"].startswith("/tfx_static_") and message["latching"] == "1"
    assert [(t["frame_id"], t["child_frame_id"]) for t in message["transforms"]] == [
        ("file_base", "file_laser"),
        ("file_base", "file_camera"),
        ("file_camera", "file_optical"),
    ]
    assert message["transforms"][1]["translation"] == [0.1, 0.0, 0.3]
    chain = tf_echo_block(ros, "file_base", "file_optical")  # through two of them
    assert "Translation: [0.100, 0.000, 0.300]" in chain
    assert "in RPY (degree) [-90.000, -0.000, -90.000]" in chain


def test_stops_at_ctrl_c_and_unregisters(ros: Ros) -> None:
    static = ros.tfx("static", "0", "0", "1", "0", "0", "0", "int_a", "int_b")
    read_line(static, "until Ctrl-C", timeout=20, stream="stderr")
    ours = wait_until(lambda: _registered(ros, static.pid), 10, "tfx's registration")
    static.send_signal(2)  # SIGINT
    assert static.wait(10) == 0
    assert ours and not _registered(ros, static.pid)


def test_rosnode_kill_stops_it(ros: Ros) -> None:
    static = ros.tfx("static", "0", "0", "1", "0", "0", "0", "kill_a", "kill_b")
    read_line(static, "until Ctrl-C", timeout=20, stream="stderr")
    (node,) = wait_until(lambda: _registered(ros, static.pid), 10, "tfx's registration")
    killed = ros.run("rosnode", "kill", node)
    assert killed.returncode == 0, killed.stderr
    assert static.wait(10) == 0
    assert static.stderr is not None and "shut down by /rosnode" in static.stderr.read()
    assert not _registered(ros, static.pid)


def _registered(ros: Ros, pid: int) -> list[str]:
    """The /tf_static publishers the master lists for the tfx process ``pid``."""
    return [node for node in ros.master.publishers("/tf_static") if node.startswith(f"/tfx_static_{pid}_")]
