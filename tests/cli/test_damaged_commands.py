"""Every command on damaged copies of real recordings (made in tmp_path, never in the corpus): each says the damage
in one line, uses what is readable, and does not report a stretch the file lost as the robot's silence."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import shared_dir
from tests.sources.bag.damaged import copied, cut, record_time_moved, zeroed_pages
from tests.sources.bag.damaged import overwritten as _overwritten

UWB = "uwb-slam-Record_2017-11-17-12-31-28.bag"  # ROS 1, 27 lz4 chunks, a Robotino's odometry and wheels


def _original(name: str) -> Path:
    """The corpus recording itself, read as it is (tfx writes nothing beside what it reads)."""
    return shared_dir() / "corpus" / name


def _json(tfx: Tfx, *args: str | Path) -> Any:  # noqa: F811
    result = tfx(*args, "--format", "json")
    assert result.stdout.strip(), result.stderr
    return json.loads(result.stdout)


def test_wtf_puts_the_pauses_a_damaged_chunk_makes_under_the_damage(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """The Robotino's bag with 16 bytes overwritten inside an lz4 chunk (446 messages lost of it): wtf warned of a
    stall ('the recorder received no transform on /tf for 2.1 s: everything on /tf stopped at once') and of 4 edges
    going silent, as if the robot had; now they are said beneath the damage, which explains them."""
    bag = copied(UWB, tmp_path)
    _overwritten(bag, 0.45)
    (report,) = _json(tfx, "wtf", "-b", bag)["bags"]
    findings = report["findings"]
    (damage,) = [f for f in findings if f["code"] == "bag_problem"]
    assert damage["key"] and "lz4 data damaged" in damage["message"]
    beneath = [f for f in findings if f["code"] in ("stall", "rate")]
    assert len(beneath) == 5 and all(f["cause"] == damage["key"] for f in beneath), beneath
    assert not [f for f in findings if not f["cause"] and f["code"] in ("stall", "rate")]
    healthy = _json(tfx, "wtf", "-b", _original(UWB))["bags"][0]["findings"]
    assert not [f for f in healthy if f["code"] in ("bag_problem", "stall", "rate")]


def test_monitor_says_a_gap_the_file_lost_is_not_a_pause(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """The same damaged bag: monitor's largest gaps (2.13 to 2.17 s, the robot publishing at 15-30 Hz) fall where
    the lz4 chunk was damaged; each is said so, in the text and in JSON (``gap_in_damage``)."""
    bag = copied(UWB, tmp_path)
    _overwritten(bag, 0.45)
    edges = {(e["parent"], e["child"]): e for e in _json(tfx, "monitor", "-b", bag)["edges"]}
    moving = {key for key, e in edges.items() if not e["static"]}
    assert {key for key, e in edges.items() if e["gap_in_damage"]} == moving and len(moving) == 4
    assert all(2.0 < edges[key]["gap_max_s"] < 2.3 for key in moving)
    text = tfx("monitor", "-b", bag)
    assert text.stdout.count("spans a damaged part of the file: transforms lost there, not a pause") == 4
    whole = _json(tfx, "monitor", "-b", _original(UWB))["edges"]
    assert not any(e["gap_in_damage"] for e in whole)


def test_a_pause_beside_a_lost_stretch_keeps_its_own_finding_and_says_where_the_file_lost(
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The Nav2 TurtleBot 4 written again with lz4 chunks (simulated time, no /clock), 16 bytes overwritten at 45%:
    20.8 s of its tf lost with the chunk's end, beside the simulation's own 1.5-2.3 s stall at +40.8 s. The stall
    check says both as one finding ('2 times'): it stays on its own (the real stall is not put down to the damage)
    and says where the file lost its transforms; each edge's rate finding too; monitor says each largest gap is the
    file's (before: 'for 1.5 s to 20.8 s ... everything on /tf stopped at once', not a word of the damage)."""
    from mcap.writer import CompressionType

    from tests.corpus.variants import rewrite_mcap

    bag = rewrite_mcap(
        copied("ros2_mcap_nav2_turtlebot4.mcap", tmp_path), tmp_path / "lz4.mcap", compression=CompressionType.LZ4
    )
    _overwritten(bag, 0.45)
    findings = _json(tfx, "wtf", "-b", bag)["bags"][0]["findings"]
    (stall,) = [f for f in findings if f["code"] == "stall"]
    assert not stall["cause"] and "2 times" in stall["message"]
    said = "(the file is damaged there: its transforms from 977.022 (+48.2 s) to 997.740 (+68.9 s) were lost)"
    assert stall["message"].endswith(said)
    rates = [f for f in findings if f["code"] == "rate"]
    assert len(rates) == 4 and all(f["message"].endswith(said) for f in rates)
    edges = _json(tfx, "monitor", "-b", bag)["edges"]
    assert sorted(e["child"] for e in edges if e["gap_in_damage"]) == ["base_link", "left_wheel", "odom", "right_wheel"]


