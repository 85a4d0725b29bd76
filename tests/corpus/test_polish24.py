"""What corpus24's recordings showed, fixed by polish24, each on the recording that showed it; the designed
reproductions are beside the code's own tests."""

from __future__ import annotations

import html
import json
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

#: Bag directories whose file was renamed after recording (metadata.yaml lists the old name), opened by their file.
RENAMED = [
    "ros2-turtlebot3-gazebo-circle-iron-metadata-names-another-file-2024-mcap",
    "ros2-robotino-gazebo-holonomic-square-no-clock-iron-2024-mcap",
    "ros2-neato-gazebo-person-follower-renamed-db3-2023",
]
STAGE = "ros1-stage-three-robots-one-never-joined-leading-slashes-pfms-2024-bag"


@pytest.mark.parametrize("recording", RENAMED)
def test_static_takes_the_file_its_directory_s_error_names(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
    recording: str,
) -> None:
    """`tfx static -b DIR` said "give tfx that file (.../circle.mcap)", and `-b .../circle.mcap` then said "is a file of
    the ROS 2 bag (give the bag's directory)": a loop. A file metadata.yaml does not list is a recording of its own."""
    file = corpus(BY_ID[recording])
    refused = tfx("static", "--repair", "-b", file.parent, "-o", tmp_path / "from_dir")
    assert refused.code != 0 and f"give tfx that file ({file})" in refused.stderr, refused
    output = tmp_path / f"out{file.suffix}"
    added = tfx("static", "0", "0", "1", "0", "0", "0", "base_link", "polish24_tool", "-b", file, "-o", output)
    assert added.code == 0 and "1 static transform added" in added.stdout, added
    assert "is a file of the ROS 2 bag" not in added.stderr


def test_a_robot_s_tree_apart_lacks_its_transform_to_world_not_a_letter(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """Three robots in Stage: robot_2's tree (odom -> base_footprint -> base_link -> base_laser_link) is robot_0's and
    robot_1's under 'robot_2/', and world -> robot_2/odom is never sent (/robot_0_tf and /robot_1_tf send theirs).
    wtf, echo and view-frames called 'robot_2/odom' a misspelling of 'robot_1/odom'."""
    path = corpus(BY_ID[STAGE])
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    (finding,) = [f for f in bag["findings"] if f["code"] == "disconnected"]
    said = "robot_2/odom's tree has the same frames as robot_0's and robot_1's under 'robot_2/'"
    joined = "joined to the rest by world -> robot_0/odom and world -> robot_1/odom: publish world -> robot_2/odom"
    echoed = tfx("echo", "world", "robot_2/base_link", "-b", path).stderr
    tfx("view-frames", "-b", path, "-o", tmp_path / "frames.svg")
    drawn = html.unescape((tmp_path / "frames.svg").read_text())
    for text in (finding["hint"], echoed, drawn):
        assert said in text and joined in text and "misspelling" not in text


DRONE = "ros2-gazebo-drone-beside-ackermann-car-two-static-publishers-pfms-2024-db3"


@pytest.mark.parametrize(
    ("recording", "code", "said", "summary"),
    [
        (STAGE, "static_on_dynamic", 2, "3 warnings (explaining 5 more)"),
        (DRONE, "urdf_extra", 2, "4 notes (explaining 9 more)"),
    ],
)
def test_one_cause_is_one_finding_with_what_follows_beneath(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    recording: str,
    code: str,
    said: int,
    summary: str,
) -> None:
    """Stage: stageros' 6 constant mounts on /tf were 6 warnings beside /local_map's (every robot at rest; the mounts
    are constant by Stage's make, so the finding holds), now one for stageros with 5 beneath. The drone beside a
    car: the car's 10 frames the drone's URDF lacks were 10 notes beside 'world', now one at orange/base_footprint
    with 9 beneath. The summary line and JSON count causes."""
    path = corpus(BY_ID[recording])
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    mine = [f for f in bag["findings"] if f["code"] == code]
    assert sum(not f.get("cause") for f in mine) == said and all(f.get("cause") for f in mine[said:])
    assert summary in tfx("wtf", path).stdout


def test_monitor_says_the_clock_s_step_and_rate_on_their_own_axes(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The TurtleBot 3 circle MCAP: /clock's 336 ticks step a median 0.095 s of sim time (31.7 s of it) over 34.1 s of
    record time, 9.8 ticks a second by ``rate_hz``: monitor said "ticks every 0.095 s (11 Hz)", the step as a rate."""
    path = corpus(BY_ID[RENAMED[0]])
    said = json.loads(tfx("monitor", "-b", path, "-f", "json").stdout)["delays_unavailable"]
    assert "/clock, which ticks every 0.095 s of sim time (9.8 Hz of record time)" in said, said
