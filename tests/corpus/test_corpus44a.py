"""What corpus44a's recording showed (a real Robotnik Guardian under a navigation controller, in the test data of
dynamic_robot_localization, 2014), fixed on the recording that showed it; the designed reproduction is beside the
code's own tests (tests/analysis/test_wtf_clocks_and_words.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

GOALS_IN_MAP = (
    "ros1-robotnik-guardian-real-navigation-controller-goals-in-map-no-localization-recorded-no-callerid-2014-bag"
)


def test_goals_in_map_without_localization_are_told_map_to_odom_not_mounts(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/pose_goal's 2 goals are in 'map'; the bag holds no map -> odom and no /tf_static. wtf's hint said the
    sensors' mounts were not recorded (record /tf_static), while `tfx filter` named the missing localization."""
    path = corpus(BY_ID[GOALS_IN_MAP])
    code, findings = _findings(tfx, path)
    (frame,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert frame["severity"] == "error" and frame["frames"] == ["map"], frame
    assert frame["message"] == "/pose_goal: 2 of 2 messages are in frame 'map', which no transform names"
    assert "'map' is localization's frame (REP 105)" in frame["hint"] and "map -> odom" in frame["hint"]
    assert "mounts" not in frame["hint"] and "/tf_static" not in frame["hint"], frame["hint"]
    assert code == 1
    said = " ".join(tfx("filter", "-b", path).stdout.split())
    assert "'map' is localization's frame (REP 105)" in said, said
