"""What the commands share when they listen to a live system instead of reading a bag."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

from tftools.cli.arguments import positive_seconds
from tftools.cli.common import stderr, warn
from tftools.cli.errors import UsageError
from tftools.core.semantics import Semantics
from tftools.render.escape import printable

if TYPE_CHECKING:
    from tftools.sources import Recording
    from tftools.sources.live import LiveSource
    from tftools.sources.live.capture import Waiting


def say(message: str) -> None:
    """A line on stderr about what tfx is doing: one line, names from peers escaped, no markup."""
    stderr.print(f"tfx: {printable(message)}")


def ros_name(ros1: bool | None) -> str | None:
    """``--ros1/--ros2`` as ``open_live`` names them (None: neither given)."""
    return None if ros1 is None else ("ros1" if ros1 else "ros2")


def open_source(ros1: bool | None, use_sim_time: bool | None, topics: Sequence[str] | None) -> LiveSource:
    """The live system the environment or ``--ros1/--ros2`` names, its notices as warnings."""
    from tftools.sources.live import open_live  # the live modules load only when listening

    return open_live(ros_name(ros1), use_sim_time, topics, on_notice=warn, name="tfx")


def capture_live(
    ros1: bool | None,
    use_sim_time: bool | None,
    duration: float,
    topics: Sequence[str] | None = None,
    semantics: Semantics | None = None,
    headers: Sequence[str] | None = None,
) -> Recording:
    """What the live system says in ``duration`` seconds (``sources.live.capture_live``: tf, and with
    ``headers``, the headers of the sensor data on those topics, () every topic with a header)."""
    from tftools.sources.live.sensor_headers import capture_live as capture

    source = start_listening(ros1, use_sim_time, duration, topics)
    with heard(duration):
        return capture(source, duration, headers, semantics=semantics)


def capture_recording(
    source: LiveSource,
    duration: float,
    sensor_topics: Sequence[str] | None,
    semantics: Semantics | None = None,
    *,
    require_tf: bool = True,
) -> Recording:
    """What ``source`` (``start_listening``'s) says in ``duration`` seconds, with the headers of the
    ``sensor_topics`` (none unless named: listening to every camera would load the network), as a recording
    for ``tfx wtf`` and ``tfx report``'s one call; what could not be heard is said as warnings, and hearing no
    transform (when ``require_tf``) as the command's error."""
    from tftools.sources.live.sensor_headers import capture_live as capture

    with heard(duration):
        recording = capture(source, duration, sensor_topics or None, semantics=semantics, require_tf=require_tf)
    for problem in [*recording.stamped.problems, *recording.problems]:
        warn(problem)
    return recording


def start_listening(
    ros1: bool | None, use_sim_time: bool | None, duration: float, topics: Sequence[str] | None = None
) -> LiveSource:
    """The live system to listen to ``duration`` seconds (``open_source``), said on stderr."""
    positive_seconds(duration, "--duration")
    source = open_source(ros1, use_sim_time, topics)
    say(f"listening to {source.describe()} for {duration:g} s")
    return source


@contextlib.contextmanager
def heard(duration: float) -> Iterator[None]:
    """The library's ``NoTransformsHeardError`` in the command line's words."""
    from tftools.sources.live.errors import NoTransformsHeardError

    try:
        yield
    except NoTransformsHeardError as error:
        raise UsageError(str(error), f"{error.hint} with --duration") from None


def no_bag_options(**given: object) -> None:
    """Refuse options that only make sense on a bag (``given``: option name -> value if given)."""
    used = [name for name, value in given.items() if value not in (None, False)]
    if used:
        raise UsageError(f"{', '.join(used)} only work on a bag", "give one with -b BAG")


def remind(waiting: Waiting) -> None:
    """Say on stderr why the transform awaited is not there yet (``sources.live.capture.wait_for_transform``)."""
    frames = ", ".join(waiting.frames[:12]) or "none yet"
    say(f"still waiting ({waiting.waited:.0f} s): {waiting.reason} Frames heard: {frames}")
