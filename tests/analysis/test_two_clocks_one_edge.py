"""One edge from two publishers on two clocks: a camera's odometry on the recorder's clock beside an EKF on a
machine whose clock runs hours ahead (corpus ros1-sail-zed-ekf-gps-two-odometries-2022-bag: a ZED2 and
robot_localization's ekf_se both sending odom -> base_link, the EKF's stamps 5.8 h ahead, its GPS fixes stepping
it 3.8-5.1 m). Each publisher's own problems are said of it: the EKF's clock ahead and its jumps, beside the two
publishers' ``multiple_authorities``."""

from __future__ import annotations

from tests.analysis.wtf_scenes import MS, START, _t, healthy, periodic, recording
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

AHEAD = 5 * 3600 * NS_PER_S


def _camera(stamp: int) -> list[Transform]:
    return [_t("odom", "base_link", stamp, 1.25)]  # at rest


def _ekf_moving_with_a_gps_step(stamp: int) -> list[Transform]:
    seconds = (stamp - AHEAD - START) / NS_PER_S
    return [_t("odom", "base_link", stamp, 0.04 * seconds + (4.0 if seconds >= 5.0 else 0.0))]


def _findings() -> list[Finding]:
    camera = periodic("/camera", 100, _camera)
    ekf = periodic("/ekf", 30, _ekf_moving_with_a_gps_step, stamp=lambda t: t + AHEAD)
    return check(recording(healthy(ekf=sorted(camera + ekf, key=lambda m: m.record_time)))).findings


def _of(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code and f.frames[:2] == ("odom", "base_link")]


def test_the_publisher_whose_clock_runs_ahead_is_future_not_both() -> None:
    (future,) = _of(_findings(), "future")
    assert future.authorities == ("/ekf",), future
    assert "odom -> base_link by /ekf: 300 of 300 transforms stamped up to 5.0 h after they arrived" in future.message


def test_the_ekfs_gps_step_is_a_jump_beside_the_two_publishers() -> None:
    findings = _findings()
    (jump,) = _of(findings, "jump")
    assert jump.authorities == ("/ekf",) and "the largest 4.0" in jump.message, jump
    assert _of(findings, "multiple_authorities")


def test_a_leading_slash_is_placed_when_it_arrived_not_at_a_stamp_hours_away() -> None:
    """The SAIL vehicle's static_transform_publishers ran on the EKF's machine: '/base_link' stamped 5.4 h after
    the recording, so the finding's time (where the report zooms) lay outside it, though its text said '+0.1 s'."""
    late = TfMessage("/tf_static", START + 2 * MS, [_t("/base_link", "/gps", START + AHEAD, 0.01)], "/gps_tf")
    (slash,) = [f for f in check(recording(healthy(statics=[late]))).findings if f.code == "leading_slash"]
    assert START <= slash.first_time <= START + NS_PER_S, slash
