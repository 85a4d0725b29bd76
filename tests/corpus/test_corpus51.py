"""What round 51's scouts found on recordings nobody here had seen (a real Pioneer P3-DX's p2os odometry whose link
to the recorder stalled twice; e-Yantra's Sahayak Bot and Agri Bot in Gazebo), fixed on the recording that showed
it; the designed reproductions are beside the code's own tests (tests/analysis/test_delay_stalls.py, test_wtf.py,
test_detections.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

TWO_STALLS = "ros1-pioneer-p2os-teleop-two-link-stalls-2025-bag"
SAHAYAK = "ros1-eyrc-sahayak-ur5-gazebo-stamps-off-their-places-2021-bag"
AGRIBOT = "ros1-eyrc-agribot-gazebo-detections-named-by-list-place-2021-bag"
ARM = ("base_link", "shoulder_link")


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


def test_one_steady_source_stamped_off_its_places_arriving_in_batches_has_no_rate(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Sahayak Bot's 12 joints, every 20 ms with one sample in six 13 ms early, recorded off a stepped simulated
    clock: 'comes in batches' with /joint_states' two sources blamed, on every edge."""
    assert not _findings(tfx, corpus(BY_ID[SAHAYAK]), "rate")


def test_detections_unseen_together_are_no_stall_and_two_joint_sources_still_told(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Agri Bot's detector names its tomatoes obj0..obj43 by their place in a list: 16 stalls were told of them
    ('look for what these publishers share') while the detector went on. Its arm's joints, fed by two /joint_states
    sources, are still told so."""
    bag = corpus(BY_ID[AGRIBOT])
    assert not _findings(tfx, bag, "stall")
    arm = [f for f in _findings(tfx, bag, "rate") if tuple(f["frames"]) == ARM]
    assert arm and "publishes irregularly" in arm[0]["message"], arm


def test_a_detection_sent_at_its_cameras_origin_is_told_so_on_the_agribot(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """1984 of the detector's 3215 transforms put the tomato exactly at camera_link2's origin; obj2's jumps were told
    as another object taken for it or a bad depth reading, the zeros unsaid."""
    jumps = {f["frames"][-1]: f for f in _findings(tfx, corpus(BY_ID[AGRIBOT]), "jump")}
    said = "; 188 of its 293 transforms exactly at camera_link2's origin (0, 0, 0), stepping there or back 33 times"
    assert jumps["obj2"]["message"].endswith(said), jumps["obj2"]["message"]
    assert jumps["obj2"]["hint"].startswith("a detector sending its camera's origin where it found nothing")
