"""``tfx wtf --init`` writes only tree files that ``--expect`` reads back: YAML is parsed within a number of lines
and items, so a recording of more frames is refused in one line (100,000 frames took ruamel 169 s to write)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.bags import BagFormat, TfMessage, write_bag
from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tftools.cli import expected
from tftools.core.transform import Transform

T0 = 1_700_000_000 * 10**9


def test_a_recording_of_more_frames_than_a_tree_file_holds_is_refused_in_one_line(
    tfx: Tfx, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(expected, "MAX_INIT_FRAMES", 5)
    result = tfx("wtf", "--init", SAMPLE_BAGS["ros1"])
    assert result.code == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1, result.stderr
    assert "frames, more than the 5 of a tree file that --expect reads back" in result.stderr
    assert "tfx diff good.bag new.bag" in result.stderr


@pytest.mark.slow  # ruamel writes and parses 5,000 frames in ~20 s of CPU
def test_the_largest_tree_init_writes_is_read_back_by_expect(tfx: Tfx, tmp_path: Path) -> None:
    frames = expected.MAX_INIT_FRAMES - 2  # with odom and base_link
    statics = [Transform((0.1, 0.2, 0.3), (0, 0, 0.6, 0.8), T0, "base_link", f"sensor_{k}") for k in range(frames)]
    stamps = [T0 + k * 10**8 for k in range(50)]
    moving = [TfMessage("/tf", t, [Transform((t * 1e-9, 0, 0), (0, 0, 0, 1), t, "odom", "base_link")]) for t in stamps]
    bag = write_bag(tmp_path / "many", [TfMessage("/tf_static", T0, statics), *moving], BagFormat.rosbag2_mcap)
    written = tfx("wtf", "--init", bag)
    assert written.code == 0, written.stderr
    tree = tmp_path / "tree.yaml"
    tree.write_text(written.stdout)
    checked = tfx("wtf", "--expect", tree, bag)
    assert checked.code == 0, checked.stderr
    assert "cannot be read" not in checked.stderr
