"""A sample whose stamp came early or late is no jump (corpus ``ros2-neato-real-wall-follower-stopped-2023-db3``):
a real Neato's driver stamps each wheel reading as its serial packet arrives, so a wheel turning a steady 25
degrees a sample at 5.9 Hz has two samples 8 ms apart, the next 185 ms later. The 25 degrees in 8 ms is 20 times
the wheel's speed, but no further than every step around it: its stamp is off, not its value."""

from __future__ import annotations

import numpy as np

from tftools.analysis.wtf import jumps

PERIOD_NS = 170_000_000  # 5.9 Hz, as the Neato's wheels


def _wheel(steps_deg: list[float], stamps_ns: list[int] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A wheel joint (a pitch about y) turning by ``steps_deg``, evenly stamped unless ``stamps_ns``."""
    angle = np.radians(np.concatenate([[0.0], np.cumsum(steps_deg)]))
    values = np.zeros((len(angle), 7))
    values[:, 1] = 0.124
    values[:, 4], values[:, 6] = np.sin(angle / 2), np.cos(angle / 2)
    stamps = np.arange(len(angle), dtype=np.int64) * PERIOD_NS if stamps_ns is None else np.array(stamps_ns)
    return stamps, values


def _jittered(samples: int, late: int) -> list[int]:
    """Even stamps, but sample ``late`` stamped 8 ms after the one before it (its packet held back, the next
    one's time made up)."""
    stamps = [i * PERIOD_NS for i in range(samples)]
    stamps[late] = stamps[late - 1] + 8_000_000
    return stamps


def test_a_steady_step_stamped_8_ms_after_the_last_is_no_jump() -> None:
    steps = [25.0, 24.5, 26.2, 25.1, 24.0, 25.5, 26.2, 24.5, 25.0, 25.8, 24.2, 25.0, 26.0, 24.8]
    stamps, values = _wheel(steps, _jittered(len(steps) + 1, 8))
    assert len(jumps.jumps(stamps, values)) == 0


def test_a_step_far_beyond_the_steps_around_it_stamped_8_ms_later_still_jumps() -> None:
    """The same wheel reset by 120 degrees in a sample stamped 8 ms after the last: beyond any step around it."""
    steps = [25.0, 24.5, 26.2, 25.1, 24.0, 25.5, 26.2, 145.0, 25.0, 25.8, 24.2, 25.0, 26.0, 24.8]
    stamps, values = _wheel(steps, _jittered(len(steps) + 1, 8))
    found = jumps.jumps(stamps, values)
    assert len(found) == 1 and int(found.at[0]) == 8


def test_a_reset_among_steps_at_rest_stamped_early_still_jumps() -> None:
    """An odometry at rest that steps 0.3 m in a sample stamped 8 ms after the last: the steps around it are 0."""
    stamps = np.array(_jittered(15, 8), dtype=np.int64)
    values = np.zeros((15, 7))
    values[:, 6] = 1.0
    values[8:, 0] = 0.3
    found = jumps.jumps(stamps, values)
    assert len(found) == 1 and round(float(found.metres[0]), 3) == 0.3
