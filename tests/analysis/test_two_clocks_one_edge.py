"""One edge from two publishers on two clocks: a camera's odometry on the recorder's clock beside an EKF on a
machine whose clock runs hours ahead (corpus ros1-sail-zed-ekf-gps-two-odometries-2022-bag: a ZED2 and
robot_localization's ekf_se both sending odom -> base_link, the EKF's stamps 5.8 h ahead, its GPS fixes stepping
it 3.8-5.1 m). Each publisher's own problems are said of it: the EKF's clock ahead and its jumps, beside the two
publishers' ``multiple_authorities``."""

from __future__ import annotations

import dataclasses
import math

import pytest

from tests.analysis.wtf_scenes import MS, START, _t, healthy, periodic, recording, sensor
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.monitor import MonitorQuery, monitor
from tftools.analysis.wtf import Scene, findings_of
from tftools.analysis.wtf.fleet import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.filter import _advice
from tftools.render.monitor import as_dict
from tftools.sources import clocks_apart
from tftools.sources.contents import StampedMessages

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


def test_a_time_on_the_clock_ahead_is_placed_on_the_recorders_never_hours_into_it() -> None:
    """The EKF's jump and future times were '+20881.5 s' into a 15.8 s recording: the tf span took the clock
    ahead for the recorder's. Now the span is the camera's, and a stamp of the EKF's says its clock and where
    it falls on the recorder's."""
    findings = _findings()
    (jump,) = _of(findings, "jump")
    (future,) = _of(findings, "future")
    for finding in (jump, future):
        assert "on a clock 5.0 h ahead of the recorder's: +" in finding.message, finding.message
        assert "(+18" not in finding.message, finding.message
    assert "on a clock 5.0 h ahead of the recorder's: +5.0 s)" in jump.message, jump.message


def _imu_on_the_ekfs_clock() -> StampedMessages:
    """An IMU on the EKF's machine, stamped on its clock at 50 Hz, arriving 5 ms later."""
    data = sensor("/imu", "base_link", 50, 5 * MS)
    return dataclasses.replace(data, stamp=data.stamp + AHEAD)


def test_a_sensor_waits_at_the_rate_of_the_publisher_on_its_clock_not_both() -> None:
    """odom -> base_link from the camera (100 Hz) and the EKF (30 Hz) on a clock 5 h ahead: a sensor stamped on
    the EKF's clock meets the EKF's samples only; its wait is at their 30 Hz, not the two blended (130 Hz)."""
    camera = periodic("/camera", 100, _camera)
    ekf = periodic("/ekf", 30, _ekf_moving_with_a_gps_step, stamp=lambda t: t + AHEAD)
    messages = healthy(ekf=sorted(camera + ekf, key=lambda m: m.record_time))
    (stream,) = Scene(recording(messages), streams=[_imu_on_the_ekfs_clock()]).sensors.streams
    assert stream.late_edge == ("odom", "base_link"), stream
    assert stream.late_rate_hz == pytest.approx(30.0, abs=0.5), stream
    # monitor's rate of the edge is of both clocks' samples: said beside the 30 Hz, named as such
    assert stream.late_rate_all_hz == pytest.approx(130.0, abs=2), stream
    assert "30.0 Hz on the messages' clock (1" in stream.wait_made_of(), stream.wait_made_of()


def test_a_sensor_waiting_for_an_edge_on_one_clock_names_one_rate() -> None:
    """The camera and the EKF on one clock: the edge's rate is monitor's, and no second figure stands beside it."""
    camera = periodic("/camera", 100, _camera)
    ekf = periodic("/ekf", 30, _ekf_moving_with_a_gps_step)
    messages = healthy(ekf=sorted(camera + ekf, key=lambda m: m.record_time))
    imu = sensor("/imu", "base_link", 50, 0, phase=0.003)  # arriving at its stamp: it waits for the next tf
    (stream,) = Scene(recording(messages), streams=[imu]).sensors.streams
    assert stream.late_rate_hz > 0 and stream.late_rate_all_hz == 0.0, stream
    assert "clock" not in stream.wait_made_of(), stream.wait_made_of()


def test_a_sensor_stamped_hours_from_tf_is_told_to_sync_clocks_not_to_wait() -> None:
    """A GPS on the EKF's machine while only the camera sends odom -> base_link (the SAIL bag recorded half an
    hour later): every fix waits for a stamp tf never reaches. No wait or cache helps: the clocks differ."""
    gps = dataclasses.replace(sensor("/fix", "base_link", 5, 5 * MS), topic="/fix")
    gps = dataclasses.replace(gps, stamp=gps.stamp + AHEAD)
    messages = healthy(ekf=periodic("/camera", 100, _camera))
    scene = Scene(recording(messages), streams=[gps])
    (stream,) = scene.sensors.streams
    assert stream.clock_apart == pytest.approx(AHEAD, abs=NS_PER_S), stream
    (lost,) = [f for f in findings_of(scene) if f.code == "sensor_lost"]
    assert "stamped 5.0 h ahead of odom -> base_link's samples" in lost.message, lost.message
    assert "chrony/NTP" in lost.hint and "no wait or cache" in lost.message, lost
    assert "keep the tf it waits for publishing" not in _advice(stream)
    assert "5.0 h ahead of tf's clock: sync the machines' clocks (chrony/NTP)" in _advice(stream)


