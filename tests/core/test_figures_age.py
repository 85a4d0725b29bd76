"""The one definition of a sample's age and the one way it is said."""

from __future__ import annotations

from tftools.core.figures import age, age_in_words
from tftools.core.time import NS_PER_S


def test_an_age_is_how_far_a_stamp_is_behind_now_signed() -> None:
    assert age(10 * NS_PER_S, 9 * NS_PER_S) == NS_PER_S
    assert age(10 * NS_PER_S, 10 * NS_PER_S + 51_000_000) == -51_000_000


def test_an_age_in_words_is_never_negative() -> None:
    assert age_in_words(1_234_000_000, "the recording's clock") == "1.234 s old"
    assert age_in_words(0, "/clock") == "0.000 s old"
    assert age_in_words(-51_000_000, "the recording's clock") == "stamped 0.051 s ahead of the recording's clock"
    assert age_in_words(-3_000_000, "/clock") == "stamped 0.003 s ahead of /clock"
