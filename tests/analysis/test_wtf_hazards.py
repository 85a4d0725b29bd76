"""Static transforms on replay (and their repair), jumps, and broadcasters inferred where bags name no publisher."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tests.cli.conftest import Result, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import shared_dir
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import check
from tftools.analysis.wtf.jumps import FLOOR_M, JUMP_FACTOR, jumps
from tftools.core.time import NS_PER_S
from tftools.sinks.static_bag import REPAIR_EVERY_S, repair_static_transforms
from tftools.sources.recording import read_recording

ROS2_FORMATS = [f for f in scenes.FORMATS if f is not BagFormat.ros1]


def loud(findings: list[Finding]) -> list[Finding]:
    return [f for f in findings if f.severity is not Severity.info]


def _volatile(bag: Path) -> Path:
    """``bag``'s metadata.yaml offering /tf_static volatile, as a recording of a volatile publisher says."""
    metadata = bag / "metadata.yaml"
    text = metadata.read_text()
    assert text.count("durability: transient_local") == 1
    metadata.write_text(text.replace("durability: transient_local", "durability: volatile"))
    return bag


def _digest(path: Path) -> str:
    files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
    return hashlib.sha256(b"".join(f.read_bytes() for f in files)).hexdigest()


# --- static transforms on replay -------------------------------------------------------------


@pytest.mark.parametrize("fmt", ROS2_FORMATS)
def test_tf_static_offered_volatile_is_a_warning_and_transient_local_is_quiet(tmp_path: Path, fmt: BagFormat) -> None:
    durable = scenes.write(tmp_path, "durable", fmt, scenes.healthy())
    assert check(read_recording([durable])) == []
    volatile = _volatile(scenes.write(tmp_path, "volatile", fmt, scenes.healthy()))
    (finding,) = check(read_recording([volatile]))
    assert (finding.code, finding.severity) == ("static_volatile", Severity.warning)
    assert "volatile" in finding.message and "--repair" in finding.hint
    assert {"base_link", "laser", "camera"} <= set(finding.frames)


def test_a_bare_db3_is_reported_as_not_checked_with_the_reason(tmp_path: Path) -> None:
    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_sqlite3, scenes.healthy())
    (file,) = bag.glob("*.db3")
    (finding,) = check(read_recording([file]))
    assert finding.skipped and finding.code == "static_volatile" and finding.severity is Severity.info
    assert "not checked" in finding.message and "metadata.yaml" in finding.message


@pytest.mark.parametrize("fmt", scenes.FORMATS)
def test_repair_makes_statics_durable_complete_and_repeated_and_leaves_the_input(
    tmp_path: Path, fmt: BagFormat
) -> None:
    bag = scenes.write(tmp_path, "long", fmt, scenes.PROBLEMS["statics_early"].make())
    if fmt is not BagFormat.ros1:
        _volatile(bag)
    before = _digest(bag)
    found = {(f.code, f.severity) for f in check(read_recording([bag]))}
    assert found == {("statics_early", Severity.info)} | (
        set() if fmt is BagFormat.ros1 else {("static_volatile", Severity.warning)}
    )
    out = tmp_path / ("fixed.bag" if fmt is BagFormat.ros1 else "fixed")
    written, statics = repair_static_transforms(bag, out)
    assert _digest(bag) == before
    assert {(t.frame_id, t.child_frame_id) for t in statics} == {("base_link", "laser"), ("base_link", "camera")}
    repaired = read_recording([written])
    assert check(repaired) == []
    batch = repaired.transforms
    times = np.unique(batch.record_time[batch.static])
    assert len(times) >= scenes.LONG / REPAIR_EVERY_S and np.diff(times).max() <= REPAIR_EVERY_S * NS_PER_S
    if fmt is BagFormat.ros1:
        from rosbags.rosbag1 import Reader

        with Reader(written) as reader:
            assert all(c.ext.latching == 1 for c in reader.connections if c.topic == "/tf_static")
            assert {c.ext.callerid for c in reader.connections if c.topic == "/tf_static"} == {"/rsp"}


def test_repair_on_the_command_line_never_writes_over_its_input(tmp_path: Path, tfx) -> None:  # noqa: F811
    bag = scenes.write(tmp_path, "in", BagFormat.ros1, scenes.healthy())
    before = _digest(bag)
    refused: Result = tfx("static", "--repair", "-b", bag, "-o", bag)
    assert refused.code == 2 and "input" in refused.stderr and _digest(bag) == before
    done: Result = tfx("static", "--repair", "-b", bag, "-o", tmp_path / "out.bag")
    assert done.code == 0 and "base_link -> laser" in done.stdout
    given: Result = tfx("static", "--repair", "0", "0", "0", "0", "0", "0", "a", "b", "-b", bag, "-o", tmp_path / "x")
    assert given.code == 2 and "--repair takes no transforms" in given.stderr


