"""The sample bags in every format, loaded by tftools, answer as rosbag + the real tf2 do."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import tftools
from tests.oracle import ERROR_CLASSES, Row, Scenario, binding_time, run_tf2
from tftools.core.errors import TransformError
from tftools.core.time import NS_PER_S

SAMPLES = Path(__file__).resolve().parents[2] / "sample_bags"
ROS1_BAG = SAMPLES / "robot.bag"
FORMATS = {"ros1": ROS1_BAG, "db3": SAMPLES / "robot_db3", "mcap": SAMPLES / "robot_mcap"}
PAIRS = [
    ("map", "gripper"),
    ("map", "laser"),
    ("odom", "left_wheel"),
    ("arm_link3", "camera_optical_frame"),
    ("gripper", "right_wheel"),
    ("base_link", "imu_link"),
]
START, END = 1_700_000_000 * NS_PER_S, 1_700_000_015 * NS_PER_S
# tf2's binding stores stamps through a double: ~100 ns of rounding at epoch times, so values
# are compared to what 1 us of motion can change, stamps to 1 us.
VALUE_TOLERANCE = 1e-5
STAMP_TOLERANCE = 1_000


def _queries() -> list[Row]:
    rng = np.random.default_rng(3)
    times = np.concatenate([rng.integers(START - NS_PER_S, END + NS_PER_S, 60), [0]])
    queries: list[Row] = [["frames"], ["yaml"]]
    for target, source in PAIRS:
        queries.append(["lct", target, source])
        for t in times:
            sec, nsec = divmod(int(t), NS_PER_S)
            queries.append(["lookup", target, source, sec, nsec])
    return queries


QUERIES = _queries()


@pytest.fixture(scope="module")
def tf2_answers(tf2_available: None) -> list[dict[str, Any]]:
    (result,) = run_tf2([Scenario(queries=QUERIES, bag=str(ROS1_BAG))])
    answers: list[dict[str, Any]] = result["answers"]
    return answers


@pytest.fixture(scope="module", params=list(FORMATS))
def buffer(request: pytest.FixtureRequest) -> tftools.Buffer:
    """Each format's copy of the ROS 1 bag, read as ROS 1's tf2 would (the oracle): ROS 2 files
    default to ROS 2's tf2, whose messages differ (tests/core/test_ros2_tf2.py)."""
    return tftools.read_recording([FORMATS[request.param]], semantics="ros1").buffer


def _stamp(answer: dict[str, Any]) -> int:
    sec: int
    nsec: int
    sec, nsec = answer["stamp"]
    return sec * NS_PER_S + nsec


def test_frames_match(buffer: tftools.Buffer, tf2_answers: list[dict[str, Any]]) -> None:
    assert buffer.all_frames_as_string() == tf2_answers[0]["text"]


def test_frames_yaml_matches(
    request: pytest.FixtureRequest, buffer: tftools.Buffer, tf2_answers: list[dict[str, Any]]
) -> None:
    ours, theirs = buffer.all_frames_as_yaml(), tf2_answers[1]["text"]
    if request.node.callspec.params["buffer"] != "ros1":  # ROS2 bags name no publisher: the topic stands in
        theirs = re.sub(r"broadcaster: '[^']*'", "broadcaster: ?", theirs)
        ours = re.sub(r"broadcaster: '[^']*'", "broadcaster: ?", ours)
    assert ours == theirs


def test_lookups_match(buffer: tftools.Buffer, tf2_answers: list[dict[str, Any]]) -> None:
    failures = 0
    for query, theirs in zip(QUERIES[2:], tf2_answers[2:], strict=True):
        if query[0] == "lct":
            assert abs(buffer.latest_common_time(query[1], query[2]) - _stamp(theirs)) <= STAMP_TOLERANCE, query
            continue
        _, target, source, sec, nsec = query
        time = sec * NS_PER_S + nsec
        try:
            ours = buffer.lookup(target, source, binding_time(time) if time else 0)
        except TransformError as error:
            assert not theirs["ok"], f"{query}: we failed ({error}), tf2 answered"
            assert type(error).__name__ == ERROR_CLASSES[theirs["error"]], query
            failures += 1
            continue
        assert theirs["ok"], f"{query}: tf2 failed ({theirs['message']}), we answered"
        assert abs(ours.stamp - _stamp(theirs)) <= STAMP_TOLERANCE, query
        np.testing.assert_allclose(ours.translation, theirs["t"], atol=VALUE_TOLERANCE, err_msg=str(query))
        np.testing.assert_allclose(ours.rotation, theirs["q"], atol=VALUE_TOLERANCE, err_msg=str(query))
    assert failures > 0, "the queries should include times outside the recording"


def test_lookup_many_matches_scalar_lookups(buffer: tftools.Buffer) -> None:
    times = np.linspace(START, END, 2001).astype(np.int64)
    batch = buffer.lookup_many("map", "gripper", times)
    assert batch.valid[100:-100].all()
    for i in np.flatnonzero(batch.valid)[::97]:
        scalar = buffer.lookup("map", "gripper", int(times[i]))
        np.testing.assert_allclose(batch.translations[i], scalar.translation, atol=1e-12)
        np.testing.assert_allclose(batch.rotations[i], scalar.rotation, atol=1e-12)
