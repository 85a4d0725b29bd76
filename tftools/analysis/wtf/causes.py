"""Findings that follow from another: each rule says once which finding explains which, and ``explain``
links them (``Finding.cause``), so that one root cause is said once, with what follows from it beneath."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from tftools.analysis.findings import Finding, Severity


def _on_its_frames(cause: Finding, finding: Finding) -> bool:
    """A finding about frames (a joint's link) that the cause found in dispute."""
    return bool(finding.frames) and set(finding.frames) <= set(cause.frames)


def edges_of(finding: Finding) -> set[tuple[str, str]]:
    """The edges a finding names as consecutive parent, child pairs."""
    return set(zip(finding.frames[0::2], finding.frames[1::2], strict=False))


def _during(cause: Finding, finding: Finding) -> bool:
    """A finding about one of the cause's edges at a time that overlaps the cause's."""
    return (
        len(finding.frames) == 2
        and edges_of(finding) <= edges_of(cause)
        and finding.first_time <= cause.last_time
        and cause.first_time <= finding.last_time
    )


@dataclass(frozen=True)
class Rule:
    """Findings of the codes ``follows`` follow from one of the codes ``causes`` when ``relates(cause, it)``."""

    causes: frozenset[str]
    follows: frozenset[str]
    relates: Callable[[Finding, Finding], bool]
    why: str


#: No code both follows and explains: a cause follows from nothing, so the causes are one level deep.
RULES = (
    Rule(
        frozenset({"static_conflict", "dynamic_on_static"}),
        frozenset({"urdf_moved", "urdf_parent", "urdf_missing"}),
        _on_its_frames,
        "a robot description that disagrees with tf on frames whose /tf_static values are in dispute: "
        "tf holds one of the disputed values, and the description agrees with another",
    ),
    Rule(
        frozenset({"stall"}),
        frozenset({"rate"}),
        _during,
        "an edge's pauses, one of them in a stall of many edges at once: one stop, not one per edge (the finding "
        "beneath it still says how many pauses that edge had)",
    ),
)


def explain(findings: Sequence[Finding], rules: Sequence[Rule] = RULES) -> list[Finding]:
    """``findings`` with each that follows from another (by the first rule, then the first cause, that
    explain it) linked to it; each cause as severe as the worst that follows from it (a recording's
    verdict and exit code go by causes); in order: causes by severity (as found), each followed by
    what it explains. Called again on findings it linked (with more added), it links them anew."""
    found = [replace(f, key="", cause="") for f in findings]
    cause_of: dict[int, int] = {}
    for i, finding in enumerate(found):
        for rule in rules:
            if finding.code in rule.follows:
                j = next((j for j, c in enumerate(found) if c.code in rule.causes and rule.relates(c, finding)), None)
                if j is not None:
                    cause_of[i] = j
                    break
    keys: dict[int, str] = {}
    for j in sorted(set(cause_of.values())):
        keys[j] = f"{found[j].code}:{sum(found[k].code == found[j].code for k in keys) + 1}"
    for j, key in keys.items():
        worst = min([found[j].severity, *(found[i].severity for i, c in cause_of.items() if c == j)], key=_rank)
        found[j] = replace(found[j], key=key, severity=worst)
    for i, j in cause_of.items():
        found[i] = replace(found[i], cause=keys[j])
    ordered = sorted((f for f in found if not f.cause), key=lambda f: f.severity.rank)
    return [g for f in ordered for g in (f, *(c for c in found if f.key and c.cause == f.key))]


def _rank(severity: Severity) -> int:
    return severity.rank
