"""The checks by code: what each looks for, its usual severity, and the function that runs it."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from tftools.analysis.findings import Finding, Severity

if TYPE_CHECKING:
    from tftools.analysis.wtf.scene import Scene

CheckFunction = Callable[["Scene"], Iterable[Finding]]


class CheckSkippedError(Exception):
    """Raised by a check that cannot run on a recording: ``reason`` says why (what the recording
    lacks), ``hint`` how to get the check to run. ``wtf`` reports it as a skipped finding."""

    def __init__(self, reason: str, hint: str) -> None:
        super().__init__(reason)
        self.reason = reason
        self.hint = hint


@dataclass(frozen=True)
class Check:
    """One check: ``code`` names it in findings, ``severity`` is the most it reports (``--list-checks``
    lists it; a finding may be milder, never more severe but as a root cause, which is as severe as the worst
    finding that follows from it: ``causes.explain``), ``title`` says what it looks for. ``run`` is
    None for what the bag runner reports itself (a bag it could not read); ``needs_transforms`` checks
    are skipped on an empty recording."""

    code: str
    severity: Severity
    title: str
    run: CheckFunction | None = None
    needs_transforms: bool = True


#: Every check, in the order findings of one severity are listed.
CHECKS: dict[str, Check] = {}


def register(
    code: str, severity: Severity, title: str, *, needs_transforms: bool = True
) -> Callable[[CheckFunction], CheckFunction]:
    """Decorator: make ``function(scene) -> findings`` the check named ``code``."""

    def add(function: CheckFunction) -> CheckFunction:
        if code in CHECKS:
            raise ValueError(f"check {code!r} registered twice")
        CHECKS[code] = Check(code, severity, title, function, needs_transforms)
        return function

    return add


def declare(code: str, severity: Severity, title: str) -> None:
    """A code that no function produces here (the bag runner reports it)."""
    CHECKS[code] = Check(code, severity, title, None, needs_transforms=False)
