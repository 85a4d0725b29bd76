"""``tfx wtf``'s checker: every check (``CHECKS``) run over a recording, as ``Finding`` s."""

from __future__ import annotations

from collections.abc import Collection, Sequence

from tftools.analysis.description import Robot
from tftools.analysis.expected import TreeShape
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import (  # noqa: F401  (they register their checks)
    clocks,
    description,
    expectations,
    jumps,
    odometry,
    replay,
    sensors,
    silence,
    source,
    structure,
    timing,
    topics,
    values,
)
from tftools.analysis.wtf.causes import explain
from tftools.analysis.wtf.registry import CHECKS, Check, CheckSkippedError
from tftools.analysis.wtf.scene import Scene
from tftools.analysis.wtf.source import said_where_damaged
from tftools.analysis.wtf.thresholds import Thresholds
from tftools.core.buffer import Buffer
from tftools.sources.contents import StampedMessages
from tftools.sources.recording import Recording

__all__ = ["CHECKS", "Check", "CheckSkippedError", "Finding", "Scene", "Severity", "Thresholds", "check", "findings_of"]


def check(
    recording: Recording | Buffer,
    thresholds: Thresholds | None = None,
    ignore: Collection[str] = (),
    streams: Sequence[StampedMessages] = (),
    target: str | None = None,
    expected: TreeShape | None = None,
    robot: Robot | None = None,
) -> list[Finding]:
    """Every problem of ``recording`` (or a bare buffer, as ``Scene`` sees it), errors first, then
    warnings, then notes (each in check order), each followed by those it explains (``causes.explain``).

    ``streams``: its sensor data (``Recording.stamped``), for the checks of data against tf, transformed
    into ``target`` (default and fallback: ``analysis.targets.choose_target``). ``expected``: the
    tree it should have (``tfx wtf --expect``), within its tolerances. ``robot``: its description and
    joint states (``tfx wtf --urdf``, ``analysis.description``). ``ignore``
    lists codes not to run. Raises ``ValueError`` for a code that does not exist.
    """
    return findings_of(Scene(recording, thresholds, streams, target, expected, robot), ignore)


def findings_of(scene: Scene, ignore: Collection[str] = ()) -> list[Finding]:
    """``check``'s findings of a prepared ``scene``, for a caller that goes on to use what it computed."""
    unknown = set(ignore) - set(CHECKS)
    if unknown:
        raise ValueError(f"no such check: {', '.join(sorted(unknown))}")
    found: list[Finding] = []
    for c in CHECKS.values():
        if c.run is None or c.code in ignore or (c.needs_transforms and not len(scene.rows)):
            continue
        try:
            found.extend(f for f in c.run(scene) if f.code not in ignore)  # a check may speak for another
        except CheckSkippedError as why:
            found.append(Finding(Severity.info, c.code, f"not checked: {why.reason}", why.hint, skipped=True))
    return explain(said_where_damaged(scene, found))
