"""The library's errors name no option; the command line words each with the option it came from, on one line,
with exit code 2 (``tftools.cli.errors.table``)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from tests.bags import TfMessage, write_bag
from tests.cli.conftest import SAMPLE_BAGS, Result, Tfx
from tftools.analysis.fleet import Fleet, run_fleet, scheduler_address
from tftools.cli.errors import UsageError, table, worded
from tftools.core.errors import (
    FleetUnavailableError,
    InvalidTransformError,
    TfToolsError,
    TransformError,
    UnknownFrameError,
)
from tftools.core.frames import known_frame
from tftools.core.transform import Transform
from tftools.sinks.static import StaticQuery, checked, copy_with_statics, copyable
from tftools.sources.errors import NoStampedDataError, PartOfBagError

BAG = str(SAMPLE_BAGS["ros1"])
DB3 = SAMPLE_BAGS["db3"] / "robot_db3.db3"


def one_error_line(result: Result) -> str:
    """The command's one line on stderr, which must be an error with exit code 2 and nothing on stdout."""
    assert result.code == 2 and result.stdout == "" and result.stderr.count("\n") == 1, result
    assert result.stderr.startswith("tfx: error: ")
    return result.stderr


def said_by_library(error: TfToolsError) -> str:
    return f"{error} {error.hint}"


def test_an_address_that_is_no_scheduler_is_the_librarys_fact_and_the_dask_options_words(tfx: Tfx) -> None:
    with pytest.raises(FleetUnavailableError) as raised:
        scheduler_address("nonsense")
    assert raised.value.address == "nonsense" and "--" not in said_by_library(raised.value)
    line = one_error_line(tfx("wtf", BAG, "--dask", "nonsense"))
    assert line.startswith("tfx: error: --dask nonsense: not a scheduler address (scheme://host:port")
    assert "e.g. --dask tcp://127.0.0.1:8786" in line


