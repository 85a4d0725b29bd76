"""tf's health as diagnostic_updater says a subsystem's: ``Status`` es (a level, a name, a message, the
figures as key/values), one for the tree, one per check and one per edge, from a ``BagReport`` and the
edges' statistics over the same span. What ``/diagnostics`` carries (``sinks.diagnostics``) and what a
findings MCAP shows beside its recording (``sinks.findings_mcap``)."""

from __future__ import annotations

import dataclasses
import enum
import itertools
import math
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass

from tftools.analysis.edges import EdgeStats
from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.wtf.fleet import BagReport
from tftools.analysis.wtf.registry import CHECKS
from tftools.core.figures import apart_in_words, silence
from tftools.core.time import to_sec

#: diagnostic_updater's default hardware_id for what is not a device: the tf tree of this system.
HARDWARE_ID = "tf"


class Level(enum.IntEnum):
    """diagnostic_msgs/DiagnosticStatus's levels."""

    OK = 0
    WARN = 1
    ERROR = 2
    STALE = 3


#: A finding's severity as a status's level: a note is information, not a fault.
LEVELS = {Severity.error: Level.ERROR, Severity.warning: Level.WARN, Severity.info: Level.OK}


@dataclass(frozen=True)
class Status:
    """One diagnostic_msgs/DiagnosticStatus: ``values`` are its key/values, in order."""

    level: Level
    name: str
    message: str
    hardware_id: str = HARDWARE_ID
    values: tuple[tuple[str, str], ...] = ()


def edge_name(parent: str, child: str) -> str:
    """An edge's status name, e.g. ``tf: odom -> base_link``."""
    return f"tf: {parent} -> {child}"


def check_name(code: str) -> str:
    """A check's status name, e.g. ``tf check: stale``."""
    return f"tf check: {code}"


#: The tree's own status.
TREE_NAME = "tf: tree"

#: An edge's silence (``figures.silence``): how long since its last sample arrived, not how old its stamp is
#: (until this key, tfx sent that figure as "age (s)").
SILENT = "silent for the last (s)"


#: The codes of the checks whose findings set an edge's level, in the order of its findings (only where it has some):
#: what a reader needs to tell a late arrival (``delay``, ``rate``) from a wrong value.
CHECKS_KEY = "checks"


def statuses(
    report: BagReport,
    edges: Sequence[EdgeStats],
    now: int,
    *,
    ignore: Collection[str] = (),
    gone: Mapping[tuple[str, str], int] | None = None,
    window: int = 0,
    hardware_id: str = HARDWARE_ID,
    delays_unavailable: str = "",
) -> list[Status]:
    """The statuses of ``report`` at ``now`` (ns, the clock of the edges' record times): the tree's
    (its worst level; STALE when nothing was heard), one per check that runs on tf (OK when it found
    nothing) and one per edge of ``edges`` (its worst finding's level, its rate, delay, longest gap and
    silence). ``gone``: edges heard before but not in this span, with when they were last heard: STALE.
    ``window``: the span's length (ns; 0 for a whole recording), and ``delays_unavailable`` why the edges'
    delays are unknown (``Timeline.delays_unavailable``), said in the tree's status."""
    checks = [_check_status(code, report.findings, hardware_id) for code in _codes(ignore)]
    if not report.transforms and report.error is None:  # nothing heard (yet): no data, as the aggregator says it
        checks = [dataclasses.replace(s, level=Level.STALE) if s.level is Level.ERROR else s for s in checks]
    edge_statuses = [_edge_status(edge, report.findings, now, hardware_id) for edge in edges]
    for (parent, child), last in sorted((gone or {}).items()):
        silent = silence(last, now)
        said = "unknown" if silent is None else f"{to_sec(silent):.3f}"
        message = "not heard" if silent is None else f"not heard for {said} s"
        values = (("parent", parent), ("child", child), (SILENT, said))
        edge_statuses.append(Status(Level.STALE, edge_name(parent, child), message, hardware_id, values))
    tree = _tree_status(report, [*checks, *edge_statuses], window, hardware_id)
    if delays_unavailable:
        tree = dataclasses.replace(tree, values=(*tree.values, ("delays", f"unknown: {delays_unavailable}")))
    return [tree, *checks, *edge_statuses]


def worst(levels: Collection[Level]) -> Level:
    """The worst of ``levels`` (STALE above ERROR, as diagnostic_aggregator ranks them); OK for none."""
    return max(levels, default=Level.OK)


