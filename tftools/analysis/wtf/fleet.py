"""Checking bags: each recording of a fleet (one bag or a split one) into a ``BagReport``."""

from __future__ import annotations

import functools
import os
from collections.abc import Collection, Iterator, Sequence
from dataclasses import dataclass, field
from typing import TypedDict

from tftools.analysis.description import Robot, robot_of
from tftools.analysis.expected import Tolerances, TreeShape
from tftools.analysis.filter import choose_target, tied_to_tf
from tftools.analysis.findings import Finding, Severity, causes
from tftools.analysis.fleet import HERE, Fleet, Unfinished, run_fleet
from tftools.analysis.wtf import Scene, findings_of
from tftools.analysis.wtf.causes import explain
from tftools.analysis.wtf.thresholds import Thresholds
from tftools.core.errors import TfToolsError
from tftools.core.semantics import Semantics
from tftools.sources.bag import ProgressCallback
from tftools.sources.bag.robot import ROBOT_TOPICS
from tftools.sources.contents import Fetched, StampedMessages
from tftools.sources.recording import Recording, read_recording
from tftools.sources.urdf import RobotDescription


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
    sensor_target: str = ""  # the frame that data was checked in
    sensor_target_reason: str = ""
    fetched: tuple[Fetched, ...] = ()  # of each file read by URL: what was fetched of it

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


def check_bags(
    paths: Sequence[str | os.PathLike[str]],
    topics: Sequence[str] | None = None,
    thresholds: Thresholds | None = None,
    ignore: Collection[str] = (),
    progress: ProgressCallback | None = None,
    semantics: Semantics | None = None,
    target: str | None = None,
    sensor_topics: Sequence[str] | None = None,
    expected: TreeShape | None = None,
    urdf: RobotDescription | None = None,
    urdf_tolerances: Tolerances | None = None,
) -> BagReport:
    """Read ``paths`` as one recording and check it, its sensor data (``sensor_topics``, default:
    every topic whose messages start with a header) against tf in ``target`` (``choose_target``),
    against the ``expected`` tree if given, and against the robot's description (``urdf``, else the
    recorded /robot_description: ``robot_of``); a bag that cannot be read is reported, not raised."""
    names = tuple(str(p) for p in paths)
    try:
        headers = tuple(sensor_topics or ())
        recording = read_recording(
            paths, topics, progress, allow_empty=True, semantics=semantics, headers=headers, whole=ROBOT_TOPICS
        )
    except TfToolsError as error:
        return unreadable(names, str(error), error.hint)
    except Exception as error:  # a reader's bug on a strange file must not stop a fleet, nor pass for damage
        return unreadable(
            names,
            f"{names[0]}: internal error of tftools while reading it ({type(error).__name__}: {error})",
            "this is a bug in tftools, not necessarily in the file: please report it with the file",
        )
    return check_read(recording, paths, thresholds, ignore, target, sensor_topics, expected, urdf, urdf_tolerances)


def check_read(
    recording: Recording,
    paths: Sequence[str | os.PathLike[str]] = (),
    thresholds: Thresholds | None = None,
    ignore: Collection[str] = (),
    target: str | None = None,
    sensor_topics: Sequence[str] | None = None,
    expected: TreeShape | None = None,
    urdf: RobotDescription | None = None,
    urdf_tolerances: Tolerances | None = None,
) -> BagReport:
    """``check_bags`` of a recording read from ``paths`` (or heard: ``analysis.live.check_live``), its sensor
    data the headers it was read with."""
    robot, said = robot_of(paths, recording, urdf, urdf_tolerances or (expected.tolerances if expected else None))
    streams = recording.stamped.streams
    checked = check_recording(recording, streams, thresholds, ignore, target, expected, robot)
    if said is not None and said.code not in ignore:
        checked.findings = explain([*checked.findings, said])
    return checked


class Checks(TypedDict, total=False):
    """``check_bags``' options of each recording's check, for ``check_fleet``."""

    topics: Sequence[str] | None
    thresholds: Thresholds | None
    ignore: Collection[str]
    semantics: Semantics | None
    target: str | None
    sensor_topics: Sequence[str] | None
    expected: TreeShape | None
    urdf: RobotDescription | None
    urdf_tolerances: Tolerances | None


def check_fleet(
    groups: Sequence[Sequence[str]],
    fleet: Fleet = HERE,
    done: Sequence[BagReport] = (),
    progress: ProgressCallback | None = None,
    checks: Checks | None = None,
) -> Iterator[BagReport]:
    """Each group of paths checked as its own recording (``check_bags`` with ``checks``) on ``fleet``, its
    report yielded as it finishes; a check that did not finish is a report that says so (code
    ``unchecked``). The reports ``done`` (of an earlier run) come first, and their recordings are not
    checked again (``remaining``). ``progress`` is told the bytes read when the fleet is one recording
    checked in this process."""
    one = functools.partial(check_bags, **(checks or {}))
    todo = remaining(groups, done)
    if progress is not None and len(todo) == 1 and fleet.dask is None:
        one = functools.partial(one, progress=progress)
    yield from done
    for index, result in run_fleet(todo, one, fleet):
        yield unchecked(tuple(todo[index]), result.why, result.hint) if isinstance(result, Unfinished) else result


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


def check_recording(
    recording: Recording,
    streams: Sequence[StampedMessages] = (),
    thresholds: Thresholds | None = None,
    ignore: Collection[str] = (),
    target: str | None = None,
    expected: TreeShape | None = None,
    robot: Robot | None = None,
) -> BagReport:
    """Check a recording read (or heard) and its sensor data ``streams`` against tf in ``target``
    (and against the ``expected`` tree, and the ``robot``'s description)."""
    scene = Scene(recording, thresholds, streams, target, expected, robot)
    checked = BagReport(
        paths=tuple(recording.paths),
        findings=findings_of(scene, ignore),
        formats=tuple(dict.fromkeys(f.format for f in recording.contents.files)),
        start=recording.start,
        end=recording.end,
        transforms=recording.transform_count,
        frames=len(recording.buffer.frames),
        fetched=tuple(f.fetched for f in recording.contents.files if f.fetched is not None),
    )
    if any(tied_to_tf(s) for s in streams):
        checked.sensor_topics = tuple(s.topic for s in streams if tied_to_tf(s))
        checked.sensor_target, checked.sensor_target_reason = choose_target(scene.tree, target)
    return checked


def unreadable(paths: tuple[str, ...], message: str, hint: str) -> BagReport:
    hint = hint or "check that the file is a complete bag"
    return BagReport(paths, error=Finding(Severity.error, "unreadable", message, hint))


def unchecked(paths: tuple[str, ...], why: str, hint: str) -> BagReport:
    """A recording whose check did not finish (its worker died, it ran out of time): said, not passed."""
    message = f"{' + '.join(paths)}: not checked: {why}"
    return BagReport(paths, error=Finding(Severity.error, "unchecked", message, hint))
