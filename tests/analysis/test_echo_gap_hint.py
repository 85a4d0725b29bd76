"""``tfx echo`` says where its lookups answered inside a pause of an edge of their chain: tf2 interpolates across
it, and tf_echo's lines look like any other (e-Yantra's fruit detection unseen for 14 s, a scout's, 2026-12-02; the
real recording is in tests/corpus/test_corpus50.py)."""

from __future__ import annotations

from tests.analysis.wtf_scenes import ekf, healthy, recording
from tftools.analysis.echo import EchoQuery, echo, gap_hint
from tftools.analysis.times import parse_time_spec


def _echoed(at: str | None = None) -> str | None:
    paused = healthy(ekf=ekf(skip=(4.0, 7.0)))  # odom -> base_link silent for 3 s from 4 s
    rec = recording(paused)
    query = EchoQuery(target="map", source="base_link", at=parse_time_spec(at) if at else None, rate=1.0)
    return gap_hint(rec.buffer, echo(rec, query))


def test_a_lookup_inside_a_pause_is_said_interpolated_across_it() -> None:
    said = _echoed("+5.5")
    assert said is not None and said.startswith("the lookup falls where odom -> base_link had no sample for 3.020 s")
    assert "tf2 interpolates across that stretch, a guess of where base_link was" in said, said


def test_a_range_says_how_many_of_its_lookups_fall_in_the_pause() -> None:
    said = _echoed()
    assert said is not None and said.startswith("3 of the 10 lookups fall where"), said  # at +4, +5 and +6 s


def test_nothing_is_said_outside_a_pause_or_on_a_steady_chain() -> None:
    assert _echoed("+2.5") is None
    rec = recording(healthy())
    assert gap_hint(rec.buffer, echo(rec, EchoQuery(target="map", source="base_link", rate=1.0))) is None