def test_a_sensor_on_the_clock_of_one_of_its_edges_publishers_is_not_told_the_clocks_differ() -> None:
    """A GPS on the EKF's machine, stamped on its clock, while the camera (100 Hz) and the EKF (30 Hz, 5 h ahead)
    both send odom -> base_link; the EKF stops at 6 s, so the later fixes are lost. The fixes' clock is the EKF's:
    how far apart the clocks are is measured against the samples on it (``figures.base_near``, as the rate they
    wait at), never against the median of both publishers' (the camera's, 5 h behind: 'sync the clocks')."""
    camera = periodic("/camera", 100, _camera)
    ekf = periodic("/ekf", 30, _ekf_moving_with_a_gps_step, stamp=lambda t: t + AHEAD, end=6.0)
    gps = dataclasses.replace(sensor("/fix", "base_link", 5, 5 * MS), topic="/fix")
    gps = dataclasses.replace(gps, stamp=gps.stamp + AHEAD)
    scene = Scene(recording(healthy(ekf=sorted(camera + ekf, key=lambda m: m.record_time))), streams=[gps])
    (stream,) = scene.sensors.streams
    assert stream.never and stream.lost_edge == ("odom", "base_link"), stream
    assert stream.clock_apart == 0, stream
    assert "sync the machines' clocks" not in _advice(stream)


def _imu_broadcaster_ahead() -> list[TfMessage]:
    """An IMU's plane -> imu_link broadcast from the EKF's machine, alone on its edge, stamped 5 h ahead."""
    return periodic("/imu_tf", 50, lambda stamp: [_t("plane", "imu_link", stamp)], stamp=lambda t: t + AHEAD)


def test_a_delay_across_two_clocks_is_said_not_measurable_never_minus_five_hours() -> None:
    """monitor showed 'Average Delay -20881.49 s' for the SAIL IMU's edge: arrival on the recorder's clock minus
    a stamp on a machine's 5.8 h ahead is how far the clocks are apart, not a delay."""
    rec = recording(healthy(wheels=_imu_broadcaster_ahead()))
    report = monitor(rec, MonitorQuery())
    (imu,) = [e for e in report.edges if e.child == "imu_link"]
    assert math.isnan(imu.delay_mean) and abs(imu.apart - AHEAD) < 10 * MS, imu
    (base,) = [e for e in report.edges if e.child == "base_link"]
    assert not math.isnan(base.delay_mean) and base.apart == 0, base  # the recorder's own clock: a delay
    said = as_dict(report)
    (shown,) = [e for e in said["edges"] if e["child"] == "imu_link"]
    assert math.isnan(shown["delay_mean_s"]) and shown["delay_unmeasurable"] == "not measurable (clock apart by 5.0 h)"
    (publisher,) = [a for a in said["authorities"] if a["authority"] == "/imu_tf"]
    assert publisher["delay_unmeasurable"] == "not measurable (clock apart by 5.0 h)", publisher
    assert all(a["delay_unmeasurable"] is None for a in said["authorities"] if a["authority"] != "/imu_tf")


def _camera_resending(stamp: int) -> list[Transform]:
    """The camera's odom -> base_link and map -> odom, each stamp sent twice: the second time computed again,
    7e-12 m off (a double's last bits), as the SAIL ZED re-sends."""
    return [_t("map", "odom", stamp, 1.25), _t("map", "odom", stamp, 1.25 + 7e-12), *_camera(stamp)]


def _backwards(findings: list[Finding], child: str) -> list[Finding]:
    return [f for f in findings if f.code == "time_backwards" and f.frames[1] == child]


def test_a_stamp_resent_with_its_value_computed_again_is_an_identical_copy() -> None:
    """ROS 1's tf2 ignores each copy (TF_REPEATED_DATA): a value 7e-12 m off is no update lost."""
    camera = periodic("/camera", 100, _camera_resending)
    (again,) = _backwards(check(recording(healthy(ekf=camera, amcl=[]))).findings, "odom")
    assert "sent 1000 transforms again with a stamp and values it had already sent" in again.message, again.message


def test_repeats_tf2_refuses_as_old_beside_a_clock_ahead_are_not_time_backwards() -> None:
    """The SAIL ZED's re-sent odom -> base_link stamps: once the EKF's sample 5.8 h ahead is in, ROS 1's tf2
    refuses each of the ZED's as too old (TF_OLD_DATA), before it would see a repeat; multiple_authorities says
    that. Its map -> odom, alone on its edge, repeats (TF_REPEATED_DATA)."""
    camera = periodic("/camera", 100, lambda stamp: [*_camera(stamp), *_camera(stamp)], start=0.1)
    ekf = periodic("/ekf", 30, _ekf_moving_with_a_gps_step, stamp=lambda t: t + AHEAD)
    findings = check(recording(healthy(ekf=sorted(camera + ekf, key=lambda m: m.record_time)))).findings
    assert not _backwards(findings, "base_link"), _backwards(findings, "base_link")
    assert _of(findings, "multiple_authorities")


def test_one_sample_on_the_clock_ahead_is_placed_by_its_own_arrival() -> None:
    """The SAIL EKF's first sample read '+0.0 s' (its stamp moved by the median arrival offset) though it arrived
    at +0.1 s: a finding about one sample places it where that sample arrived; the median only places a stamp
    no arrival tells."""
    camera = periodic("/camera", 100, _camera)
    ekf = periodic("/ekf", 30, _ekf_moving_with_a_gps_step, stamp=lambda t: t + AHEAD)
    ekf[0] = dataclasses.replace(ekf[0], record_time=ekf[0].record_time + 300 * MS)  # it arrived 0.3 s late
    rec = recording(healthy(ekf=sorted(camera + ekf, key=lambda m: m.record_time)))
    (future,) = _of(check(rec).findings, "future")
    assert "the first stamped 1700018000.000 (on a clock 5.0 h ahead of the recorder's: +0.3 s)" in future.message
    # no arrival given: by the median, the stamp at the origin
    placed = clocks_apart.placed(rec.timeline, START + AHEAD)
    assert placed is not None and abs(placed[0]) < 0.001 and abs(placed[1] - AHEAD) < 3 * MS, placed
