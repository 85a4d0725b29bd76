"""What corpus33's recordings showed, fixed on the recording that showed it; the designed reproduction is beside
the code's own tests (tests/analysis/test_wtf_hazards.py)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording, load_manifest

_, RECORDINGS = load_manifest()
BY_ID = {r.id: r for r in RECORDINGS}

Corpus = Callable[[Recording], Path]

JARVIS = "ros1-jarvis-tricycle-agv-real-nav350-reflector-localisation-map-odom-no-callerid-2014-bag"


def test_a_localizers_map_under_odom_is_no_odometry_told_to_stay_continuous(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The Jarvis AGV's NAV350 localizer hangs map_contours_nav under odom, re-sent at 208 Hz and stepping with each
    correction (0.31 m once): the jump's hint said REP 105 wants odom -> base continuous, of a frame that is no
    base; it now says a correction belongs on map -> odom."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[JARVIS]), "--format", "json").stdout)["bags"]
    (finding,) = [f for f in bag["findings"] if f["code"] == "jump"]
    assert finding["frames"][:2] == ["odom", "map_contours_nav"], finding
    assert "publish it as map -> odom" in finding["hint"] and "odom -> base" not in finding["hint"], finding["hint"]
