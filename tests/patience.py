"""How long tests wait for a process to come up, answer or finish: hang guards, never time limits.

A CI machine shares its two cores with other jobs; a roscore, a DDS participant or a headless Chromium that
answers in a second on a quiet machine can take a minute there. Every wait ends as soon as its condition
holds, so a longer guard only lengthens a test that fails anyway.
"""

from __future__ import annotations

#: Each wait a test names is multiplied by this.
PATIENCE = 4.0


def patient(seconds: float) -> float:
    """The guard for a wait that takes ``seconds`` on a quiet machine at most."""
    return seconds * PATIENCE
