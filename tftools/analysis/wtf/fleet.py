"""``tfx wtf``'s one call: ``check(recording, query)``, a recording's ``BagReport``; and ``check_fleet``, each
recording of a fleet (one bag or a split one) read and checked."""

from __future__ import annotations

import functools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

from tftools.analysis.description import robot_of
from tftools.analysis.findings import Finding, Severity, causes
from tftools.analysis.fleet import HERE, Fleet, Unfinished, run_fleet
from tftools.analysis.reading import Progress, unwatched
from tftools.analysis.targets import choose_target, tied_to_tf
from tftools.analysis.wtf import Scene, findings_of
from tftools.analysis.wtf.causes import explain
from tftools.analysis.wtf.query import CHECK_DEFAULTS, CheckQuery
from tftools.core.errors import TfToolsError
from tftools.sources.contents import Fetched
from tftools.sources.recording import Recording


@dataclass
class BagReport:
    """What checking one recording found; ``error`` (code ``unreadable``) when it could not be read."""

    paths: tuple[str, ...]
    findings: list[Finding] = field(default_factory=list)
    error: Finding | None = None
    formats: tuple[str, ...] = ()
    start: int = 0  # record time of its first message (ns)
    end: int = 0
    transforms: int = 0
    frames: int = 0
    sensor_topics: tuple[str, ...] = ()  # topics of data with a header, checked against tf
    sensor_target: str = ""  # the frame that data was checked in; "" where there is no tree (targets.NO_TREE)
    sensor_target_reason: str = ""
    fetched: tuple[Fetched, ...] = ()  # of each file read by URL: what was fetched of it
    #: tf's first and last stamp (ns, ``Timeline.stamped``) where the record times are no clock (``start`` to
    #: ``end`` spans nothing); None where they are one.
    stamped: tuple[int, int] | None = None

    @property
    def name(self) -> str:
        return " + ".join(self.paths)

    @property
    def usable(self) -> bool:
        return self.error is None

    def count(self, severity: Severity) -> int:
        """Findings of ``severity`` that follow from no other (``Finding.cause``), or the error."""
        return sum(f.severity is severity for f in causes(self.findings)) + (
            self.error is not None and severity is Severity.error
        )

    def failed(self, strict: bool = False) -> bool:
        """Errors (or, ``strict``, warnings too) found, or the bag could not be read."""
        return self.error is not None or any(f.severity.fails(strict) for f in causes(self.findings))


def check(recording: Recording, query: CheckQuery = CHECK_DEFAULTS) -> BagReport:
    """``tfx wtf``'s check of ``recording`` (read from files or URLs with ``query.reading()``, or captured live):
    every check but those ignored, its sensor data (the headers it was read with) against tf, against the
    expected tree if given, and against the robot's description (``robot_of``)."""
    scene, findings = checked_scene(recording, query)
    streams, timeline = scene.streams, scene.timeline
    checked = BagReport(
        paths=tuple(recording.paths),
        findings=findings,
        formats=tuple(dict.fromkeys(f.format for f in recording.contents.files)),
        start=recording.start,
        end=recording.end,
        stamped=timeline.stamped,
        transforms=recording.transform_count,
        frames=len(recording.buffer.frames),
        fetched=tuple(f.fetched for f in recording.contents.files if f.fetched is not None),
    )
    if any(tied_to_tf(s) for s in streams):
        checked.sensor_topics = tuple(s.topic for s in streams if tied_to_tf(s))
        checked.sensor_target, checked.sensor_target_reason = choose_target(scene.tree, query.target)
    return checked


