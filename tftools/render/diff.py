"""``tfx diff`` output: a line per difference, or one JSON document."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict
from typing import IO, Any

from tftools import __version__
from tftools.analysis.differences import Difference, describe
from tftools.analysis.expected import Tolerances, TreeShape
from tftools.analysis.findings import counted
from tftools.render import jsonl
from tftools.render.escape import printable


def write_text(
    a: TreeShape,
    b: TreeShape,
    differences: list[Difference],
    tolerances: Tolerances,
    out: IO[str],
    notes: Sequence[str] = (),
    damaged: tuple[str, str] = ("", ""),
) -> None:
    """Which is A and which B (one read only in part said so: ``damaged``, its first problem), each difference
    on its line (with what says a damaged side may have made it: ``notes``, one a difference), and a verdict
    naming the tolerances."""
    for label, tree, problem in (("A", a, damaged[0]), ("B", b, damaged[1])):
        frames = f"0 frames: {tree.empty}" if tree.empty else f"{len(tree.frames)} frames"
        frames += f"; read only in part, compared as far as it could be read: {problem}" if problem else ""
        out.write(printable(f"{label}: {tree.source} ({frames})") + "\n")
    for d, note in zip(differences, notes or [""] * len(differences), strict=True):
        said = f" ({note})" if note else ""
        out.write(printable(f"  {d.change.value:<11} {describe(d)}{said}") + "\n")
    within = f"{tolerances.translation_mm:g} mm, {tolerances.rotation_deg:g}°, rates {tolerances.rate_percent:g}%"
    verdict = counted(len(differences), "difference") if differences else "no differences"
    out.write(f"{verdict} beyond the tolerances ({within})\n")


def write_json(
    a: TreeShape,
    b: TreeShape,
    differences: list[Difference],
    tolerances: Tolerances,
    exit_code: int,
    out: IO[str],
    notes: Sequence[str] = (),
    damaged: tuple[str, str] = ("", ""),
) -> None:
    """One document: the two sides (with why one has no frame: ``a_empty``, ``b_empty``, null where it has; the
    first problem of a damaged one: ``a_damaged``, ``b_damaged``), the tolerances, whether they differ, and each
    difference with its message and what says a damaged side may have made it (``damage``, null where nothing)."""
    jsonl.write_document(
        {
            "tool": "tfx diff",
            "version": __version__,
            "a": a.source,
            "b": b.source,
            "a_empty": a.empty or None,
            "b_empty": b.empty or None,
            "a_damaged": damaged[0] or None,
            "b_damaged": damaged[1] or None,
            "tolerances": asdict(tolerances),
            "differ": bool(differences),
            "exit_code": exit_code,
            "differences": [
                _difference(d, note) for d, note in zip(differences, notes or [""] * len(differences), strict=True)
            ],
        },
        out,
    )


def _difference(d: Difference, note: str) -> dict[str, Any]:
    return {
        "change": d.change.value,
        "frame": d.frame,
        "message": describe(d),
        "a": asdict(d.before) if d.before is not None else None,
        "b": asdict(d.after) if d.after is not None else None,
        "translation_mm": d.translation_mm,
        "rotation_deg": d.rotation_deg,
        "rate_change": d.rate_change,
        "source": d.source,
        "part": d.part.value if d.part is not None else None,
        "beneath": d.beneath,
        "said_with": list(d.said_with),
        "sent_in": d.sent_in or None,
        "mimics": list(d.mimics),
        "other": d.other or None,
        "damage": note or None,
    }
