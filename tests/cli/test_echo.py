"""``tfx echo`` on the sample bags: tf2's numbers, tf_echo's layout, scriptable formats, clean errors."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import re
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from tests.bags import TfMessage
from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tests.oracle import Scenario, binding_time, run_tf2
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

FORMATS = list(SAMPLE_BAGS)


@pytest.mark.parametrize("fmt", FORMATS)
def test_json_lines_match_tf2_on_the_ros1_bag(tfx: Tfx, tf2_available: None, fmt: str) -> None:
    result = tfx("echo", "map", "gripper", "-b", SAMPLE_BAGS[fmt], "--rate", "4", "--format", "json")
    assert result.code == 0, result.stderr
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert 55 <= len(records) <= 61  # 4 Hz over the ~14.9 s where every edge of the chain has data
    queries = [["lookup", "map", "gripper", *divmod(binding_time(r["stamp_ns"]), NS_PER_S)] for r in records]
    (theirs,) = run_tf2([Scenario(queries=queries, bag=str(SAMPLE_BAGS["ros1"]))])
    for ours, answer in zip(records, theirs["answers"], strict=True):
        assert answer["ok"], answer
        np.testing.assert_allclose(ours["translation"], answer["t"], atol=1e-5)
        np.testing.assert_allclose(ours["rotation"], answer["q"], atol=1e-5)


def test_text_has_tf_echo_layout(tfx: Tfx) -> None:
    result = tfx("echo", "map", "base_link", "-b", SAMPLE_BAGS["db3"], "--rate", "1", "--end", "+3")
    assert result.code == 0, result.stderr
    blocks = result.stdout.strip().split("At time ")[1:]
    assert len(blocks) == 3
    number = r"-?\d+\.\d{3}"

    def vector(n: int) -> str:
        return r"\[" + ", ".join([number] * n) + r"\]"

    pattern = (
        rf"{number}\n- Translation: {vector(3)}\n- Rotation: in Quaternion {vector(4)}\n"
        rf"\s+in RPY \(radian\) {vector(3)}\n\s+in RPY \(degree\) {vector(3)}\n?"
    )
    for block in blocks:
        assert re.fullmatch(pattern, block), block


def test_formats_agree(tfx: Tfx) -> None:
    outputs = [
        tfx("echo", "odom", "arm_link4", "-b", SAMPLE_BAGS[f], "-f", "json", "--rate", "2").stdout for f in FORMATS
    ]
    parsed = [[json.loads(line) for line in out.splitlines()] for out in outputs]
    assert len(parsed[0]) > 20
    for other in parsed[1:]:
        assert [r["stamp_ns"] for r in other] == [r["stamp_ns"] for r in parsed[0]]
        np.testing.assert_allclose([r["translation"] for r in other], [r["translation"] for r in parsed[0]], atol=1e-12)


def test_csv_columns_and_every_sample(tfx: Tfx) -> None:
    result = tfx("echo", "map", "odom", "-b", SAMPLE_BAGS["mcap"], "--all", "--format", "csv")
    assert result.code == 0, result.stderr
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert len(rows) == 150  # amcl published map -> odom 150 times in 15 s
    assert rows[0].keys() >= {"time", "stamp_ns", "x", "y", "z", "qx", "qy", "qz", "qw", "roll", "pitch", "yaw"}
    stamps = [int(r["stamp_ns"]) for r in rows]
    assert stamps == sorted(stamps)


@pytest.mark.parametrize(("fmt", "lines"), [("text", 5), ("json", 1)])
def test_every_sample_of_a_static_chain_is_its_one_transform(tfx: Tfx, fmt: str, lines: int) -> None:
    """``--all`` on frames joined by static edges alone (a calibration bag of one /tf_static message) printed
    nothing and exited 0: the chain's one transform, holding at every time, is one line (the first of the
    default once-a-second echo)."""
    frames = ("base_link", "camera_optical_frame")
    every = tfx("echo", *frames, "-b", SAMPLE_BAGS["ros1"], "--all", "-f", fmt)
    assert every.code == 0, every.stderr
    once_a_second = tfx("echo", *frames, "-b", SAMPLE_BAGS["ros1"], "-f", fmt).stdout.splitlines()
    assert every.stdout.splitlines() == once_a_second[:lines]


def test_failed_lookup_prints_tf2_reason_and_exits_1(tfx: Tfx) -> None:
    result = tfx("echo", "map", "gripper", "-b", SAMPLE_BAGS["db3"], "--at", "1699999000")
    assert result.code == 1
    assert result.stdout.startswith(
        "Failure at 1699999000.000000000\nException thrown:Lookup would require extrapolation"
    )
    assert "into the past" in result.stdout


def test_unknown_frame_is_one_line_with_close_matches(tfx: Tfx) -> None:
    result = tfx("echo", "map", "grippr", "-b", SAMPLE_BAGS["db3"])
    assert result.code == 2
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert "frame 'grippr' does not exist" in result.stderr and "gripper" in result.stderr


@pytest.mark.parametrize(
    ("make", "expected"),
    [
        (lambda tmp: tmp / "missing.bag", "no such file"),
        (lambda tmp: _write(tmp / "noise.bag", bytes(range(256)) * 20), "not a ROS1 bag"),
        (lambda tmp: _write(tmp / "empty.bag", b""), "an empty file: 0 bytes"),
        (lambda tmp: _write(tmp / "old.bag", b"#ROSRECORD V1.2\n" + b"\0" * 64), "a ROS 1 bag of the old format 1.2"),
    ],
)
def test_bad_bags_are_one_line_errors(tfx: Tfx, tmp_path: Path, make: Callable[[Path], Path], expected: str) -> None:
    result = tfx("echo", "map", "odom", "-b", make(tmp_path))
    assert result.code == 2
    assert result.stderr.startswith("tfx: error:") and result.stderr.count("\n") == 1
    assert expected in result.stderr


def test_console_script_runs(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "tftools", "echo", "map", "laser", "-b", SAMPLE_BAGS["ros1"], "--at", "+5"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("At time 1700000005.005")  # 5 s after the first tf stamp (1700000000.005191875)


def _write(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def test_precision_sets_the_decimals_and_matrix_adds_the_homogeneous_matrix(tfx: Tfx) -> None:
    args = ("echo", "map", "laser", "-b", SAMPLE_BAGS["ros1"], "--at", "+5")
    six = tfx(*args, "--precision", "6", "--matrix")
    assert six.code == 0, six.stderr
    assert re.match(r"At time 1700000005\.005192\n- Translation: \[-?\d+\.\d{6}, ", six.stdout)
    lines = six.stdout.splitlines()
    rows = lines[lines.index("- Matrix:") + 1 :]
    matrix = np.array([[float(v) for v in row.split()] for row in rows])
    (record,) = [json.loads(line) for line in tfx(*args, "-f", "json").stdout.splitlines()]
    expected = Transform(tuple(record["translation"]), tuple(record["rotation"])).as_matrix()
    np.testing.assert_allclose(matrix, expected, atol=1e-6)
    assert "- Matrix:" not in tfx(*args).stdout  # --no-matrix is the default
    assert tfx(*args, "--precision", "13").code == 2


def test_cache_sets_the_live_buffers_length(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    asked: list[int | None] = []

    class ListenedError(Exception):
        pass

    def listen(source: object, cache_time: int | None, semantics: object = None) -> None:
        asked.append(cache_time)
        raise ListenedError

    monkeypatch.setenv("TFX_DEBUG", "1")  # the test's own exception comes through

    class Feed(contextlib.nullcontext[None]):
        format = "ros1-live"  # as LiveSource says which ROS it hears

        def describe(self) -> str:
            return "a test"

    monkeypatch.setattr("tftools.cli.echo.live.open_source", lambda *args: Feed())
    monkeypatch.setattr("tftools.sources.live.capture.listen", listen)
    with pytest.raises(ListenedError):
        tfx("echo", "map", "odom", "--cache", "2.5")
    assert asked == [2_500_000_000]
    refused = tfx("echo", "map", "odom", "--cache", "0")
    assert refused.code == 2 and "--cache 0: must be above 0" in refused.stderr


def test_a_failure_between_separate_trees_keeps_tf2_s_reason_and_hints_at_the_trees(tfx: Tfx, tmp_path: Path) -> None:
    """The real UR5 cobots (krishi_cobot_ur5_topic_tf_2025, logistic_cobot_pymoveit2_zero_record_times_2024): an
    arm on simulated time and detected objects on wall time, in two trees: tf2 reports an extrapolation on the
    first edge it walks, not that the trees do not meet; the hint under it says so."""
    from tests.analysis.wtf_scenes import FORMATS, healthy, periodic, sim, write

    def marker(stamp: int) -> list[Transform]:
        return [Transform((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "camera_root", "marker")]

    bag = write(tmp_path, "two_trees", FORMATS[1], healthy(markers=periodic("/detector", 5, marker, stamp=sim)))
    result = tfx("echo", "base_link", "marker", "-b", bag)
    assert result.code == 1
    assert "Exception thrown:Lookup would require extrapolation" in result.stdout  # tf2's own words, untouched
    assert result.stderr.startswith(
        "hint: marker and base_link are in separate trees, marker in camera_root's (2 frames) and base_link in "
        "map's (6 frames): no transform joins them"
    )
    assert "publish the transform that attaches camera_root to the map tree" in result.stderr
    joined = tfx("echo", "map", "laser", "-b", bag, "--at", "1")  # one tree: a failure there gets no such hint
    assert joined.code == 1 and "separate trees" not in joined.stderr
    played = tfx("echo", "base_link", "marker", "-b", bag, "--play", "--start", "-0.5", "--rate", "10")
    assert played.code == 1
    assert "Exception thrown:Could not find a connection between 'base_link' and 'marker'" in played.stdout
    assert played.stderr.count("hint: ") == 1  # once, however many lookups failed
    assert played.stderr.startswith(
        "hint: marker and base_link are in separate trees, marker in camera_root's (2 frames) and base_link in "
        "map's (6 frames): no transform joins them, so no lookup between them succeeds at any time; publish"
    )  # tf2's reason says they are not in one tree: no word on which edge it names


def test_a_replay_whose_frames_are_joined_later_gives_no_separate_trees_hint(tfx: Tfx, tmp_path: Path) -> None:
    """Replayed, frames apart at first (map known by a landmark latched under it, map -> odom not sent yet) and
    joined later: the first lookups fail, and no hint says no transform joins them; echo looks at the tree as the
    replay ends, as a whole read does."""
    from tests.analysis.wtf_scenes import FORMATS, START, _t, amcl, healthy, statics, write

    landmark = TfMessage("/tf_static", START, [_t("map", "landmark", START)], "/map_server")
    bag = write(tmp_path, "late_map", FORMATS[0], healthy(amcl=amcl(start=1.0), statics=[landmark, statics()]))
    played = tfx("echo", "map", "base_link", "-b", bag, "--play", "--end", "+1.5", "--rate", "10")
    assert played.code == 1 and "- Translation:" in played.stdout
    assert "Exception thrown:Could not find a connection between 'map' and 'base_link'" in played.stdout
    assert "separate trees" not in played.stderr


def test_the_rate_after_the_frames_is_tf_echo_s_echo_rate(tfx: Tfx) -> None:
    """``tf_echo source target [echo_rate]`` (ROS 1's and ROS 2's tf2_echo alike): ``tfx echo map base_link 2``
    was 'Got unexpected extra argument(s) (2)'. The third argument is the rate, as --rate; both differing: refused."""
    args = ("echo", "map", "base_link", "-b", SAMPLE_BAGS["db3"], "--end", "+3")
    third = tfx(*args[:3], "2", *args[3:])
    assert third.code == 0, third.stderr
    assert (
        third.stdout == tfx(*args, "--rate", "2").stdout and third.stdout.count("At time ") == 6
    )  # 0 to 2.5 s every 0.5 s
    assert tfx(*args[:3], "2", *args[3:], "--rate", "2").stdout == third.stdout
    twice = tfx(*args[:3], "2", *args[3:], "--rate", "3")
    assert twice.code == 2 and "two rates: 2 after the frames and --rate 3" in twice.stderr


@pytest.mark.parametrize(
    ("given", "fixed"),
    [
        (["_precision:=6"], "--precision 6"),  # rosrun tf tf_echo's private parameters
        (["_rate:=2", "_precision:=6"], "--rate 2 --precision 6"),
        (["--ros-args", "-p", "use_sim_time:=true"], "--use-sim-time"),  # ros2 run's
        (["--ros-args", "-p", "use_sim_time:=False"], "--wall-time"),
    ],
)
def test_a_ros_node_s_arguments_are_shown_as_tfx_options(tfx: Tfx, given: list[str], fixed: str) -> None:
    """``_precision:=6`` was 'Got unexpected extra argument(s)', ``--ros-args`` 'No such option': a ROS tool's
    node arguments, which tfx is not; the error shows the command line in tfx's options."""
    bag = str(SAMPLE_BAGS["ros1"])
    result = tfx("echo", "map", "base_link", "-b", bag, *given)
    assert result.code == 2 and result.stderr.count("\n") == 1
    assert f"{given[0]}: a ROS node's argument" in result.stderr
    assert f"in tfx's options: tfx echo map base_link -b {bag} {fixed})" in result.stderr