@pytest.mark.parametrize("summary", [True, False])
def test_diff_says_a_difference_the_damage_made_in_its_output(
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
    summary: bool,
) -> None:
    """The Nav2 TurtleBot 4 in lz4 chunks against its copy with 16 bytes overwritten at 45% (read through its
    summary, or cut before it and read record by record): each edge's rate is 22% lower in the copy, the 20.8 s
    its damaged chunk lost counted as silence (3 differences: the two wheels, sent in one message, said as one).
    Before, only stderr said the copy was damaged, and the rate differences read as the robot's; now each says so,
    in the text and in JSON (``damage``, ``b_damaged``)."""
    from mcap.writer import CompressionType

    from tests.corpus.variants import rewrite_mcap

    intact = rewrite_mcap(
        copied("ros2_mcap_nav2_turtlebot4.mcap", tmp_path), tmp_path / "lz4.mcap", compression=CompressionType.LZ4
    )
    damaged = tmp_path / "damaged.mcap"
    damaged.write_bytes(intact.read_bytes())
    _overwritten(damaged, 0.45)
    if not summary:
        cut(damaged, int(damaged.stat().st_size * 0.97))
    found = _json(tfx, "diff", intact, damaged)
    assert found["a_damaged"] is None and "is damaged (lz4 chunk cannot be decompressed whole" in found["b_damaged"]
    rates = [d for d in found["differences"] if d["change"] == "rate"]
    assert len(rates) == 3 and len(found["differences"]) == 3  # the two wheels, sent in one message, said once
    assert [d["said_with"] for d in rates if d["said_with"]] == [["right_wheel"]]
    lost = re.compile(r"^B is damaged: its transforms from 48\.\d s to 69\.\d s into it were lost; the transforms lost")
    assert all(lost.match(d["damage"]) for d in rates), rates
    text = tfx("diff", intact, damaged).stdout
    assert (
        text.count("(B is damaged: its transforms from 48.") == 3
        and "read only in part, compared as far as it could be read: " in text
    )
    swapped = _json(tfx, "diff", damaged, intact)
    assert all(d["damage"].startswith("A is damaged: ") for d in swapped["differences"]) and swapped["a_damaged"]
    same = _json(tfx, "diff", intact, intact)
    assert (same["a_damaged"], same["b_damaged"], same["differences"]) == (None, None, [])


def _cut_at(share: float) -> Callable[[Path], None]:
    def damage(path: Path) -> None:
        cut(path, int(path.stat().st_size * share))

    return damage


def _flipped_at(share: float) -> Callable[[Path], None]:
    return lambda path: _overwritten(path, share)


def _flipped_and_cut(share: float, kept: float) -> Callable[[Path], None]:
    """Overwritten at ``share``, then cut to ``kept`` of its size: before its index or summary."""

    def damage(path: Path) -> None:
        _overwritten(path, share)
        cut(path, int(path.stat().st_size * kept))

    return damage


def _recorded_at(to: Callable[[int], int]) -> Callable[[Path], None]:
    """The middle /tf message recorded at ``to(its record time)``: decades from the rest."""

    def damage(path: Path) -> None:
        record_time_moved(path, to)

    return damage


_YEARS_50 = 50 * 365 * 86_400 * 1_000_000_000

