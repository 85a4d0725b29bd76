"""``Finding``: one problem the checker found, with what it involves and how to fix it; findings that
follow from another (its ``cause``) are shown beneath it and counted with it."""

from __future__ import annotations

import enum
from collections.abc import Sequence
from dataclasses import dataclass, field


def counted(n: int, thing: str) -> str:
    """``n`` and ``thing``, plural unless ``n`` is 1: "1 frame", "3 frames"."""
    return f"{n} {thing}{'' if n == 1 else 's'}"


class Severity(str, enum.Enum):
    """How badly a problem breaks lookups: errors break them, warnings are tolerated by tf2."""

    error = "error"
    warning = "warning"
    info = "info"

    @property
    def rank(self) -> int:
        return {"error": 0, "warning": 1, "info": 2}[self.value]

    def fails(self, strict: bool = False) -> bool:
        """Whether a finding of this severity fails a check: an error does; a warning too, ``strict``."""
        return self is Severity.error or (strict and self is Severity.warning)

    @property
    def noun(self) -> str:
        """What one finding of this severity is called in text: an error, a warning, a note."""
        return "note" if self is Severity.info else self.value


@dataclass(frozen=True)
class Finding:
    """A problem: its code (e.g. ``cycle``), a one-line message naming what is involved, a hint.

    ``frames`` lists the frames involved (edges as consecutive parent, child pairs where that
    matters is up to the check), ``first_time``/``last_time`` where it shows (ns), on the stamps' clock:
    stamps, or ROS time at arrival (``Scene.ros_times``), 0 where unknown, never record times; ``count`` how
    many samples or messages show it. A ``skipped`` finding says that its check could not run on this
    recording, and why: never a silent pass. ``key`` names a finding that
    explains others (unique among one recording's findings); ``cause`` is the key of the finding this one
    follows from (``analysis.wtf.causes``), empty for a finding that stands on its own. ``figures`` holds
    what was observed, by name (counts, metres, degrees, seconds), as the message says it: for JSON and the
    report.
    """

    severity: Severity
    code: str
    message: str
    hint: str
    frames: tuple[str, ...] = ()
    authorities: tuple[str, ...] = ()
    first_time: int = 0
    last_time: int = 0
    count: int = 0
    skipped: bool = False
    key: str = ""
    cause: str = ""
    figures: dict[str, float | int | str] = field(default_factory=dict, hash=False)


def causes(findings: Sequence[Finding]) -> list[Finding]:
    """The findings that follow from no other: what a recording's verdict and counts are made of."""
    return [f for f in findings if not f.cause]


def explained(findings: Sequence[Finding], cause: Finding) -> list[Finding]:
    """The findings that follow from ``cause``, in their order (none where it explains nothing: no key; asked
    of each of 20,000 findings of a frame flood, a scan each took minutes)."""
    if not cause.key:
        return []
    return [f for f in findings if f.cause == cause.key]


def explaining(findings: Sequence[Finding], severity: Severity) -> int:
    """How many findings follow from those of ``severity`` (``explained``): "1 error (explaining 45 more)"."""
    keys = {f.key for f in causes(findings) if f.severity is severity and f.key}
    return sum(f.cause in keys for f in findings)


def tallied(findings: Sequence[Finding], severity: Severity, word: str) -> str:
    """The causes of ``severity`` counted as ``word`` s, with what follows from them: "1 error (explaining
    45 more)", "2 warnings"."""
    n = sum(f.severity is severity for f in causes(findings))
    more = explaining(findings, severity)
    return counted(n, word) + (f" (explaining {more} more)" if more else "")
