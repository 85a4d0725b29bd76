"""What corpus35's recordings showed (three students' own disc-robot simulators, Texas A&M CSCE 452, 2023), fixed
on the recording that showed it; the designed reproductions are beside the code's own tests
(tests/analysis/test_wtf.py, tests/analysis/test_wtf_one_link_description.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

PAUSES = "ros2-csce452-disc-robot-own-simulator-tf-pauses-while-scanning-two-static-laser-publishers-2023-db3"
ONE_LINK = "ros2-csce452-disc-robot-own-simulator-scan-frame-never-on-tf-rsp-empty-tf-static-2023-db3"


def _findings(tfx: Tfx, path: Path) -> tuple[int, list[dict[str, Any]]]:  # noqa: F811
    result = tfx("wtf", path, "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    return result.code, bag["findings"]


def test_a_simulator_pausing_once_a_second_is_said_as_runs_and_pauses(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """world -> base_link comes every 0.100 s but stops for 0.62-0.70 s once a second while the simulator
    computes its scan: rate said '81% of its intervals are more than 50% off the 0.637 s it keeps up most of the
    time', the pauses named its rhythm. Now its runs and its 27 pauses, about one a second."""
    code, findings = _findings(tfx, corpus(BY_ID[PAUSES]))
    (rate,) = [f for f in findings if f["code"] == "rate"]
    assert rate["message"] == (
        "world -> base_link on /tf publishes irregularly: every 0.100 s in runs, broken 27 times by pauses of "
        "0.616 s to 0.702 s, about one every 1.000 s (64% of its time)"
    ), rate["message"]
    assert "0.702 s" in rate["hint"] and rate["severity"] == "warning"
    assert code == 0


def test_a_scan_frame_the_one_link_urdf_lacks_is_the_urdf_s_not_a_publisher_that_did_not_run(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The URDF recorded holds base_link alone: robot_state_publisher's one /tf_static message is empty and the
    scans are in 'laser'. The hint said the static publishers 'sent nothing while recorded; check that they ran'
    and silent_tf warned '1 of 1 messages on /tf_static carry no transform (0 transforms in the others)' of a
    publisher 'misconfigured'; both now name the description."""
    code, findings = _findings(tfx, corpus(BY_ID[ONE_LINK]))
    (frame,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert "the recorded /robot_description has no link 'laser' (its links: base_link)" in frame["hint"]
    assert "check that they ran" not in frame["hint"]
    (silent,) = [f for f in findings if f["code"] == "silent_tf"]
    assert silent["message"].endswith(": its only message on /tf_static carries no transform"), silent["message"]
    assert silent["severity"] == "info" and "misconfigured" not in silent["hint"], silent
    assert code == 1
