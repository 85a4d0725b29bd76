"""One formatter for a signed seconds figure (``core.time.signed_seconds``): the monitor's header, wtf's
"+S" and the report's offsets; a hair before the origin is "+0.0", never "-0.0"."""

from __future__ import annotations

from tftools.core.time import NS_PER_S, signed_seconds
from tftools.render.monitor import live_header

T0 = 1_700_000_000 * NS_PER_S


def test_a_signed_figure_never_shows_minus_zero() -> None:
    assert [signed_seconds(s) for s in (-0.04, -0.0, 0.0, 0.05, 2.96, -1.25)] == [
        "+0.0", "+0.0", "+0.0", "+0.1", "+3.0", "-1.2",
    ]  # fmt: skip
    assert (signed_seconds(-0.0004, 3), signed_seconds(1.2345, 3)) == ("+0.000", "+1.234")


def test_the_monitor_header_counts_from_the_first_arrival_with_it() -> None:
    """A replay's clock a hair before the first transform it played (its start): "+0.0 s", as wtf says it."""
    assert (
        live_header(T0 - 40_000_000, T0, 10 * NS_PER_S, "rate 2x") == "time 1699999999.960 (+0.0 s), last 10 s, rate 2x"
    )
    assert live_header(T0 + 15 * NS_PER_S, T0, 5 * NS_PER_S) == "time 1700000015.000 (+15.0 s), last 5 s"
    assert live_header(T0, None, 10 * NS_PER_S) == "time 1700000000.000 (+0.0 s), last 10 s"  # nothing arrived yet
