"""A localizer's own map hung under odom, where odom has its parent already (issue 39's hints that point the wrong
way): Jarvis, a real AGV (tests/corpus/test_rules46.py), sends map -> odom at 8 Hz and its laser localizer's
odom -> map_contours_nav, a leaf re-sent at 208 Hz holding each value between steps. ``jump`` warned of its steps
with the hint "publish corrections as map -> odom", which the recording already does. Its steps are its
localizer's corrections, as map -> odom's are: a ``map_corrections`` note. A leaf under odom that moves sample
after sample and steps once is still a ``jump``, whose hint no longer asks for the map -> odom sent already."""

from __future__ import annotations

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START, SECONDS = scenes.START, scenes.SECONDS


def _held_map(stamp: int) -> list[Transform]:
    """odom -> local_map, corrected every 0.5 s (0.2 m and 2 degrees back and forth), held in between."""
    update = int((stamp - START) / NS_PER_S / 0.5)
    return [scenes._t("odom", "local_map", stamp, 3.0 + 0.2 * (update % 2), 0.035 * (update % 2))]


def _drifting_leaf(stamp: int) -> list[Transform]:
    """odom -> goal, moving 1 mm a sample, stepping 0.5 m once half way."""
    seconds = (stamp - START) / NS_PER_S
    return [scenes._t("odom", "goal", stamp, 2.0 + 0.01 * seconds + (0.5 if seconds >= SECONDS / 2 else 0.0))]


def _robot(leaf: scenes.Make) -> list[TfMessage]:
    return scenes.with_extra(
        scenes.periodic("/localizer", 100, leaf),
        amcl=scenes.periodic("/amcl", 8, scenes.map_odom),
    )


def _codes(findings: list[Finding]) -> dict[str, list[Finding]]:
    found: dict[str, list[Finding]] = {}
    for f in findings:
        found.setdefault(f.code, []).append(f)
    return found


def test_a_localizer_s_map_under_odom_steps_by_corrections_not_jumps() -> None:
    found = _codes(check(scenes.recording(_robot(_held_map))))
    assert "jump" not in found, [f.message for f in found["jump"]]
    (note,) = [f for f in found["map_corrections"] if f.frames == ("odom", "local_map")]
    assert (
        "odom -> local_map by /localizer: it holds its value between steps (it changed value 19 times in 1,000 "
        "samples) and no frame hangs under it, while odom has its parent already (map -> odom): a localizer's own map "
        "under odom, it seems; it was corrected 19 times"
    ) in note.message, note.message
    assert note.hint.startswith("nothing to fix: REP 105 lets a localizer's map step") and "map -> odom" in note.hint


def test_a_leaf_under_odom_that_moves_and_steps_still_jumps_without_asking_for_map_to_odom_again() -> None:
    found = _codes(check(scenes.recording(_robot(_drifting_leaf))))
    (jumped,) = [f for f in found["jump"] if f.frames == ("odom", "goal")]
    assert "publish it as map -> odom" not in jumped.hint
    assert "map -> odom is sent already, so if it corrects where goal lies, send goal under map" in jumped.hint
