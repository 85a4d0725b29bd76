"""``tfx echo A B --at`` outside the recording's tf of the chain (a real Neato's 27.9 s drive,
ros2_db3_neato_real_drive_square_isha_2023, asked at +40.9): tf2's extrapolation text stays as tf2 says it;
the hint beneath says the chain's span on its clock and the ``+S`` (or ``-S``) that reach it, and those do."""

from __future__ import annotations

import re

import pytest

from tests.analysis.wtf_scenes import ekf, healthy, recording
from tftools.analysis.echo import EchoQuery, echo, span_hint
from tftools.analysis.times import parse_time_spec
from tftools.sources.recording import Recording

#: odom -> base_link from 2 s to 8 s of a 10 s recording whose other edges span all of it: +S counts from 0 s.
REC = recording(healthy(ekf=ekf(start=2.0, end=8.0)))


def _hint(rec: Recording, at: str) -> tuple[bool, str | None]:
    query = EchoQuery(target="odom", source="base_link", at=parse_time_spec(at, "at"))
    series = echo(rec, query)
    return bool(series.valid.all()), span_hint(rec, query, series)


@pytest.mark.parametrize(
    ("at", "where", "sign"), [("+40.9", "after", "+"), ("+0.5", "before", "+"), ("-9.5", "before", "-")]
)
def test_a_time_outside_the_chain_gets_its_span_and_the_times_that_reach_it(at: str, where: str, sign: str) -> None:
    ok, said = _hint(REC, at)
    assert not ok and said is not None
    assert f"is {where} the recording's tf of odom <- base_link" in said, said
    reach = re.search(r"--at (\S+) to (\S+) look it up there", said)
    assert reach is not None, said
    for bound in reach.groups():  # the first and the last time said both look the chain up
        assert bound.startswith(sign) and _hint(REC, bound) == (True, None), (bound, said)


def test_a_time_inside_the_chain_or_the_latest_gets_no_hint() -> None:
    assert _hint(REC, "+5") == (True, None)
    query = EchoQuery(target="odom", source="base_link", at=parse_time_spec("0", "at"))
    assert span_hint(REC, query, echo(REC, query)) is None
