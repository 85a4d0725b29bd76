"""``--urdf`` on the command line: ``tfx wtf`` naming the joint, its link and the cause; ``tfx report`` with
the same findings; ``tfx diff robot.urdf run.bag``; and a URDF that cannot be used (xacro, missing, not
XML) as one line and exit 2, nothing written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.analysis.robot_scenes import MOVED, URDF, Setup, robot_bag, urdf_file
from tests.cli.conftest import Tfx
from tests.cli.test_bad_input import check_stderr


def test_wtf_names_the_joint_the_link_and_the_cause(tfx: Tfx, tmp_path: Path) -> None:
    bag = robot_bag(tmp_path, "rover", Setup(joint_states=("wheel_left_joint",), real_origins={"laser_joint": MOVED}))
    result = tfx("wtf", bag, "--urdf", urdf_file(tmp_path))
    assert result.code == 1, result.stderr
    out = result.stdout
    assert "urdf_missing: joint wheel_right_joint (continuous, base_link -> wheel_right_link) of" in out
    assert "no message on /joint_states names wheel_right_joint" in out
    assert "urdf_moved: joint laser_joint (fixed, base_link -> laser): tf puts laser 20.0 mm and 0.00°" in out
    assert "2 errors, 0 warnings, 1 note: FAILED" in out


def test_wtf_on_a_healthy_robot_passes(tfx: Tfx, tmp_path: Path) -> None:
    bag = robot_bag(tmp_path, "rover", Setup())
    result = tfx("wtf", bag, "--urdf", urdf_file(tmp_path), "--format", "json")
    assert result.code == 0, result.stderr
    (report,) = json.loads(result.stdout)["bags"]
    assert [(f["code"], f["severity"]) for f in report["findings"]] == [("urdf_extra", "info")]


def test_report_shows_the_findings_and_the_frames(tfx: Tfx, tmp_path: Path) -> None:
    bag = robot_bag(tmp_path, "rover", Setup(state_publisher=False, description=True))
    page = tmp_path / "report.html"
    result = tfx("report", "-b", bag, "-o", page)  # the recorded description
    assert result.code == 1 and result.stderr == f"wrote {page}: 1 error, 1 note\n"
    text = page.read_text()
    assert "urdf_missing" in text and "robot_state_publisher did not run" in text and "Frames in 3D" in text


def test_diff_against_a_urdf(tfx: Tfx, tmp_path: Path) -> None:
    bag = robot_bag(tmp_path, "rover", Setup(real_origins={"laser_joint": MOVED}))
    result = tfx("diff", urdf_file(tmp_path), bag, "--format", "json")
    assert result.code == 1, result.stderr
    changes = [(d["change"], d["frame"]) for d in json.loads(result.stdout)["differences"]]
    assert changes == [("moved", "laser")]  # odom above the robot, the wheels' rates: no difference from a URDF
    reverse = tfx("diff", bag, tmp_path / "rover.urdf", "--format", "json")
    assert [(d["change"], d["frame"]) for d in json.loads(reverse.stdout)["differences"]] == changes
    healthy = robot_bag(tmp_path, "healthy", Setup())
    assert tfx("diff", tmp_path / "rover.urdf", healthy).code == 0


@pytest.mark.parametrize(
    ("name", "text", "said"),
    [
        ("robot.urdf.xacro", URDF, "is xacro, which tfx does not expand"),
        ("robot.urdf", '<robot xmlns:xacro="http://ros.org/wiki/xacro"><xacro:macro name="m"/></robot>', "is xacro"),
        ("robot.urdf", "<robot", "not well-formed XML"),
        ("robot.urdf", None, "no such file"),
    ],
)
@pytest.mark.parametrize("command", ["wtf", "report", "diff"])
def test_a_urdf_that_cannot_be_used(
    tfx: Tfx, tmp_path: Path, name: str, text: str | None, said: str, command: str
) -> None:
    bag = robot_bag(tmp_path, "rover", Setup())
    urdf = tmp_path / name
    if text is not None:
        urdf.write_text(text)
    args = {
        "wtf": ("wtf", bag, "--urdf", urdf),
        "report": ("report", "-b", bag, "--urdf", urdf, "-o", tmp_path / "out.html"),
        "diff": ("diff", urdf, bag),
    }[command]
    before = sorted(tmp_path.iterdir())
    result = tfx(*args)
    assert result.code == 2 and result.stdout == ""
    check_stderr(result.stderr, result.code)
    assert said in result.stderr
    assert sorted(tmp_path.iterdir()) == before


def test_the_tolerances_apply_to_the_urdf(tfx: Tfx, tmp_path: Path) -> None:
    bag = robot_bag(tmp_path, "rover", Setup(real_origins={"laser_joint": MOVED}))  # 20 mm off
    urdf = urdf_file(tmp_path)
    assert "urdf_moved" in tfx("wtf", bag, "--urdf", urdf, "--tolerance-mm", "19").stdout
    loose = tfx("wtf", bag, "--urdf", urdf, "--tolerance-mm", "21")
    assert loose.code == 0 and "urdf_moved" not in loose.stdout
