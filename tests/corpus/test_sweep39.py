"""Defects found by sweep39 (every command on every recording, read as a new user would), each on the recording
that showed it; the designed reproductions are beside the code's own tests."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.test_issue39 import BY_ID, Corpus, _findings

JETACKER_REAL = "ros2-jetacker-real-two-odometries-2026-db3"


def test_a_real_jetackers_two_joints_of_one_message_are_said_once(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """ros2_db3_jetacker_real_two_odometries: base_link -> link1 and link1 -> w_link come in one /tf message (a ROS 2
    bag names no node). wtf said two static_on_dynamic warnings (570 transforms each) and two time_backwards
    warnings (7 out of order each, at the same stamps): 4 warnings for 2 things. Now one of each, the other edge
    beneath it; the verdict is unchanged."""
    code, bag, findings = _findings(tfx, corpus(BY_ID[JETACKER_REAL]))
    for kind in ("static_on_dynamic", "time_backwards"):
        alike = [f for f in findings if f["code"] == kind]
        assert [f["frames"] for f in alike] == [["base_link", "link1"], ["link1", "w_link"]], alike
        assert alike[0]["cause"] == "" and alike[1]["cause"] == alike[0]["key"] != "", alike
    assert code == 1 and bag["verdict"] == "failed"
