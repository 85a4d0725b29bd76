"""Two robots whose nodes send the same frame names (issue 39): each drone runs MAVROS in its own namespace
(/uav_2/mavros, /uav_3/mavros), and each sends fcu -> lidarlite_laser without a robot prefix, attached to
neither drone's frames; the drones' clocks 2.3 s behind the recorder's, and a WiFi outage holding every sample
back for 12 s. First on a designed bag, then on the real one (3d-SWAP's flight of 2017: tests/corpus/
test_corpus46.py)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check
from tftools.analysis.wtf.robots import robots_of
from tftools.sources.recording import read_recording

MS = scenes.MS
START = scenes.START
BEHIND = 2300 * MS  # the drones' clocks behind the recorder's
OUTAGE = (15_000 * MS, 27_000 * MS)  # nothing received meanwhile; then the backlog, 50 ms apart
SECONDS = 40


def _arrival(sent: int) -> int:
    """When a sample sent at ``sent`` (recorder's time) arrived: at once before the outage; after it, in order,
    those held back first, 20 times faster than they were sent, until the link caught up."""
    begin, end = START + OUTAGE[0], START + OUTAGE[1]
    return sent if sent < begin else max(sent, end + (sent - begin) // 20)


def _at_once(sent: int) -> int:
    return sent


def _two_drones(
    prefixed: bool = False,
    behind: Callable[[int, int], int] = lambda n, i: BEHIND,
    arrival: Callable[[int], int] = _arrival,
) -> list[TfMessage]:
    """Every 100 ms each drone's UAL server sends uav_N_home -> uav_N and its MAVROS the rangefinder's mount (the
    same value on both drones), both stamped on the drone's clock, ``behind(n, i)`` behind the recorder's at the
    i-th; the homes on /tf_static."""
    messages = [
        TfMessage(
            "/tf_static", START, [scenes._t("map", f"uav_{n}_home", START - 10 * 1000 * MS, n * 10.0)], f"/ual_{n}"
        )
        for n in (2, 3)
    ]
    for i in range(SECONDS * 10):
        for n in (2, 3):
            sent = START + i * 100 * MS + n * MS
            stamp = sent - behind(n, i)
            fcu = f"uav_{n}/fcu" if prefixed else "fcu"
            messages.append(
                TfMessage("/tf", arrival(sent), [scenes._t(f"uav_{n}_home", f"uav_{n}", stamp, 0.01 * i)], f"/ual_{n}")
            )
            mount = scenes._t(fcu, "lidarlite_laser" if not prefixed else f"uav_{n}/lidarlite_laser", stamp, -0.1)
            messages.append(TfMessage("/tf", arrival(sent + 5 * MS), [mount], f"/uav_{n}/mavros"))
    return sorted(messages, key=lambda m: m.record_time)


def _findings(tmp_path: Path, messages: list[TfMessage]) -> list[Finding]:
    return check(read_recording([scenes.write(tmp_path, "drones", BagFormat.ros1, messages)])).findings


def test_robots_are_the_same_node_in_several_namespaces() -> None:
    assert robots_of(["/uav_3/mavros", "/uav_2/mavros"]) == ("/uav_2", "/uav_3")
    assert robots_of(["/robot_0/base/driver", "/robot_1/base/driver"]) == ("/robot_0/base", "/robot_1/base")
    assert robots_of(["/ekf_se", "/cartographer_node"]) is None  # two nodes of one robot
    assert robots_of(["/mavros", "/uav_2/mavros"]) is None  # one outside any namespace
    assert robots_of(["/uav_2/mavros", "/uav_3/px4_bridge"]) is None  # different nodes
    assert robots_of(["/uav_2/mavros"]) is None and robots_of(["", ""]) is None


def test_two_drones_frames_without_a_prefix_are_one_cause(tmp_path: Path) -> None:
    findings = _findings(tmp_path, _two_drones())
    (two,) = [f for f in findings if f.code == "multiple_authorities"]
    assert two.severity.name == "error" and two.frames == ("fcu", "lidarlite_laser")
    assert "(the same node in the namespaces of 2 robots, /uav_2 and /uav_3)" in two.message, two.message
    assert "uav_2/fcu" in two.hint and "prefix" in two.hint and "robot_localization" not in two.hint, two.hint
    (apart,) = [f for f in findings if f.code == "disconnected"]
    assert apart.cause == two.key  # the tree apart follows from the frames every drone names alike
    assert "fcu's tree is sent by the same node in the namespaces of 2 robots" in apart.hint, apart.hint


def test_delays_of_one_clock_are_said_once_with_the_outage(tmp_path: Path) -> None:
    findings = _findings(tmp_path, _two_drones())
    late = [f for f in findings if f.code == "delay"]
    (cause,) = [f for f in late if not f.cause]
    assert len(late) == 3 and all(f.cause == cause.key for f in late if f is not cause)
    assert cause.figures["late_s_min"] == pytest.approx(2.3, abs=0.01)
    assert (
        "none arrived for 12.1 s from 1700000014.90" in cause.message and "held back on their way" in cause.message
    ), cause.message


def test_prefixed_frames_of_two_drones_are_no_problem_of_names(tmp_path: Path) -> None:
    codes = {f.code for f in _findings(tmp_path, _two_drones(prefixed=True))}
    assert "multiple_authorities" not in codes  # each drone's own frames: no edge from two nodes
    assert "disconnected" in codes  # still attached to no drone: said, as a tree apart


def test_drones_clocks_less_than_a_second_behind_are_one_offset(tmp_path: Path) -> None:
    """3d-SWAP's flight of 2017-11-20 (tests/corpus/test_corpus48.py): every sample of both drones 0.39-0.44 s
    late, none sooner than 0.385-0.403 s; grouping began at 1 s, so three delay warnings said one offset three
    times, each blaming a busy publisher or a slow link. Now one, its hint naming the clocks first."""
    findings = _findings(tmp_path, _two_drones(behind=lambda n, i: (400 + 5 * n + 30 * (i % 3)) * MS, arrival=_at_once))
    late = [f for f in findings if f.code == "delay"]
    (cause,) = [f for f in late if not f.cause]
    assert len(late) == 3 and all(f.cause == cause.key for f in late if f is not cause)
    assert "nor much later, as with 2 more edges: one steady offset, most likely the publishers' clock" in cause.hint


@pytest.mark.parametrize(
    "behind",
    [
        pytest.param(lambda n, i: (400 if n == 2 else 700) * MS, id="each-drone-its-own-delay"),
        pytest.param(lambda n, i: (250 + 150 * (i % 6)) * MS, id="delays-spread-from-their-floor"),
    ],
)
def test_delays_not_alike_are_not_one_offset(tmp_path: Path, behind: Callable[[int, int], int]) -> None:
    """Edges late by unrelated amounts (0.4 s and 0.7 s), or each late anywhere from 0.25 to 1.0 s (a link's
    delays, not a clock's steady one): each is said on its own, its hint not of clocks."""
    late = [f for f in _findings(tmp_path, _two_drones(behind=behind, arrival=_at_once)) if f.code == "delay"]
    assert len(late) == 3 and not any(f.cause for f in late)
    assert not any("clock" in f.hint for f in late), [f.hint for f in late]


def test_echo_between_the_drones_and_their_unprefixed_frames_names_the_robots(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """echo uav_2 fcu on 3d-SWAP's flights: the hint said to attach fcu to the map tree 'or check the frame names
    for typos', where wtf says both drones' MAVROS send it without a prefix. Now echo says what wtf says."""
    bag = scenes.write(tmp_path, "drones", BagFormat.ros1, _two_drones())
    result = tfx("echo", "uav_2", "fcu", "-b", bag, "--at", "+1")
    assert result.code == 1
    assert "fcu's tree is sent by the same node in the namespaces of 2 robots, /uav_2 and /uav_3" in result.stderr
    assert "uav_2/fcu" in result.stderr and "typos" not in result.stderr, result.stderr
