"""What the commands share when they listen to a live system instead of reading a bag."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from tftools.cli.arguments import positive_seconds
from tftools.cli.common import stderr, warn
from tftools.core.errors import TransformError, UsageError
from tftools.core.semantics import Semantics
from tftools.core.time import Clock
from tftools.render.escape import printable

if TYPE_CHECKING:
    from tftools.core.buffer import Buffer
    from tftools.sources import Recording
    from tftools.sources.contents import StampedMessages
    from tftools.sources.headers import StampedRead
    from tftools.sources.live import LiveSource

#: Seconds between "still waiting" notices.
REMIND_EVERY = 5.0


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
    sensors: Sequence[str] | None = None,
    *,
    require_tf: bool = True,
) -> tuple[Recording, list[StampedMessages]]:
    """What the live system says in ``duration`` seconds: tf, and the headers of the ``sensors`` topics
    (none unless named: listening to every camera would load the network), their problems as warnings.
    Hearing no transform is an error, unless not ``require_tf``."""
    from tftools.sources.live.capture import capture
    from tftools.sources.live.sensor_headers import capture_stamped

    source = _start_listening(ros1, use_sim_time, duration, topics)
    if not sensors:
        recording, streams = capture(source, duration, semantics=semantics), []
    else:
        recording, stamped = capture_stamped(source, duration, sensors, semantics=semantics)
        streams = stamped.streams
        for problem in stamped.problems:
            warn(problem)
    return _transforms_heard(recording, source, duration) if require_tf else recording, streams


def capture_with_headers(
    ros1: bool | None,
    use_sim_time: bool | None,
    duration: float,
    sensor_topics: Sequence[str] | None,
    semantics: Semantics | None,
) -> tuple[Recording, StampedRead]:
    """As ``capture_live`` (tf on /tf and /tf_static), and the headers of the sensor topics heard
    meanwhile (default: every topic whose messages start with a header), their problems not yet said."""
    from tftools.sources.live.sensor_headers import capture_stamped

    source = _start_listening(ros1, use_sim_time, duration)
    recording, stamped = capture_stamped(source, duration, sensor_topics, semantics=semantics)
    return _transforms_heard(recording, source, duration), stamped


def _start_listening(
    ros1: bool | None, use_sim_time: bool | None, duration: float, topics: Sequence[str] | None = None
) -> LiveSource:
    positive_seconds(duration, "--duration")
    source = open_source(ros1, use_sim_time, topics)
    say(f"listening to {source.describe()} for {duration:g} s")
    return source


def _transforms_heard(recording: Recording, source: LiveSource, duration: float) -> Recording:
    if not recording.transform_count:
        heard = ", ".join(recording.contents.topics)
        raise UsageError(
            f"no transforms on {heard} from {source.describe()} in {duration:g} s",
            "is anything publishing? (rostopic info /tf) listen longer with --duration",
        )
    return recording


def no_bag_options(**given: object) -> None:
    """Refuse options that only make sense on a bag (``given``: option name -> value if given)."""
    used = [name for name, value in given.items() if value not in (None, False)]
    if used:
        raise UsageError(f"{', '.join(used)} only work on a bag", "give one with -b BAG")


def wait_for_transform(buffer: Buffer, target: str, source: str, what: str, timeout: float | None) -> None:
    """Block until ``target`` <- ``source`` can be looked up, saying on stderr what is awaited
    (and, every few seconds, why it is not there yet); ``timeout`` seconds (None: for ever)."""
    started = time.monotonic()
    say(f"listening to {what}; waiting for the transform {target} <- {source}")
    while True:
        patience = REMIND_EVERY if timeout is None else min(REMIND_EVERY, started + timeout - time.monotonic())
        try:
            buffer.wait_for_transform(target, source, 0, max(patience, 0.0))
            return
        except TransformError as error:
            reason = str(error).strip().split("\n")[0]
            waited = time.monotonic() - started
            if timeout is not None and waited >= timeout:
                raise UsageError(
                    f"no transform {target} <- {source} from {what} after {waited:.1f} s: {reason}",
                    "check the frame names with `tfx frames`, or wait longer with --wait",
                ) from None
            frames = ", ".join(buffer.frames[:12]) or "none yet"
            say(f"still waiting ({waited:.0f} s): {reason} Frames heard: {frames}")


def every(
    rate: float, count: int | None, stop: Callable[[], bool], on_tick: Callable[[], None], clock: Clock | None = None
) -> None:
    """Call ``on_tick`` ``rate`` times a second, ``count`` times (None: until ``stop()`` or Ctrl-C), the
    first at once; seconds of ``clock`` when it is a ``SimClock``, else of the wall (``tick_every``)."""
    from tftools.sources.ticker import tick_every

    with contextlib.suppress(KeyboardInterrupt):
        tick_every(1.0 / rate, on_tick, count=count, stop=stop, clock=clock)
