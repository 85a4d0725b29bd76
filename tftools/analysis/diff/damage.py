"""Which of ``tfx diff``'s differences a damaged recording may have made: said beside them, not left to stderr."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from tftools.analysis.differences import Change, Difference
from tftools.sources.recording import Recording


@dataclass(frozen=True)
class Damaged:
    """A recording read only in part: its first problem line, and the stretches (ns into it) whose transforms were
    lost or read from damaged bytes (``SourceInfo.damaged``; none where the reader cannot place them)."""

    problem: str
    lost: tuple[tuple[int, int], ...] = ()


def damage_of(recording: Recording) -> Damaged | None:
    """What was damaged in ``recording``; None where every file was read whole."""
    problems = [line for source in recording.contents.files for line in source.problems]
    if not problems:
        return None
    start = recording.start
    spans = sorted(span for source in recording.contents.files for span in source.damaged)
    return Damaged(problems[0], tuple((max(a - start, 0), max(b - start, 0)) for a, b in spans))


def damage_notes(
    differences: Sequence[Difference], a: Damaged | None, b: Damaged | None, names: tuple[str, str] = ("A", "B")
) -> tuple[str, ...]:
    """For each difference, what says a damaged side may have made it ("" where neither side's damage can): a
    frame missing from a damaged side, a damaged side's lower rate or early stop (transforms lost there count as
    silence), a fixed value moved where a side holds values read from damaged bytes; for a difference said with
    others (``Difference.folded``), what each of them says, once each."""
    return tuple(_notes(d, a, b, names) for d in differences)


def _notes(d: Difference, a: Damaged | None, b: Damaged | None, names: tuple[str, str]) -> str:
    """What a damaged side may have made of ``d`` and of each difference said with it (``folded``), once each."""
    notes = dict.fromkeys(_note(one, a, b, names) for one in (d, *d.folded))
    return "; ".join(note for note in notes if note)


def _note(d: Difference, a: Damaged | None, b: Damaged | None, names: tuple[str, str]) -> str:
    sides = ((names[0], a, d.before), (names[1], b, d.after))
    if d.change is Change.lost:
        return _said(names[1], b, "the frame may have been sent only in what was lost")
    if d.change is Change.added:
        return _said(names[0], a, "the frame may have been sent only in what was lost")
    if d.change is Change.rate and d.before is not None and d.after is not None:
        was, now = d.before.rate_hz, d.after.rate_hz
        slower = 1 if (now or 0.0) < (was or 0.0) else 0
        name, damaged, _ = sides[slower]
        return _said(name, damaged, "the transforms lost there count as silence in its rate")
    if d.change is Change.stopped:
        for name, damaged, shape in sides:
            tail = shape.tail if shape is not None else None
            if tail is not None and tail.stopped and damaged is not None:
                reaches = not damaged.lost or any(end >= tail.arrived for _, end in damaged.lost)
                return _said(name, damaged, "it may have been sent on in what was lost") if reaches else ""
        return ""
    if d.change is Change.moved:
        notes = [_said(name, damaged, "a value read from damaged bytes may be wrong") for name, damaged, _ in sides]
        return "; ".join(note for note in notes if note)
    return ""


def _said(name: str, damaged: Damaged | None, why: str) -> str:
    if damaged is None:
        return ""
    if not damaged.lost:
        return f"{name} was read only in part ({damaged.problem}); {why}"
    (first, last), more = damaged.lost[0], len(damaged.lost) - 1
    where = f"its transforms from {first / 1e9:.1f} s to {last / 1e9:.1f} s into it were lost"
    where += f" (and in {more} more stretch{'es' if more > 1 else ''})" if more else ""
    return f"{name} is damaged: {where}; {why}"
