"""``figures.kept_in_words``: the share of a stream the suggested wait keeps, said as a count of messages can give it
(a real TurtleBot 4's 116 scans were said "99.9% within 0.115 s": 99.9% of 116 is all 116)."""

from __future__ import annotations

import numpy as np
import pytest

from tftools.core.figures import KEEP, kept_in_words, wait_keeping


@pytest.mark.parametrize(
    ("decided", "said"), [(1, "all"), (116, "all"), (999, "all"), (1000, "99.9%"), (5275, "99.9%")]
)
def test_the_share_kept_is_all_where_it_is_every_message(decided: int, said: str) -> None:
    assert kept_in_words(decided) == said


def test_all_is_said_exactly_where_the_wait_kept_is_the_longest() -> None:
    """Below a thousand messages the wait keeping 99.9% is the longest wait: "all within" it is the truth."""
    waits = np.arange(1, 117, dtype=np.int64) * 1000
    assert wait_keeping(waits, 0, len(waits), KEEP) == waits.max()
    waits = np.arange(1, 2001, dtype=np.int64) * 1000
    assert wait_keeping(waits, 0, len(waits), KEEP) < waits.max() and kept_in_words(len(waits)) == "99.9%"
