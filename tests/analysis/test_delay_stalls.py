"""A link to the recorder that stalls more than once (a Pioneer's p2os odometry, Dinisas/SA's odometry3.bag:
nothing recorded for 12.3 s, then for 7.7 s, the samples stamped meanwhile arriving together after each): ``delay``
names every stall, longest first, and is timed by when its late transforms arrived, as its "first at" says."""

from __future__ import annotations

from pathlib import Path

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check
from tftools.sources.recording import read_recording

MS = scenes.MS
START = scenes.START
STALLS = ((40_000 * MS, 52_300 * MS), (70_000 * MS, 77_700 * MS))  # nothing recorded meanwhile
HICCUPS = ((20_000 * MS, 21_500 * MS), (85_000 * MS, 86_200 * MS))  # a WiFi link's short ones beside them


def _arrival(sent: int, stalls: tuple[tuple[int, int], ...] = STALLS) -> int:
    """At once, except from a stall on: those held back then arrive in order when it ends, 100 times faster than
    they were sent, until the link has caught up."""
    arrival = sent
    for begin, end in sorted(stalls):
        if sent >= START + begin:
            arrival = max(sent, START + end + (sent - START - begin) // 100)
    return arrival


def _odometry(seconds: int = 100, stalls: tuple[tuple[int, int], ...] = STALLS) -> list[TfMessage]:
    messages = []
    for i in range(seconds * 10):
        stamp = START + i * 100 * MS
        moved = scenes._t("odom", "base_link", stamp, 0.01 * i)
        sent = stamp + 40 * MS
        messages.append(TfMessage("/tf", _arrival(sent, stalls), [moved], "/p2os"))
    return sorted(messages, key=lambda m: m.record_time)


def _delay(tmp_path: Path, messages: list[TfMessage]) -> Finding:
    findings = check(read_recording([scenes.write(tmp_path, "pioneer", BagFormat.ros1, messages)])).findings
    (late,) = [f for f in findings if f.code == "delay"]
    return late


def test_every_stall_of_the_link_is_named_longest_first(tmp_path: Path) -> None:
    late = _delay(tmp_path, _odometry())
    first = "none arrived for 12.4 s from 1700000039.94"
    second = "and for 7.8 s from 1700000069.94"
    assert first in late.message and second in late.message, late.message
    assert late.message.index(first) < late.message.index(second)
    assert "while its stamps went on" in late.message


def test_a_delay_is_timed_when_its_late_transforms_arrived(tmp_path: Path) -> None:
    late = _delay(tmp_path, _odometry())
    first_late_arrival = _arrival(START + STALLS[0][0] + 40 * MS)  # the first held back, as the stall ends
    assert START + STALLS[0][1] <= first_late_arrival < START + STALLS[0][1] + MS
    assert late.first_time == first_late_arrival, (late.first_time, first_late_arrival)
    assert late.last_time >= START + STALLS[1][1]  # the second stall's backlog, on arrival


def test_stalls_much_shorter_than_the_longest_are_counted(tmp_path: Path) -> None:
    late = _delay(tmp_path, _odometry(stalls=STALLS + HICCUPS))
    assert "none arrived for 12.4 s from 1700000039.94" in late.message, late.message
    assert "and for 7.8 s from 1700000069.94" in late.message
    assert "(and 2 shorter times, of 1.3 s to 1.6 s) while its stamps went on" in late.message, late.message
