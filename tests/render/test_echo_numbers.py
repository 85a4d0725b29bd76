"""tf_echo's fixed notation, but a number past 1e15 (1e308 from a hostile bag: 309 digits) with an exponent."""

from __future__ import annotations

import math

import pytest

from tftools.render.echo import FIXED_LIMIT, fixed


@pytest.mark.parametrize(
    ("value", "shown"),
    [(0.5, "0.500"), (-12.3456, "-12.346"), (1e308, "1.000e+308"), (-1e300, "-1.000e+300"), (math.inf, "inf")],
)
def test_numbers_as_echo_shows_them(value: float, shown: str) -> None:
    assert fixed(value, 3) == shown


def test_below_the_limit_every_digit_is_kept_as_tf_echo_keeps_it() -> None:
    assert fixed(FIXED_LIMIT / 10, 1) == "100000000000000.0"
