"""What corpus43b's recordings showed (ROS 2 recordings of kinds the corpus lacked), fixed on the recording that showed
it; the designed reproductions are beside the code's own tests (tests/analysis/test_out_of_order_localizer.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

CART = "ros2-thesis-cart-real-ros2-control-odometry-0-9-hz-amcl-post-dated-out-of-order-2026-db3"


def test_amcl_sending_queued_scans_out_of_order_is_one_publisher_out_of_order(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The cart's odometry comes at 0.9 Hz; amcl waits for it, then sends map -> odom for each queued scan at once,
    in no order (six in a row stamped ever earlier). tfx said 'several broadcasters taking turns, it seems' (an error:
    'up to 69.8 mm and 13.34° apart') and 'publishes irregularly ... the 1.0 s it keeps up'; the stamps are one
    publisher's, out of order, following the scans' steady cycle. Now time_backwards says so, and what follows."""
    code, findings = _findings(tfx, corpus(BY_ID[CART]))
    assert not [f for f in findings if f["code"] in ("multiple_authorities", "rate")], findings
    (backwards,) = [f for f in findings if f["code"] == "time_backwards"]
    assert backwards["severity"] == "warning" and backwards["frames"] == ["map", "odom"]
    assert backwards["message"].startswith(
        "map -> odom on /tf: 174 transforms arrived out of order, stamped up to 0.787 s before one already received"
    ), backwards["message"]
    assert (
        "; 5 of them carry another value than the one already stamped after them (up to 0.075 m and 2.2°)"
        in (backwards["message"])
    )
    (wait,) = [f for f in findings if f["code"] == "sensor_wait"]
    assert "for odom -> base_link" in wait["message"] and "at 0.9 Hz" in wait["message"], wait["message"]
    assert code == 1


@pytest.mark.parametrize("command", ["view-frames", "report"])
def test_the_cart_s_pictures_pin_what_wtf_says(corpus: Corpus, tfx: Tfx, tmp_path: Path, command: str) -> None:  # noqa: F811
    """view-frames and report count the findings wtf makes: one error (future), two warnings, one note."""
    out = tmp_path / ("tree.svg" if command == "view-frames" else "page.html")
    result = tfx(command, "-b", corpus(BY_ID[CART]), "-o", out)
    assert "1 error, 2 warnings, 1 note" in result.stdout + result.stderr, result.stdout + result.stderr
