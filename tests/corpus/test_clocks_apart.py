"""The SAIL vehicle's two clocks (issue 39): a ZED2 on the recorder's clock beside robot_localization's EKF, an
IMU and a u-blox GPS on a machine 5.8 h ahead. Each defect on the real recording that showed it (designed
reproductions: tests/analysis/test_two_clocks_one_edge.py); each skips while its recording awaits placement."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tftools.analysis.report.recording import recording_facts
from tftools.sources.recording import read_recording

TWO_ODOMETRIES = "ros1-sail-zed-ekf-gps-two-odometries-2022-bag"
REVALUED = "ros1-sail-zed-revalued-stamps-2022-bag"


def test_every_time_a_finding_says_is_placed_on_the_recorders_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """'+20881.5 s' into a 15.8 s recording: the EKF's clock taken for the recorder's. Every '+S' now lies
    within the recording, and a stamp on the EKF's clock says so."""
    result = tfx("wtf", "-b", corpus(BY_ID[TWO_ODOMETRIES]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    for finding in bag["findings"]:
        for said in re.findall(r"[+-](\d+\.\d) s\b", finding["message"]):
            assert float(said) <= 16.0, finding["message"]
    (future,) = [f for f in bag["findings"] if f["code"] == "future" and "/ekf_se" in f["message"]]
    # its first sample arrived 0.091 s after the ZED's first stamp (20,881.415 s before its own stamp, where the
    # EKF's median is 20,881.49 s): placed where it arrived, not '+0.0 s' by the median
    assert "the first stamped 1653313872.750 (on a clock 5.8 h ahead of the recorder's: +0.1 s)" in future["message"]
    monitor = tfx("monitor", "-b", corpus(BY_ID[TWO_ODOMETRIES]))
    assert ": tf stamped over 15.882 s from 1653292991.243 to 1653293007.126" in monitor.stdout.splitlines()[0]
    facts = dict(recording_facts(read_recording([corpus(BY_ID[TWO_ODOMETRIES])])))
    assert facts["Clocks"].startswith(
        "tf stamps on the record clock; but part of base_link, imu_link on a clock 5.8 h ahead"
    )


def test_the_imu_waits_at_the_rate_of_the_ekf_on_its_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/imu/data (stamped on the EKF's clock) waits for odom -> base_link, which the ZED (~310 Hz of new stamps)
    and the EKF (30 Hz) both send: the wait is made of the EKF's samples, at 30.0 Hz, not the blend's 341.7 Hz.
    monitor shows the blend as the edge's rate: the finding said "at 30.0 Hz" of the same edge, unnamed; now it
    says which clock its figure is on, and the blend's beside it, the very number monitor shows."""
    path = corpus(BY_ID[TWO_ODOMETRIES])
    report = json.loads(tfx("filter", "-b", path, "--format", "json").stdout)
    (imu,) = [t for t in report["topics"] if t["topic"] == "/imu/data"]
    assert imu["late_edge"] == ["odom", "base_link"] and imu["late_rate_hz"] == pytest.approx(30.0, abs=0.2), imu
    (bag,) = json.loads(tfx("wtf", "-b", path, "--format", "json").stdout)["bags"]
    (wait,) = [f for f in bag["findings"] if f["code"] == "sensor_wait"]
    # the two rates of the one edge are said as two figures, each with its name: monitor shows the blend's
    assert "at 30.0 Hz on the messages' clock (341.7 Hz over all its clocks, as monitor counts it)" in wait["message"]
    assert imu["late_rate_all_hz"] == pytest.approx(341.7, abs=0.1), imu
    (edge,) = [
        e for e in json.loads(tfx("monitor", "-b", path, "-f", "json").stdout)["edges"] if e["child"] == "base_link"
    ]
    assert edge["rate_hz"] == pytest.approx(imu["late_rate_all_hz"]), edge


def test_a_gps_on_a_clock_hours_ahead_is_told_to_sync_clocks(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Every /ublox/fix is stamped 5.8 h ahead of the ZED's odom -> base_link: 'keep the tf it waits for
    publishing' was wrong (it publishes throughout); no wait or cache helps, one clock does."""
    path = corpus(BY_ID[REVALUED])
    report = json.loads(tfx("filter", "-b", path, "--format", "json").stdout)
    (fix,) = [t for t in report["topics"] if t["topic"] == "/ublox/fix"]
    assert fix["clock_apart_s"] == pytest.approx(20881.45, abs=0.1), fix
    text = " ".join(tfx("filter", "-b", path).stdout.split())
    assert "it is stamped 5.8 h ahead of tf's clock: sync the machines' clocks (chrony/NTP)" in text, text
    assert "keep the tf it waits for publishing" not in text
    (bag,) = json.loads(tfx("wtf", "-b", path, "--format", "json").stdout)["bags"]
    (lost,) = [f for f in bag["findings"] if f["code"] == "sensor_lost"]
    assert "all stamped 5.8 h ahead of odom -> base_link's samples" in lost["message"], lost["message"]
    assert "which stopped before reaching their stamps" not in lost["message"] and "chrony/NTP" in lost["hint"]


def test_a_delay_across_the_two_clocks_is_not_measurable_in_every_command(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """monitor showed 'Average Delay -20881.49 s' for imu_link, /ekf_se and /tf_broadcaster_imu: their stamps on
    the EKF machine's clock minus arrivals on the recorder's. Now monitor (text, JSON), report and view-frames
    say the delay is not measurable, the clocks 5.8 h apart; the ZED's edges keep their 19 ms."""
    path = corpus(BY_ID[TWO_ODOMETRIES])
    said = "not measurable (clock apart by 5.8 h)"
    text = tfx("monitor", "-b", path).stdout
    assert "-20881" not in text and text.count(said) == 3, text
    report = json.loads(tfx("monitor", "-b", path, "--format", "json").stdout)
    edges = {e["child"]: e for e in report["edges"]}
    assert edges["imu_link"]["delay_mean_s"] is None and edges["imu_link"]["delay_unmeasurable"] == said
    assert edges["odom"]["delay_mean_s"] == pytest.approx(0.019, abs=0.001) and not edges["odom"]["delay_unmeasurable"]
    ahead = {a["authority"] for a in report["authorities"] if a["delay_unmeasurable"] == said}
    assert ahead == {"/ekf_se", "/tf_broadcaster_imu"}, report["authorities"]
    tfx("report", path, "-o", tmp_path / "sail.html")
    assert f"delay {said}" in (tmp_path / "sail.html").read_text(), "report"
    tfx("view-frames", "-b", path, "-f", "dot", "-o", tmp_path / "sail.gv")
    assert f"Delay: {said}" in (tmp_path / "sail.gv").read_text(), "view-frames"


def test_time_backwards_is_the_repeats_ros1s_tf2_logs_as_repeated(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """ROS 1's tf2 fed the bag's /tf ignores 3,014 of the ZED's map -> odom samples (TF_REPEATED_DATA), 126 of
    them 7e-12 off their first value; on odom -> base_link it refuses the ZED's as old (TF_OLD_DATA), the EKF's
    stamps being 5.8 h newer. tfx said 132 + 126 'updates lost' and 2,882 + 2,888 copies, on both edges."""
    (bag,) = json.loads(tfx("wtf", "-b", corpus(BY_ID[TWO_ODOMETRIES]), "--format", "json").stdout)["bags"]
    (again,) = [f for f in bag["findings"] if f["code"] == "time_backwards"]
    assert again["message"].startswith(
        "map -> odom by /zed2_left/zed_node_left sent 3014 transforms again with a stamp and values it had already"
    ), again["message"]
    # tf2 logs each at WARN level ('Warning: TF_REPEATED_DATA') and answers every lookup as before: a warning, as
    # tf2 says it; it was an error, though nothing is lost (exit 1 stays: the EKF's stamps ahead are)
    assert again["severity"] == "warning", again


def test_repeats_with_other_values_are_counted_per_row_tf2_refuses(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The second SAIL bag: ROS 1's tf2 refuses all 17,659 re-sent stamps per edge (TF_REPEATED_DATA), keeping each
    stamp's first value; 703 (odom -> base_link) and 714 (map -> odom) of the refused rows carry another value, on
    650 and 659 stamps (the manifest said 650 and 659 re-sends): those rows' updates are lost (an error), the other
    16,956 and 16,945 repeat the value tf2 kept (a warning: its log floods)."""
    (bag,) = json.loads(tfx("wtf", "-b", corpus(BY_ID[REVALUED]), "--format", "json").stdout)["bags"]
    said = {(f["severity"], f["frames"][1]): f["message"] for f in bag["findings"] if f["code"] == "time_backwards"}
    assert set(said) == {(s, c) for s in ("error", "warning") for c in ("odom", "base_link")}, said
    assert "odom by /zed2_left/zed_node_left sent 714 transforms with a stamp" in said["error", "odom"]
    assert "(659 stamps)" in said["error", "odom"]
    assert "sent 703 transforms with a stamp" in said["error", "base_link"]
    assert "(650 stamps)" in said["error", "base_link"]
    assert "sent 16945 transforms again with a stamp and values" in said["warning", "odom"]
    assert "sent 16956 transforms again with a stamp and values" in said["warning", "base_link"]


def test_the_ekfs_gps_steps_are_counted_as_the_bytes_hold_them(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/ekf_se's odom -> base_link steps 0.98-5.10 m 13 times (each right after an /odometry/gps message; six of
    them 3.8-5.1 m), moving 4.3 cm a sample otherwise: 13 jumps, the largest 5.098 m."""
    (bag,) = json.loads(tfx("wtf", "-b", corpus(BY_ID[TWO_ODOMETRIES]), "--format", "json").stdout)["bags"]
    (jump,) = [f for f in bag["findings"] if f["code"] == "jump"]
    assert "by /ekf_se jumped 13 times" in jump["message"] and "the largest 5.098 m" in jump["message"], jump
