"""The commands' work on a live system, one call each, as on a bag: ``check_live`` (``tfx wtf``),
``report_live`` (``tfx report``). (``tfx filter`` captures a recording and makes its one call on it;
``tfx echo`` streams: ``analysis.echo.echo_stream``.)

Each is given a live source not yet started (``sources.live.open_live``), listens to it, and closes it;
what it has to say while it works goes to callbacks (``on_problem``, ``on_reminder``), never to a terminal."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from tftools.analysis.report import RecordingReport, report_read
from tftools.analysis.wtf.fleet import BagReport, Checks, check_read
from tftools.core.semantics import Semantics
from tftools.sources.live.base import LiveSource
from tftools.sources.live.capture import Waiting
from tftools.sources.live.sensor_headers import capture_live
from tftools.sources.recording import Recording
from tftools.sources.urdf import RobotDescription

__all__ = ["Waiting", "capture_live", "check_live", "report_live"]

OnProblem = Callable[[str], object]


def check_live(
    source: LiveSource, duration: float = 5.0, checks: Checks | None = None, on_problem: OnProblem | None = None
) -> BagReport:
    """``tfx wtf`` without bags: ``check_bags``' checks (``checks``, as ``check_fleet`` takes them; the tf
    topics are the source's) on what ``source`` says in ``duration`` seconds, the headers of the
    ``sensor_topics`` (none unless named: listening to every camera would load the network) with it.
    Hearing no transform is the ``no_tf`` finding; what could not be heard goes to ``on_problem``."""
    checks = checks or {}
    sensors = checks.get("sensor_topics")
    recording = capture_live(source, duration, sensors or None, semantics=checks.get("semantics"), require_tf=False)
    _tell([*_stamped_problems(recording), *recording.problems], on_problem)
    return check_read(
        recording,
        thresholds=checks.get("thresholds"),
        ignore=checks.get("ignore", ()),
        target=checks.get("target"),
        sensor_topics=sensors,
        expected=checks.get("expected"),
        urdf=checks.get("urdf"),
        urdf_tolerances=checks.get("urdf_tolerances"),
    )


def report_live(
    source: LiveSource,
    duration: float = 5.0,
    target: str | None = None,
    sensor_topics: Sequence[str] | None = None,
    urdf: RobotDescription | None = None,
    semantics: Semantics | None = None,
    on_problem: OnProblem | None = None,
) -> RecordingReport:
    """``tfx report`` without bags: ``report_bags``' report of what ``source`` says in ``duration`` seconds
    (and the headers of the ``sensor_topics``, none unless named); what could not be heard of them goes to
    ``on_problem``. Hearing no transform is a ``NoTransformsHeardError``."""
    recording = capture_live(source, duration, sensor_topics or None, semantics=semantics)
    _tell(_stamped_problems(recording), on_problem)
    return report_read(recording, target=target, sensor_topics=sensor_topics, urdf=urdf)


def _stamped_problems(recording: Recording) -> list[str]:
    return [problem for info in recording.contents.files for problem in info.stamped_problems]


def _tell(problems: Sequence[str], on_problem: OnProblem | None) -> None:
    if on_problem is not None:
        for problem in problems:
            on_problem(problem)