def checked_scene(recording: Recording, query: CheckQuery = CHECK_DEFAULTS) -> tuple[Scene, list[Finding]]:
    """The one list of ``tfx wtf``'s checks, which view-frames and the report run too (so that every command
    counts the same findings): the scene of ``recording`` with its sensor data (the headers it was read with)
    and its robot's description (``robot_of``: ``query.urdf``, else a recorded /robot_description), and
    every finding but those ``query.ignore`` s, each under the one that explains it."""
    robot, said = robot_of(recording.paths, recording, query.urdf, query.robot_tolerances)
    scene = Scene(recording, query.thresholds, recording.stamped.streams, query.target, query.expected, robot)
    findings = findings_of(scene, query.ignore)
    if said is not None and said.code not in query.ignore:
        findings = explain([*findings, said])
    return scene, findings


def check_fleet(
    sources: Sequence[Sequence[str]],
    query: CheckQuery = CHECK_DEFAULTS,
    fleet: Fleet = HERE,
    *,
    done: Sequence[BagReport] = (),
    progress: Progress | None = None,
) -> Iterator[BagReport]:
    """Each group of paths or URLs in ``sources`` read as its own recording and checked (``check``) on
    ``fleet``, its report yielded as it finishes; one that cannot be read is a report that says so (code
    ``unreadable``), one whose check did not finish too (code ``unchecked``). The reports ``done`` (of an
    earlier run) come first, and their recordings are not checked again (``remaining``). ``progress``: for
    each recording read in this process, a context told the bytes read (a progress bar)."""
    todo = remaining(sources, done)
    yield from done
    task = functools.partial(_check_group, query, progress or unwatched)
    for index, result in run_fleet(todo, task, fleet):
        yield unchecked(tuple(todo[index]), result) if isinstance(result, Unfinished) else result


def _check_group(query: CheckQuery, progress: Progress, paths: Sequence[str]) -> BagReport:
    """One recording of a fleet read and checked (``progress`` told of it throughout); one that cannot be
    read is reported, not raised."""
    names = tuple(str(p) for p in paths)
    with progress(paths) as told:
        try:
            recording = query.reading().read(paths, told)
        except TfToolsError as error:
            return unreadable(names, str(error), error.hint)
        except Exception as error:  # a reader's bug on a strange file must not stop a fleet, nor pass for damage
            return unreadable(
                names,
                f"{names[0]}: internal error of tftools while reading it ({type(error).__name__}: {error})",
                "this is a bug in tftools, not necessarily in the file: please report it with the file",
            )
        return check(recording, query)


def remaining(groups: Sequence[Sequence[str]], done: Sequence[BagReport]) -> list[list[str]]:
    """The groups of paths that no report of ``done`` is about."""
    finished = {bag.paths for bag in done}
    return [list(g) for g in groups if tuple(g) not in finished]


def in_order(groups: Sequence[Sequence[str]], reports: Sequence[BagReport]) -> list[BagReport]:
    """The reports in the order of ``groups``, then those about recordings not in ``groups``."""
    by_paths = {bag.paths: bag for bag in reports}
    given = [tuple(g) for g in groups]
    return [by_paths[g] for g in given] + [bag for paths, bag in by_paths.items() if paths not in given]


def exit_code(reports: Sequence[BagReport], strict: bool = False) -> int:
    """``tfx wtf``'s exit code (its JSON's ``exit_code``): 2 when no recording could be read, 1 when any failed
    (``BagReport.failed``) or could not be read, else 0."""
    if not any(r.usable for r in reports):
        return 2
    return 1 if any(r.failed(strict) for r in reports) else 0


def unreadable(paths: tuple[str, ...], message: str, hint: str) -> BagReport:
    hint = hint or "check that the file is a complete bag"
    return BagReport(paths, error=Finding(Severity.error, "unreadable", message, hint))


def unchecked(paths: tuple[str, ...], unfinished: Unfinished) -> BagReport:
    """A recording whose check did not finish (its worker died, it ran out of time): said, not passed; its
    ``UnfinishedCause`` in the finding's figures (``cause``)."""
    message = f"{' + '.join(paths)}: not checked: {unfinished.why}"
    figures: dict[str, float | int | str] = {"cause": unfinished.cause.value}
    return BagReport(paths, error=Finding(Severity.error, "unchecked", message, unfinished.hint, figures=figures))
