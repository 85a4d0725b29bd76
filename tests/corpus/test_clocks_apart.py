"""The SAIL vehicle's two clocks (issue 39): a ZED2 on the recorder's clock beside robot_localization's EKF, an
IMU and a u-blox GPS on a machine 5.8 h ahead. Each defect on the real recording that showed it (designed
reproductions: tests/analysis/test_two_clocks_one_edge.py); each skips while its recording awaits placement."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording, load_manifest
from tftools.analysis.report.recording import recording_facts
from tftools.sources.recording import read_recording

_, RECORDINGS = load_manifest()
BY_ID = {r.id: r for r in RECORDINGS}

Corpus = Callable[[Recording], Path]

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
    assert "on a clock 5.8 h ahead of the recorder's: +0." in future["message"], future["message"]
    monitor = tfx("monitor", "-b", corpus(BY_ID[TWO_ODOMETRIES]))
    assert ": 15.882 s from 1653292991.243 to 1653293007.126" in monitor.stdout.splitlines()[0]
    facts = dict(recording_facts(read_recording([corpus(BY_ID[TWO_ODOMETRIES])])))
    assert facts["Clocks"].startswith(
        "tf stamps on the record clock; but part of base_link, imu_link on a clock 5.8 h ahead"
    )


def test_the_imu_waits_at_the_rate_of_the_ekf_on_its_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/imu/data (stamped on the EKF's clock) waits for odom -> base_link, which the ZED (~310 Hz of new stamps)
    and the EKF (30 Hz) both send: the wait is made of the EKF's samples, at 30.0 Hz, not the blend's 341.7 Hz."""
    path = corpus(BY_ID[TWO_ODOMETRIES])
    report = json.loads(tfx("filter", "-b", path, "--format", "json").stdout)
    (imu,) = [t for t in report["topics"] if t["topic"] == "/imu/data"]
    assert imu["late_edge"] == ["odom", "base_link"] and imu["late_rate_hz"] == pytest.approx(30.0, abs=0.2), imu
    (bag,) = json.loads(tfx("wtf", "-b", path, "--format", "json").stdout)["bags"]
    (wait,) = [f for f in bag["findings"] if f["code"] == "sensor_wait"]
    assert "at 30.0 Hz" in wait["message"] and "341.7" not in wait["message"], wait["message"]


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