#: A real recording of each format and a damage to its copy (of its one data file, in a bag directory).
DAMAGED: dict[str, tuple[str, Callable[[Path], None]]] = {
    "ros1 plain, cut": ("ros1_car_path_follower.bag", _cut_at(0.6)),
    "ros1 bz2, cut": ("ros1_sail_zed_revalued_stamps_2022.bag", _cut_at(0.6)),
    "ros1 bz2, overwritten": ("ros1_sail_zed_revalued_stamps_2022.bag", _flipped_at(0.45)),
    "ros1 lz4, overwritten": (UWB, _flipped_at(0.45)),
    "db3, cut": ("ros2_db3_tb3_gazebo_walker", _cut_at(0.6)),
    "mcap zstd, overwritten": ("ros2_mcap_nav2_turtlebot4.mcap", _flipped_at(0.45)),
    "mcap zstd, cut": ("ros2_mcap_nav2_turtlebot4.mcap", _cut_at(0.6)),
    "mcap uncompressed, cut": ("ros2_mcap_coug_auv_replayed", _cut_at(0.6)),
    "ros1 lz4, overwritten, no index": (UWB, _flipped_and_cut(0.45, 0.97)),
    "mcap zstd, overwritten, no summary": ("ros2_mcap_nav2_turtlebot4.mcap", _flipped_and_cut(0.45, 0.97)),
    "db3, pages zeroed": ("ros2_db3_tb3_gazebo_walker", lambda path: zeroed_pages(path, 0.45)),
    "db3, a record time 50 years on": ("ros2_db3_tb3_gazebo_walker", _recorded_at(lambda t: t + _YEARS_50)),
    "mcap zstd, a record time of the last int64": ("ros2_mcap_nav2_turtlebot4.mcap", _recorded_at(lambda t: 2**63 - 1)),
    # a u64 past the int64s: static --repair said 'OUT: cannot be written (OverflowError ...)', blaming its output
    "mcap zstd, a record time of 2**63": ("ros2_mcap_nav2_turtlebot4.mcap", _recorded_at(lambda t: 2**63)),
    "ros1, a record time in 2106": (UWB, _recorded_at(lambda t: 0xFFFFFFFF * 1_000_000_000)),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", list(DAMAGED))
def test_every_command_on_a_damaged_copy_says_so_and_reads_the_rest(
    case: str,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """frames, wtf, monitor, view-frames, report, filter, echo, diff (against the intact recording) and static
    --repair (a copy: written whole or not at all) on the damaged copy: each exits 0, 1 or 2 (a damaged file is
    never taken for a healthy one's verdict alone), with no traceback, and says the damage: on stdout (wtf,
    report's page, diff) or as a warning on stderr."""
    name, damage = DAMAGED[case]
    original = _original(name)
    bag = copied(name, tmp_path)
    damage(next(p for p in sorted(bag.iterdir()) if p.suffix in (".db3", ".mcap")) if bag.is_dir() else bag)
    repaired = tmp_path / f"repaired{bag.suffix}"
    frames = _json(tfx, "frames", "-b", bag)
    moving = [(f["parent"], f["frame"]) for f in frames["frames"] if f["parent"] and not f["static"]]
    runs = {
        "wtf": tfx("wtf", "-b", bag),
        "monitor": tfx("monitor", "-b", bag),
        "view-frames": tfx("view-frames", "-b", bag, "-o", tmp_path / "f.dot"),
        "report": tfx("report", "-b", bag, "-o", tmp_path / "r.html"),
        "filter": tfx("filter", "-b", bag),
        "diff": tfx("diff", original, bag),
        "echo": tfx("echo", *moving[0], "-b", bag, "--at", "+1"),
        "static": tfx("static", "--repair", "-b", bag, "-o", repaired),
    }
    assert runs["static"].code in (0, 2) and (runs["static"].code == 0) == repaired.exists()  # no half copy
    said = ("damaged", "cut short", "truncated", "lost")
    for command, result in runs.items():
        assert result.code in (0, 1, 2), f"{command}: exit {result.code}"
        assert "Traceback" not in result.stderr and "internal error" not in result.stderr, f"{command}: {result.stderr}"
        shown = result.stdout + result.stderr
        if command == "report":
            shown += (tmp_path / "r.html").read_text()
        assert any(word in shown for word in said), f"{command} did not say the damage: {shown[:2000]}"