def test_dask_not_installed_is_said_without_the_option_by_the_library(
    tfx: Tfx, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed raises ImportError
    with pytest.raises(FleetUnavailableError) as raised:
        dict(run_fleet([[BAG]], len, Fleet(dask="tcp://127.0.0.1:8786")))
    assert raised.value.address is None and "--" not in said_by_library(raised.value)
    line = one_error_line(tfx("wtf", BAG, "--dask", "tcp://127.0.0.1:8786"))
    assert "--dask needs Dask's distributed package, which is not installed" in line


def test_a_transform_tf2_cannot_take_is_an_invalid_transform(tfx: Tfx, tmp_path: Path) -> None:
    with pytest.raises(InvalidTransformError, match=r"the frame and the child frame are the same \(a\)"):
        checked(Transform((0, 0, 0), (0, 0, 0, 1), 0, "a", "a"))
    line = one_error_line(tfx("static", "0", "0", "0", "0", "0", "0", "0", "a", "b", "-b", BAG, "-o", tmp_path / "o"))
    assert "a -> b: the quaternion is zero (the identity is qx 0 qy 0 qz 0 qw 1)" in line


def test_a_frame_the_bag_has_names_tfx_frames_only_on_the_command_line(tfx: Tfx, tmp_path: Path) -> None:
    laser = Transform((0, 0, 0), (0, 0, 0, 1), 0, "base_link", "laser")
    with pytest.raises(InvalidTransformError, match="already has laser") as raised:
        copy_with_statics(BAG, tmp_path / "copy.bag", StaticQuery((laser,)))
    assert (raised.value.child, raised.value.recording) == ("laser", BAG)
    assert "tfx" not in str(raised.value)
    assert raised.value.hint == "add only frames the bag lacks"
    args = ("0", "0", "0", "0", "0", "0", "1", "base_link", "laser", "-b", BAG, "-o", tmp_path / "copy.bag")
    line = one_error_line(tfx("static", *args))
    assert f"add only frames the bag lacks: tfx frames -b {BAG} lists its own" in line
    assert "would give tf2 two values for it, and tfx wtf would fail the copy" in line
    assert not (tmp_path / "copy.bag").exists()


def test_a_file_of_a_ros2_bag_is_refused_in_the_bags_words_and_then_the_b_options(tfx: Tfx, tmp_path: Path) -> None:
    with pytest.raises(PartOfBagError) as raised:
        copyable(str(DB3))
    assert raised.value.bag == str(DB3.parent) and "-b" not in said_by_library(raised.value)
    args = ("0", "0", "0", "0", "0", "0", "1", "a", "b", "-b", DB3, "-o", tmp_path / "copy")
    line = one_error_line(tfx("static", *args))
    assert f"-b {DB3} is a file of the ROS 2 bag {DB3.parent}" in line
    assert f"-b {DB3.parent} -o OUTPUT" in line


def test_a_frame_not_there_carries_the_frames_there_are(tfx: Tfx) -> None:
    with pytest.raises(UnknownFrameError) as raised:
        known_frame(["odom", "base_link", "laser"], "/lasr")
    assert raised.value.frame == "/lasr" and raised.value.frames == ("laser", "base_link", "odom")
    assert isinstance(raised.value, TransformError) and "--" not in said_by_library(raised.value)
    line = one_error_line(tfx("echo", "odm", "base_link", "-b", BAG))
    assert "frame 'odm' does not exist (frames: odom, " in line


def test_no_frame_at_all_says_tf2_kept_none_and_where_to_see_why(tfx: Tfx, tmp_path: Path) -> None:
    # nvnmangla/beginner_tutorials' talker sends world -> talk with the rotation (1, 1, 0, 1): ROS 1's tf2 refuses
    # every one, so the buffer has no frame, and "(frames: )" said nothing (corpus ros2-talker-tf-...-2022-db3)
    with pytest.raises(UnknownFrameError) as raised:
        known_frame([], "world")
    assert raised.value.frames == () and raised.value.hint == "no frame at all: tf2 kept no transform"
    stamps = [1_670_130_358 * 10**9 + i * 500_000_000 for i in range(4)]
    bag = write_bag(
        tmp_path / "denormalised.bag",
        [
            TfMessage(
                "/tf", s + 100_000, [Transform((2.0, 2.0, 1.0), (1.0, 1.0, 0.0, 1.0), s, "world", "talk")], "/talker"
            )
            for s in stamps
        ],
    )
    line = one_error_line(tfx("echo", "world", "talk", "-b", bag))
    assert "frame 'world' does not exist (tf2 kept no transform: `tfx wtf` says which it refused, and why)" in line
    assert tfx("wtf", bag).code == 1  # which names them: refused by tf2, a rotation of length 1.73


def test_no_sensor_data_is_a_source_error_with_its_reasons() -> None:
    error = NoStampedDataError(["/scan: not in the recording"])
    assert error.problems == ["/scan: not in the recording"] and "--" not in said_by_library(error)
    said, code = worded(error)
    assert isinstance(said, UsageError) and str(said) == str(error) and code == 2


def test_the_table_has_one_row_per_error_sorted_and_others_pass_as_they_are() -> None:
    names = [kind.__name__ for kind in table()]
    assert names == sorted(names)
    plain = TfToolsError("something")
    assert worded(plain) == (plain, 2)


def test_a_findings_file_that_may_not_be_written_names_force_only_on_the_command_line(tfx: Tfx, tmp_path: Path) -> None:
    from tftools.sinks.errors import FindingsFileError
    from tftools.sinks.findings_mcap import refuse_output

    there = tmp_path / "findings.mcap"
    there.write_bytes(b"")
    with pytest.raises(FindingsFileError) as raised:
        refuse_output(there, [BAG], force=False)
    assert raised.value.reason == "exists" and "--" not in said_by_library(raised.value)
    line = one_error_line(tfx("wtf", BAG, "--mcap", there))  # the command line's one rule of outputs words it first
    assert f"--mcap {there} already exists (name another output, or --force to replace it)" in line
    line = one_error_line(tfx("wtf", BAG, "--mcap", tmp_path))
    assert f"--mcap {tmp_path} is a directory (give a file name, e.g. --mcap {tmp_path}/findings.mcap)" in line
