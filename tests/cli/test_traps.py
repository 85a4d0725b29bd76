"""The small traps a new user falls into, each met with a way through: a folder of bags without its final
slash, a bag given without -b, the same bag twice, a ROS 2 bag's file or a bare MCAP file to ``tfx static``,
and a static transform the bag already has."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS, SAMPLES, Tfx, tfx
from tftools.sources.recording import read_recording

__all__ = ["tfx"]  # a fixture, for pytest


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A folder of the three sample recordings (and their generator, which is not one)."""
    bags = tmp_path / "bags"
    shutil.copytree(SAMPLES, bags)
    return bags


@pytest.mark.parametrize("slash", ["", "/"], ids=["no slash", "slash"])
@pytest.mark.parametrize("command", ["wtf", "report"])
def test_a_folder_of_bags_is_each_of_them(tfx: Tfx, folder: Path, tmp_path: Path, command: str, slash: str) -> None:
    output = ("-o", tmp_path / "fleet.html") if command == "report" else ()
    result = tfx(command, f"{folder}{slash}", *output)
    assert result.code == 0, result.stderr
    if command == "wtf":
        assert "3 recordings checked: 3 passed" in result.stdout
    else:
        assert "0 of 3 failed" in result.stderr


@pytest.mark.parametrize("slash", ["", "/"], ids=["no slash", "slash"])
def test_a_folder_of_bags_after_b_says_what_to_give(tfx: Tfx, folder: Path, slash: str) -> None:
    result = tfx("frames", "-b", f"{folder}{slash}")
    assert result.code == 2 and result.stderr.count("\n") == 1
    assert f"-b {folder}{slash} is a folder of 3 recordings, not a bag" in result.stderr
    assert f"e.g. -b {folder}/robot.bag" in result.stderr and f"tfx wtf {folder}/ checks each" in result.stderr


@pytest.mark.parametrize(
    "args",
    [
        ["frames", "BAG"],
        ["echo", "map", "odom", "BAG"],
        ["echo", "BAG", "map", "odom"],
        ["monitor", "BAG"],
        ["filter", "BAG"],
    ],
    ids=lambda a: "-".join(a),
)
def test_one_bag_without_b_is_read_as_with_it(tfx: Tfx, args: list[str]) -> None:
    """``tfx frames robot.bag`` as ``tfx wtf robot.bag`` takes it (a new user's first try, round 49's trial): read,
    not refused with the command line it stands for; echo and monitor would otherwise listen to a live system."""
    bag = str(SAMPLE_BAGS["ros1"])
    given = tfx(*[bag if a == "BAG" else a for a in args])
    with_b = tfx(*[w for a in args for w in (["-b", bag] if a == "BAG" else [a])])
    assert given.code == with_b.code == 0, given.stderr
    assert given.stdout == with_b.stdout and given.stdout


def test_bags_without_b_are_shown_each_on_its_own_too(tfx: Tfx) -> None:
    """``tfx filter logs/*.bag`` (as ``tfx wtf`` takes a fleet): the fix shown was every bag after -b, which reads
    them as the parts of one split recording; it says so, and shows each checked on its own."""
    first, second = str(SAMPLE_BAGS["ros1"]), str(SAMPLE_BAGS["mcap"])
    result = tfx("filter", first, second)
    assert result.code == 2 and result.stderr.count("\n") == 1
    assert f"tfx filter -b {first} -b {second} (the parts of one recording)" in result.stderr
    assert f'each on its own: for b in {first} {second}; do tfx filter -b "$b"; done' in result.stderr


def test_an_extra_argument_that_is_no_bag_points_to_help(tfx: Tfx) -> None:
    result = tfx("frames", "nothing_here")
    assert result.code == 2 and "see tfx frames --help" in result.stderr and "-b" not in result.stderr


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
def test_the_same_bag_twice_is_read_once(tfx: Tfx, fmt: str) -> None:
    bag = SAMPLE_BAGS[fmt]
    once = tfx("wtf", "-b", bag)
    twice = tfx("wtf", "-b", bag, "-b", f"{bag.parent}/./{bag.name}")
    assert twice.code == once.code == 0
    assert twice.stdout == once.stdout
    assert twice.stderr.startswith("tfx: warning: ") and "is given twice" in twice.stderr
    assert twice.stderr.count("\n") == 1


def test_a_rosbag2_file_and_its_directory_are_one_bag(tfx: Tfx) -> None:
    folder = SAMPLE_BAGS["db3"]
    result = tfx("frames", "-b", folder, "-b", folder / "robot_db3.db3", "-f", "json")
    assert result.code == 0 and "given twice (as" in result.stderr


def test_the_same_bag_twice_as_arguments_is_checked_once(tfx: Tfx) -> None:
    bag = SAMPLE_BAGS["ros1"]
    result = tfx("wtf", bag, bag)
    assert result.code == 0 and "given twice" in result.stderr
    assert "recordings checked" not in result.stdout  # one recording: no fleet summary


