"""Numbers given on the command line, checked once, here, against named limits (times against a recording:
``tftools.analysis.times``)."""

from __future__ import annotations

import math

from tftools.cli.errors import UsageError

#: ``--rate`` (lines, refreshes or replay speed per second) from one a fortnight to a million a second.
MIN_RATE_HZ = 1e-6
MAX_RATE_HZ = 1e6
#: The longest ``--duration``, ``--window``, ``--cache``, ``--wait`` or threshold: a year.
MAX_SECONDS = 365 * 86400.0


def positive_seconds(value: float, option: str, example: str = "5") -> float:
    """A duration option (``--duration``, ``--window``, ``--cache``, ``--wait``, thresholds): finite,
    above 0 and at most ``MAX_SECONDS``."""
    if not math.isfinite(value) or not 0 < value <= MAX_SECONDS:
        raise UsageError(
            f"{option} {value:g}: must be above 0 and at most a year ({MAX_SECONDS:.0f} s)", f"e.g. {option} {example}"
        )
    return value


def rate_hz(value: float, example: str = "10") -> float:
    """``--rate``: finite, from ``MIN_RATE_HZ`` to ``MAX_RATE_HZ``."""
    if not math.isfinite(value) or not MIN_RATE_HZ <= value <= MAX_RATE_HZ:
        bounds = f"from {MIN_RATE_HZ:g} to {MAX_RATE_HZ:g} a second"
        raise UsageError(f"--rate {value:g}: must be {bounds}", f"e.g. --rate {example}")
    return value
