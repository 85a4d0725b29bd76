"""What round 51's scouts found on recordings nobody here had seen (a real Pioneer P3-DX's p2os odometry whose link
to the recorder stalled twice), fixed on the recording that showed it; the designed reproductions are beside the
code's own tests (tests/analysis/test_delay_stalls.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

TWO_STALLS = "ros1-pioneer-p2os-teleop-two-link-stalls-2025-bag"


def _findings(tfx: Tfx, path: Path, code: str) -> list[dict[str, Any]]:  # noqa: F811
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    return [f for f in bag["findings"] if f["code"] == code]


def test_both_stalls_of_the_pioneers_link_are_told_and_timed_on_arrival(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Nothing recorded for 12.3 s, then for 7.7 s, the stamps going on: only the longest was told, and the JSON's
    first_time was the stamp (1747072687.865) of the transform whose arrival the text said (1747072700.125)."""
    (late,) = _findings(tfx, corpus(BY_ID[TWO_STALLS]), "delay")
    assert "196 of 1457 transforms more than 0.2 s after their stamp" in late["message"], late["message"]
    assert (
        "none arrived for 12.3 s from 1747072687.808 (+96.1 s) and for 7.7 s from 1747072718.021 (+126.3 s) while "
        "its stamps went on" in late["message"]
    ), late["message"]
    assert "first at 1747072700.125" in late["message"] and round(late["first_time"], 3) == 1747072700.125, late
