"""The commands' work on a live system, one call each, as on a bag: ``check_live`` (``tfx wtf``),
``report_live`` (``tfx report``), ``filter_live`` (``tfx filter``), ``echo_live`` (``tfx echo``).

Each is given a live source not yet started (``sources.live.open_live``), listens to it, and closes it;
what it has to say while it works goes to callbacks (``on_problem``, ``on_reminder``), never to a terminal."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Sequence

from tftools.analysis.echo import EchoSeries, echo_latest
from tftools.analysis.filter import FilterReport, filter_heard
from tftools.analysis.report import RecordingReport, report_read
from tftools.analysis.wtf.fleet import BagReport, Checks, check_read
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.frames import frame_name
from tftools.core.semantics import Semantics
from tftools.sources.live.base import LiveSource
from tftools.sources.live.capture import Waiting, listen, wait_for_transform
from tftools.sources.live.sensor_headers import capture_live
from tftools.sources.recording import Recording
from tftools.sources.ticker import tick_every
from tftools.sources.urdf import RobotDescription

__all__ = ["Waiting", "capture_live", "check_live", "echo_live", "filter_live", "report_live"]

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


def filter_live(
    source: LiveSource,
    duration: float = 5.0,
    target: str | None = None,
    topics: Sequence[str] | None = None,
    *,
    cache_time: int = DEFAULT_CACHE_TIME,
    wait: int | None = None,
    queue: int | None = None,
    semantics: Semantics | None = None,
    on_problem: OnProblem | None = None,
) -> FilterReport:
    """``tfx filter`` without bags: ``filter_recording`` of what ``source`` says in ``duration`` seconds, tf
    and the headers of the sensor ``topics`` (default: every topic whose messages start with a header).
    Raises ``NoTransformsHeardError``, or ``NoStampedDataError`` when no sensor data was heard."""
    recording = capture_live(source, duration, tuple(topics or ()), semantics=semantics)
    return filter_heard(recording, target, cache_time, wait, queue, on_problem)


def echo_live(
    source: LiveSource,
    target: str,
    source_frame: str,
    on_series: Callable[[EchoSeries, Buffer], object],
    rate: float = 1.0,
    count: int | None = None,
    *,
    wait: float | None = None,
    cache_time: int = DEFAULT_CACHE_TIME,
    semantics: Semantics | None = None,
    on_reminder: Callable[[Waiting], object] | None = None,
) -> None:
    """``tfx echo`` without bags, as tf_echo: listen to ``source`` into a buffer of ``cache_time``, wait for
    ``target`` <- ``source_frame`` (``wait`` seconds at most: ``TransformNotHeardError``; meanwhile
    ``on_reminder``, as ``wait_for_transform``), then give ``on_series`` the latest one (``echo_latest``)
    and the buffer (its frames, to say after a failure) ``rate`` times a second of the source's clock,
    ``count`` times, or until the source ends or Ctrl-C."""
    target, source_frame = frame_name(target), frame_name(source_frame)
    with source:
        buffer = listen(source, cache_time, semantics)
        wait_for_transform(buffer, target, source_frame, wait, on_reminder)

        def tick() -> None:
            on_series(echo_latest(buffer, target, source_frame), buffer)

        with contextlib.suppress(KeyboardInterrupt):
            tick_every(1.0 / rate, tick, count=count, stop=lambda: source.finished, clock=source.clock)


def _stamped_problems(recording: Recording) -> list[str]:
    return recording.stamped.problems


def _tell(problems: Sequence[str], on_problem: OnProblem | None) -> None:
    if on_problem is not None:
        for problem in problems:
            on_problem(problem)
