"""Issue 39's findings that the bytes explain better (brief siblings39), each on the real recording that showed it:
the GrandTour calibration whose one /tf_static message gives a frame two parents, repaired."""

from __future__ import annotations

from pathlib import Path

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.test_issue39 import BY_ID, Corpus, _findings

GTBOX_NEW = "grandtour-calibration-2025-bag"


def test_a_repaired_copy_of_gtbox_changes_box_base_models_parent_as_often_as_the_recording(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """ros1_gtbox_tf_static_metadata_new_0.bag: one /tf_static message (its first message) sends box_base_model
    under stim320_imu and then under box_base. Its repaired copy repeated that message ahead of itself: 'it changed
    parent 3 times' where the recording says 1. The copy now says 1, ends under box_base as the recording does,
    and lists the 36 static transforms tf2 holds (the message's 37 less the one it loses)."""
    bag = corpus(BY_ID[GTBOX_NEW])
    copy = tmp_path / "repaired.bag"
    said = tfx("static", "--repair", "-b", bag, "-o", copy)
    assert said.code == 0 and "with its 36 static transforms" in said.stdout, said.stdout
    assert "stim320_imu -> box_base_model" not in said.stdout
    for path in (bag, copy):
        (parents,) = [f for f in _findings(tfx, path)[2] if f["code"] == "multiple_parents"]
        assert parents["count"] == 1 and parents["frames"] == ["box_base_model", "stim320_imu", "box_base"], parents
        assert "it changed parent 1 time" in parents["message"] and "is now under box_base" in parents["message"]
