"""``tfx wtf --watch``: what it refuses, before listening to anything."""

from __future__ import annotations

from pathlib import Path

from tests.bags import TfMessage, write_bag
from tests.cli.conftest import Tfx
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform


def test_watch_is_for_a_live_system(tfx: Tfx, tmp_path: Path) -> None:
    stamp = 1_700_000_000 * NS_PER_S
    bag = write_bag(
        tmp_path / "a.bag", [TfMessage("/tf", stamp, [Transform(stamp=stamp, frame_id="a", child_frame_id="b")])]
    )
    result = tfx("wtf", bag, "--watch")
    assert result.code == 2 and "--watch listens to a live system" in result.stderr
    result = tfx("wtf", "--watch", "--window", "0")
    assert result.code == 2 and "--window" in result.stderr
    result = tfx("wtf", "--watch", "-f", "json")
    assert result.code == 2 and "--watch says its changes as text lines" in result.stderr
