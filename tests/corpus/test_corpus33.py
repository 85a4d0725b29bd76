"""What corpus33's recordings showed, fixed on the recording that showed it; the designed reproduction is beside
the code's own tests (tests/analysis/test_wtf_hazards.py). The Jarvis AGV's map under odom, whose jump hint corpus33
turned to "publish it as map -> odom", is rules46's now: the recording sends map -> odom already, and the steps are
its localizer's corrections (tests/corpus/test_rules46.py)."""

from __future__ import annotations

import json

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

GUARDIAN_DECEMBER = "ros1-robotnik-guardian-real-tilting-laser-pallet-robot-clock-7.6-s-ahead-no-callerid-2014-bag"
GUARDIAN_SEPTEMBER = "ros1-robotnik-guardian-real-lab-run-empty-tf-messages-rsp-post-dated-no-callerid-2014-bag"


def test_diff_of_one_robot_three_months_apart_says_how_far_its_mounts_on_tf_moved(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The Guardian of December and September 2014 sends its fixed joints on /tf at 50 Hz, never changing: base_link
    sits 111 mm higher in December, the front laser 40 mm to the side, the tracks turned 180 degrees; diff said only
    that the four wheels were lost, as it compared the values of /tf_static's edges only."""
    result = tfx("diff", corpus(BY_ID[GUARDIAN_DECEMBER]), corpus(BY_ID[GUARDIAN_SEPTEMBER]), "--format", "json")
    by_frame = {d["frame"]: d for d in json.loads(result.stdout)["differences"]}
    moved = {frame: (round(d["translation_mm"], 1), round(d["rotation_deg"], 1)) for frame, d in by_frame.items()}
    assert {f: m for f, m in moved.items() if by_frame[f]["change"] == "moved"} == {
        "base_link": (111.0, 0.0),
        "hokuyo_frontal_laser_link": (40.0, 0.0),
        "left_track": (0.0, 180.0),
        "right_track": (0.0, 180.0),
    }, by_frame
    assert {f for f, d in by_frame.items() if d["change"] == "lost"} == {
        "back_left_wheel",
        "back_right_wheel",
        "front_left_wheel",
        "front_right_wheel",
    }
    assert result.code == 1


SHIP_SIM = "ros1-gazebo-guardian-ship-interior-record-times-from-zero-ground-truth-repeated-stamps-no-callerid-2014-bag"


def test_a_ground_truth_repeating_its_stamp_2_to_24_times_is_one_publisher_not_twins(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The Guardian's Gazebo model: base_footprint -> map_ground_truth comes ~624 times a second on 1,616 stamps
    (one /tf connection, no callerid), 890 of them sent 2 to 24 times with other values. wtf said 'arrives twice
    ... two identical publishers, it seems' and no time_backwards; it is one publisher whose stamp does not advance,
    and ROS 1's tf2 drops the 11,354 repeats."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[SHIP_SIM]), "--format", "json").stdout)["bags"]
    said = {(f["code"], tuple(f["frames"][:2])): f for f in bag["findings"]}
    assert ("multiple_authorities", ("base_footprint", "map_ground_truth")) not in said, said.keys()
    repeated = said[("time_backwards", ("base_footprint", "map_ground_truth"))]
    assert "11354 transforms with a stamp it had already sent" in repeated["message"], repeated["message"]


def test_a_clock_ahead_and_rsp_s_fixed_joints_half_a_second_further_are_one_future(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The December Guardian's clock runs 7.6 s ahead of the recorder's; ROS 1's robot_state_publisher stamps the
    fixed joints it sends on /tf 0.5 s further (8.1 s). wtf said two future errors, 6 and 7 edges, for one clock
    (corpus33's note); now one, the 12 other edges beneath it, the verdict unchanged."""
    code, out = (r := tfx("wtf", corpus(BY_ID[GUARDIAN_DECEMBER]), "--format", "json")).code, r.stdout
    (bag,) = json.loads(out)["bags"]
    future = [f for f in bag["findings"] if f["code"] == "future"]
    (head,) = [f for f in future if not f["cause"]]
    assert head["frames"] == ["odom", "base_footprint"] and len(future) == 13, future
    assert all(f["cause"] == head["key"] for f in future if f is not head)
    assert {round(f["figures"]["ahead_s_median"], 1) for f in future} == {7.6, 8.1}
    assert code == 1 and bag["verdict"] == "failed"
