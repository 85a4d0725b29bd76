"""``Thresholds``: how far a recording may stray before the checker calls it a problem."""

from __future__ import annotations

from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class Thresholds:
    """Limits in seconds; the defaults stay silent on a healthy robot.

    ``stale_after``: an edge silent this long before the recording ends has stopped (and at
    least ``figures.PERIODS`` of its periods). ``max_gap``: a pause inside the recording longer than
    this (and ``PERIODS`` periods) is reported (``figures.pauses``). ``delay``: transforms arriving this
    much after their stamp are late (costmap_2d's default ``transform_tolerance``). ``future``: stamps
    this much ahead of their arrival are from the future (roswtf's limit). ``clock``: stamps this much behind their
    arrival (the median) are on another clock altogether, like stamps counting from boot next to
    epoch time.
    """

    stale_after: float = 1.0
    max_gap: float = 0.5
    delay: float = 0.2
    future: float = 1.0
    clock: float = 10.0

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            if not value > 0:
                raise ValueError(f"threshold {name} must be above 0 seconds, got {value}")