def test_static_on_a_file_of_a_rosbag2_directory_names_the_directory(tfx: Tfx, tmp_path: Path) -> None:
    bag = SAMPLE_BAGS["mcap"] / "robot_mcap.mcap"
    result = tfx("static", "0", "0", "1", "0", "0", "0", "base_link", "tool", "-b", bag, "-o", tmp_path / "out")
    assert result.code == 2 and result.stderr.count("\n") == 1
    assert "not an MCAP file" not in result.stderr
    assert f"is a file of the ROS 2 bag {SAMPLE_BAGS['mcap']}" in result.stderr
    assert f"-b {SAMPLE_BAGS['mcap']} -o OUTPUT" in result.stderr
    assert not (tmp_path / "out").exists()


def test_static_on_a_file_its_metadata_yaml_does_not_list_copies_it(tfx: Tfx, tmp_path: Path) -> None:
    """A bag directory whose file was renamed after recording (circle_0.mcap to circle.mcap, metadata.yaml unchanged):
    the directory's error says "give tfx that file", so static takes the file, as every command does."""
    bag = tmp_path / "renamed"
    shutil.copytree(SAMPLE_BAGS["mcap"], bag)
    (bag / "robot_mcap.mcap").rename(bag / "renamed.mcap")
    refused = tfx("static", "--repair", "-b", bag, "-o", tmp_path / "dir_out")
    assert refused.code != 0 and f"give tfx that file ({bag / 'renamed.mcap'})" in refused.stderr, refused
    args = ("0", "0", "1", "0", "0", "0", "base_link", "tool", "-b", bag / "renamed.mcap", "-o", tmp_path / "out.mcap")
    result = tfx("static", *args)
    assert result.code == 0 and "1 static transform added" in result.stdout, result
    assert read_recording([tmp_path / "out.mcap"]).buffer.lookup("base_link", "tool").translation == (0.0, 0.0, 1.0)


def test_static_on_a_bare_mcap_file_copies_it_to_a_bare_mcap_file(tfx: Tfx, tmp_path: Path) -> None:
    bare = tmp_path / "bare.mcap"
    shutil.copy(SAMPLE_BAGS["mcap"] / "robot_mcap.mcap", bare)
    result = tfx("static", "0", "0", "1", "0", "0", "0", "base_link", "tool", "-b", bare, "-o", tmp_path / "out.mcap")
    assert result.code == 0 and "1 static transform added" in result.stdout, result
    copy = read_recording([tmp_path / "out.mcap"])
    assert copy.buffer.lookup("base_link", "tool").translation == (0.0, 0.0, 1.0)


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
@pytest.mark.parametrize("edge", [("base_link", "laser"), ("map", "laser"), ("odom", "base_footprint")])
def test_static_refuses_a_frame_the_bag_already_has(tfx: Tfx, tmp_path: Path, fmt: str, edge: tuple[str, str]) -> None:
    output = tmp_path / "out"
    result = tfx("static", "0", "0", "1", "0", "0", "0", *edge, "-b", SAMPLE_BAGS[fmt], "-o", output)
    assert result.code == 2 and result.stderr.count("\n") == 1
    assert f"already has {edge[1]}," in result.stderr and "tfx wtf would fail the copy" in result.stderr
    assert not output.exists()


def test_static_adds_a_new_frame_and_wtf_passes_the_copy(tfx: Tfx, tmp_path: Path) -> None:
    output = tmp_path / "out.bag"
    result = tfx("static", "0", "0", "1", "0", "0", "0", "base_link", "tool", "-b", SAMPLE_BAGS["ros1"], "-o", output)
    assert result.code == 0, result.stderr
    assert tfx("wtf", output).code == 0


@pytest.mark.parametrize(
    ("angles", "extra", "warned"),
    [
        (["90", "0", "0"], [], "yaw 90 taken in radians"),
        (["0", "0", "-180"], [], "roll -180"),
        (["90", "0", "0"], ["--deg"], ""),
    ],
)
def test_an_angle_past_a_whole_turn_is_taken_in_radians_with_a_hint(
    tfx: Tfx, tmp_path: Path, angles: list[str], extra: list[str], warned: str
) -> None:
    """ROS's rule is radians, so yaw 90 is 90 rad, as static_transform_publisher takes it; but it was almost
    surely meant in degrees: said once, with --deg."""
    out = tmp_path / "copy.bag"
    result = tfx(
        "static", "0.1", "0", "0.2", *angles, "base_link", "sonar", *extra, "-b", SAMPLE_BAGS["ros1"], "-o", out
    )
    assert result.code == 0, result
    if warned:
        assert warned in result.stderr and "add --deg if you meant degrees" in result.stderr
    else:
        assert "radians" not in result.stderr