def _codes(ignore: Collection[str]) -> list[str]:
    return [code for code, check in CHECKS.items() if check.run is not None and code not in ignore]


def _tree_status(report: BagReport, others: Sequence[Status], window: int, hardware_id: str) -> Status:
    values = [("frames", str(report.frames)), ("transforms", str(report.transforms))]
    if window:
        values.append(("window (s)", f"{to_sec(window):g}"))
    errors, warnings = report.count(Severity.error), report.count(Severity.warning)
    values += [("errors", str(errors)), ("warnings", str(warnings))]
    if report.error is not None:
        return Status(Level.ERROR, TREE_NAME, report.error.message, hardware_id, tuple(values))
    if not report.transforms:
        return Status(Level.STALE, TREE_NAME, "no transform heard", hardware_id, tuple(values))
    level = worst([s.level for s in others])
    if errors or warnings:
        message = ", ".join(part for part in (_some(errors, "error"), _some(warnings, "warning")) if part)
    else:
        message = f"{counted(report.frames, 'frame')}, no problem found"
    if level is Level.STALE and not errors:
        message = f"{message}; some edges not heard"
    return Status(level, TREE_NAME, message, hardware_id, tuple(values))


def _some(n: int, thing: str) -> str:
    return counted(n, thing) if n else ""


def _check_status(code: str, findings: Sequence[Finding], hardware_id: str) -> Status:
    found = [f for f in findings if f.code == code]
    check = CHECKS[code]
    values: list[tuple[str, str]] = [("check", check.title)]
    if not found:
        return Status(Level.OK, check_name(code), "OK", hardware_id, tuple(values))
    problems = [f for f in found if not f.skipped]
    if not problems:
        return Status(Level.OK, check_name(code), f"not checked: {found[0].message}", hardware_id, tuple(values))
    first = problems[0]
    message = first.message + (f" (and {len(problems) - 1} more)" if len(problems) > 1 else "")
    values += [("findings", str(len(problems))), ("hint", first.hint)]
    if first.frames:
        values.append(("frames", " ".join(first.frames)))
    if first.count:
        values.append(("count", str(first.count)))
    level = worst([LEVELS[f.severity] for f in problems])
    return Status(level, check_name(code), message, hardware_id, tuple(values))


def concerns(finding: Finding, parent: str, child: str) -> bool:
    """Whether ``finding`` is about the edge ``parent`` -> ``child``: it names both frames next to each other
    (an edge, either way round), or names the child alone."""
    frames = finding.frames
    if frames == (child,):
        return True
    pairs = set(itertools.pairwise(frames))
    return (parent, child) in pairs or (child, parent) in pairs


def _edge_status(edge: EdgeStats, findings: Sequence[Finding], now: int, hardware_id: str) -> Status:
    about = [f for f in findings if not f.skipped and concerns(f, edge.parent, edge.child)]
    values = [("parent", edge.parent), ("child", edge.child), ("publishers", " ".join(edge.authorities))]
    if edge.static:
        values.append(("rate (Hz)", "static"))
    else:
        values += [
            ("rate (Hz)", "unknown" if edge.once else f"{edge.rate_hz:.3f}"),  # one sample has none
            ("delay mean (s)", apart_in_words(edge.apart) if edge.apart else _seconds(edge.delay_mean)),
            ("delay max (s)", _seconds(edge.delay_max)),
            ("longest gap (s)", _seconds(math.nan if edge.once else float(edge.longest_interval))),
            (SILENT, _seconds(math.nan if edge.silent_for is None else float(edge.silent_for))),
        ]
    values.append(("samples", str(edge.count)))
    if about:
        first = min(about, key=lambda f: f.severity.rank)
        level = LEVELS[first.severity]
        message = first.message + (f" (and {len(about) - 1} more)" if len(about) > 1 else "")
        values.append((CHECKS_KEY, " ".join(dict.fromkeys(f.code for f in about))))
    else:
        level = Level.OK
        message = "static" if edge.static else "OK, 1 sample" if edge.once else f"OK, {edge.rate_hz:.1f} Hz"
    return Status(level, edge_name(edge.parent, edge.child), message, hardware_id, tuple(values))


def _seconds(ns: float) -> str:
    return "unknown" if math.isnan(ns) else f"{ns / 1e9:.3f}"