def test_a_node_argument_no_option_says_is_named(tfx: Tfx) -> None:
    result = tfx("monitor", "-b", SAMPLE_BAGS["ros1"], "--ros-args", "-r", "__ns:=/robot1")
    assert (
        result.code == 2 and "__ns:=/robot1: no option of tfx monitor says it; see tfx monitor --help" in result.stderr
    )
    precision = tfx("monitor", "-b", SAMPLE_BAGS["ros1"], "_precision:=6")  # tf_echo's, not tf_monitor's
    assert precision.code == 2 and "_precision:=6: no option of tfx monitor says it" in precision.stderr


def test_a_slashed_frame_is_looked_up_without_it_and_said_so_on_ros2_data(tfx: Tfx) -> None:
    """``/map``: ROS 1's tf_echo drops the slash, ROS 2's tf2 refuses it ("in tf2 frame_ids cannot start with a
    '/'"). tfx looks up map on both; on ROS 2 data a hint says a ROS 2 node must ask for map."""
    for fmt in ("ros1", "db3"):
        args = ("-b", SAMPLE_BAGS[fmt], "--at", "+5")
        slashed, plain = tfx("echo", "/map", "base_link", *args), tfx("echo", "map", "base_link", *args)
        assert slashed.code == 0 and slashed.stdout == plain.stdout and not plain.stderr
        if fmt == "ros1":
            assert not slashed.stderr
        else:
            assert slashed.stderr.startswith("hint: /map looked up as map, as ROS 1's tf_echo does: ROS 2's tf2")
            assert "so a ROS 2 node asks for map\n" in slashed.stderr
    monitored = tfx("monitor", "/map", "/base_link", "-b", SAMPLE_BAGS["db3"], "-f", "json")
    assert monitored.code == 0 and "/map, /base_link looked up as map, base_link" in monitored.stderr