def test_statics_repeated_through_a_long_recording_are_quiet() -> None:
    statics = scenes.statics().transforms
    repeated = [TfMessage("/tf_static", scenes.START + i * 5 * NS_PER_S + 1, statics, "/rsp") for i in range(14)]
    messages = scenes.healthy(
        statics=repeated,
        amcl=scenes.amcl(end=scenes.LONG),
        ekf=scenes.ekf(end=scenes.LONG),
        wheels=scenes.wheels(end=scenes.LONG),
    )
    assert check(scenes.recording(messages)) == []


# --- jumps and REP 105 -----------------------------------------------------------------------


def test_a_jump_on_another_edge_is_a_warning_with_when_and_how_far() -> None:
    def arm(stamp: int) -> list:  # type: ignore[type-arg]
        return [scenes._t("base_link", "arm", stamp, 0.1 * scenes._s(stamp) + (0.5 if scenes._s(stamp) >= 6 else 0.0))]

    (finding,) = check(scenes.recording(scenes.healthy(wheels=[*scenes.wheels(), *scenes.periodic("/arm", 20, arm)])))
    assert (finding.code, finding.severity, finding.frames) == ("jump", Severity.warning, ("base_link", "arm"))
    assert "0.505 m" in finding.message and "+6.0 s" in finding.message


def test_motion_from_rest_fast_turns_and_a_gap_are_explained_by_the_edge_s_own_motion() -> None:
    seconds = np.arange(0, 20, 0.02)
    speed = np.where(seconds < 5, 0.0, 2.0)  # standing still, then off at 2 m/s
    x = np.cumsum(speed * 0.02)
    yaw = np.where(seconds < 10, 0.0, 3.0 * (seconds - 10))  # then turning at 3 rad/s
    keep = (seconds < 12) | (seconds > 13)  # and a second lost
    values = np.zeros((len(seconds), 7))
    values[:, 0] = x
    values[:, 5], values[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)
    stamps = (seconds * NS_PER_S).astype(np.int64)
    assert len(jumps(stamps[keep], values[keep])) == 0
    values[600:, 0] += JUMP_FACTOR * 0.04 + FLOOR_M  # beyond what 4 cm a sample explains, by a hair
    assert jumps(stamps, values).at.tolist() == [600]


@pytest.mark.parametrize("ros1", [True, False], ids=["ros1", "ros2"])
def test_the_healthy_robots_jumps_and_rep105_stay_quiet(ros1: bool) -> None:
    assert not [
        f
        for f in check(scenes.recording(scenes.healthy(), ros1=ros1))
        if f.code in {"jump", "map_corrections", "rep105"}
    ]


# --- several broadcasters where the bag names none -------------------------------------------


def _fighting(stamp: int) -> list:  # type: ignore[type-arg]
    """A second odometry, 0.3 m off the first."""
    return [scenes._t("odom", "base_link", stamp, 0.4 * scenes._s(stamp) + 0.3, 0.1 * scenes._s(stamp))]


def _late_twin(stamp: int) -> list:  # type: ignore[type-arg]
    """A second broadcaster of the same motion whose stamps lag 30 ms behind."""
    return scenes.odom_base(stamp - 30_000_000)


@pytest.mark.parametrize("fmt", ROS2_FORMATS)
@pytest.mark.parametrize(
    ("second", "sign"), [(_fighting, "alternated between two places"), (_late_twin, "stamps went back")]
)
def test_two_broadcasters_taking_turns_are_inferred_in_ros2_bags(
    tmp_path: Path, fmt: BagFormat, second: object, sign: str
) -> None:
    other = scenes.periodic("/ekf2", 50, second, phase=0.01)  # type: ignore[arg-type]
    bag = scenes.write(
        tmp_path, "two", fmt, scenes.healthy(ekf=sorted(scenes.ekf() + other, key=lambda m: m.record_time))
    )
    findings = loud(check(read_recording([bag])))
    assert [f.code for f in findings] == ["multiple_authorities"], findings
    assert sign in findings[0].message and findings[0].frames == ("odom", "base_link")


#: The shared corpus's recordings that do have one of these findings, checked by eye.
TRUE_HAZARDS = {
    "ros1_talker_world_talk.bag": {"jump"},  # world -> talk's z wraps from 4 m to -5 m at +9.5 s
    "ros2_mcap_nav2_turtlebot4.mcap": {"map_corrections"},  # AMCL's map -> odom steps (a note)
}


def test_sample_bags_and_the_shared_corpus_show_no_jump_and_no_inferred_broadcaster() -> None:
    samples = Path(__file__).resolve().parents[2] / "sample_bags"
    shared = shared_dir() / "corpus"  # ../shared beside the repository, as in CI
    bags = [samples / "robot.bag", samples / "robot_db3", samples / "robot_mcap"]
    bags += sorted(p for p in shared.glob("*") if p.is_dir() or p.suffix in (".bag", ".mcap"))
    for bag in bags:
        codes = {f.code for f in check(read_recording([bag], allow_empty=True))}
        hazards = codes & {"jump", "map_corrections", "rep105", "multiple_authorities"}
        assert hazards == TRUE_HAZARDS.get(bag.name, set()), (bag, codes)
