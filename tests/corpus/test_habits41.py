"""A ROS engineer's habits and issue 39's leftovers (left41), each on the real recording that showed it.

Each test skips while its recording awaits placement in the shared corpus, as the rest of the corpus tests do."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

LISTENER = "beginner-tutorials-constant-world-2019-bag"


def test_filter_of_named_topics_does_not_suggest_the_command_just_run(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Arjung27's beginner_tutorials listener bag holds /chatter (std_msgs/String), /rosout, /rosout_agg and /tf:
    ``tfx filter /scan`` (not there), ``/chatter`` (no header) and ``/rosout`` (a header without a frame_id)
    each answered 'e.g. tfx filter /scan -b BAG', /scan's the very command run. Each says what it is, and that
    naming none checks every topic with a Header."""
    path = corpus(BY_ID[LISTENER])
    for topic, why in (
        ("/scan", "/scan: not in the recording"),
        ("/chatter", "/chatter: std_msgs/String messages have no header"),
        ("/rosout", "only /rosout, whose header has no frame_id"),
    ):
        said = tfx("filter", topic, "-b", path)
        assert said.code == 2 and not said.stdout and len(said.stderr.strip().splitlines()) == 1, said.stderr
        assert why in said.stderr and "e.g. tfx filter" not in said.stderr, said.stderr
        assert "or none: tfx filter -b BAG checks every such topic" in said.stderr, said.stderr


EVO = "evo-tf-example-bag"
LEADING_SLASH = "ros2-turtlebot3-gazebo-leading-slash-2025-db3"
WEEK11 = "ros1-stage-three-robots-one-never-joined-leading-slashes-pfms-2024-bag"


def test_echo_takes_tf_echo_s_rate_after_the_frames_and_refuses_node_arguments(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """evo's tf example bag (odom -> base_footprint at 10 Hz): ``tfx echo odom base_link 2`` as tf_echo takes its
    echo_rate was 'Got unexpected extra argument(s) (2)'; it prints what --rate 2 does. ``_precision:=5`` (rosrun's
    private parameter) and ``--ros-args -p use_sim_time:=true`` (ros2 run's) were an extra argument and 'No such
    option': each is refused with the command line in tfx's options."""
    path = corpus(BY_ID[EVO])
    third = tfx("echo", "odom", "base_link", "2", "-b", path, "--end", "+2")
    assert (
        third.code == 0
        and third.stdout == tfx("echo", "odom", "base_link", "-b", path, "--end", "+2", "-r", "2").stdout
    )
    assert third.stdout.count("At time ") == 5  # 1714741164.178 to .178 + 2 s, every 0.5 s
    for given, fixed in (
        (["_precision:=5"], "--precision 5"),
        (["--ros-args", "-p", "use_sim_time:=true"], "--use-sim-time"),
    ):
        said = tfx("echo", "odom", "base_link", "-b", path, *given)
        assert said.code == 2 and f"in tfx's options: tfx echo odom base_link -b {path} {fixed})" in said.stderr


def test_slashed_frames_are_looked_up_without_it_and_said_so_on_ros2_data(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The UJI TurtleBot3 (ROS 2) whose robot_state_publisher names its frames '/base_link' ...: ``tfx echo /odom
    /base_scan`` answered as ``odom base_scan`` without a word, where ROS 2's tf2_echo is refused ('in tf2 frame_ids
    cannot start with a /') and so is any ROS 2 node asking so: a hint says it. PFMS week 11's Stage bag (ROS 1,
    frames named '/robot_0/odom'): ROS 1's tf_echo drops the slash, and tfx does so without a word."""
    path = corpus(BY_ID[LEADING_SLASH])
    slashed, plain = (
        tfx("echo", *frames, "-b", path, "--at", "+5") for frames in (["/odom", "/base_scan"], ["odom", "base_scan"])
    )
    assert slashed.code == plain.code == 0 and slashed.stdout == plain.stdout and not plain.stderr
    assert slashed.stderr == (
        "hint: /odom, /base_scan looked up as odom, base_scan, as ROS 1's tf_echo does: ROS 2's tf2 refuses a frame "
        "id that starts with '/' (\"in tf2 frame_ids cannot start with a '/'\"), so a ROS 2 node asks for odom and "
        "base_scan\n"
    )
    ros1 = tfx("echo", "/world", "/robot_0/odom", "-b", corpus(BY_ID[WEEK11]), "--at", "+1")
    assert ros1.code == 0 and "At time" in ros1.stdout and not ros1.stderr


def test_view_frames_output_named_as_ros2_s_view_frames_names_it(corpus: Corpus, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """``view_frames -o NAME`` (ROS 2) writes NAME.pdf: on evo's tf example bag, tfx view-frames -o NAME wrote a
    PDF called NAME; it writes NAME.pdf, the bag's 3 frames in it."""
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    result = tfx("view-frames", "-b", corpus(BY_ID[EVO]), "-o", tmp_path / "evo_frames")
    assert result.code == 0 and f"wrote {tmp_path / 'evo_frames.pdf'}: 3 frames, 2 transforms" in result.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["evo_frames.pdf"]
