"""rules48: issue 39's leftovers on the real recordings that show them (a JSON robot description, the words of
two message layouts, ROS 2's repeated stamps); the designed reproductions are beside the code's own tests."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_issue39 import _findings

FRANKA_JSON = "json-mcap-franka-teleop-2025"


def test_a_json_robot_description_is_read_and_its_absent_publisher_said_once(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Franka teleop's MCAP logs /robot_description (std_msgs/msg/String in JSON, at log time 0: a URDF of 14 joints,
    9 moving) and JSON /joint_states naming the 9; tf carries only world -> base -> fr3_link0. tfx did not read the
    description (no URDF check ran); read, it said 11 urdf_missing errors, one per joint, and urdf_kind for the two
    fixed joints mixed_static names. One urdf_missing now, the urdf_kind warnings beneath mixed_static."""
    code, bag, findings = _findings(tfx, corpus(BY_ID[FRANKA_JSON]))
    (missing,) = [f for f in findings if f["code"] == "urdf_missing"]
    assert missing["cause"] == "" and missing["severity"] == "error", missing
    said = missing["message"]
    assert "none of the 9 moving joints of the recorded /robot_description is on tf" in said, said
    assert "/joint_states names each" in said and "tf carries only world_to_base and fr3_base_joint" in said, said
    assert "12 are missing" in said and "fr3_joint1 (fr3_link1)" in said, said
    assert "robot_state_publisher did not run" in missing["hint"] and "ros2 launch" in missing["hint"]
    kinds = [f for f in findings if f["code"] == "urdf_kind"]
    assert len(kinds) == 2 and all(f["cause"].startswith("mixed_static") for f in kinds), kinds
    assert code == 1 and bag["summary"]["errors"] == 2, bag["summary"]
