"""rules48: issue 39's leftovers on the real recordings that show them (a JSON robot description, the words of
two message layouts, ROS 2's repeated stamps); the designed reproductions are beside the code's own tests."""

from __future__ import annotations

import pytest

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


TURTLEBOT4_WHEELS = "ros2-turtlebot4-ignition-gazebo-wheels-from-two-publishers-five-static-senders-sim-clock-2025-db3"
TURTLEBOT4_PAUSED = (
    "ros2-turtlebot4-ignition-gazebo-simulation-paused-at-end-tf-fresh-on-sim-time-wheels-from-two-publishers-2025-db3"
)


@pytest.mark.parametrize(
    ("recording_id", "messages", "both"), [(TURTLEBOT4_WHEELS, 117, 10), (TURTLEBOT4_PAUSED, 94, 15)]
)
def test_turtlebot4s_kind_of_message_whose_wheels_stay_at_zero_says_so(
    recording_id: str,
    messages: int,
    both: int,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Both TurtleBot 4 runs: one kind of message (4 transforms) holds the wheels always at the identity. wtf said
    'their values always the same' right after listing both kinds, as if of both; it now says which edges never
    change and where they stay, in that kind's own clause. At the stamps both kinds sent, it says what ROS 2's tf2
    does (cache.cpp insertData: keeps both, the last received answering), where the manifest had said it drops
    them with TF_REPEATED_DATA, a ROS 1 log ROS 2's tf2 does not have."""
    _, _, findings = _findings(tfx, corpus(BY_ID[recording_id]))
    (authorities,) = [f for f in findings if f["code"] == "multiple_authorities"]
    said = authorities["message"]
    assert (
        f"{messages} messages of 4 transforms (with base_link -> wheel_drop_left and base_link -> wheel_drop_right), "
        "every 99.0 ms, in which wheel_drop_left -> left_wheel and wheel_drop_right -> right_wheel never change, each "
        "always at 0.0 mm and 0.00° from its parent (the identity);"
    ) in said, said
    assert "their values always the same" not in said
    assert f"{both} stamps of each came in both, with other values up to" in said
    assert "ROS 2's tf2 keeps both: at that stamp it answers with the one received last" in said
    assert "TF_REPEATED_DATA" not in said and "TF_REPEATED_DATA" not in authorities["hint"]
    why = BY_ID[TURTLEBOT4_WHEELS].meta["why"]
    assert "drops the 10 stamps sent twice" not in why and "ROS 2's tf2 keeps both" in why
