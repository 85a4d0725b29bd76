"""The one error hierarchy of lookups, with tf2's meanings and tf2's message text."""

from __future__ import annotations

from typing import Any


class TfToolsError(Exception):
    """Base of every error tftools raises on purpose; the CLI prints it as one line. It pickles whole (its
    class and attributes), so that one met in a worker process reaches the command line as it was raised."""

    hint: str = ""

    def __reduce__(self) -> tuple[Any, ...]:
        # not Exception's: that calls the class with ``args`` (the message), which its constructor does not take
        return _rebuilt, (type(self), self.args), self.__dict__


def _rebuilt(kind: type[TfToolsError], args: tuple[Any, ...]) -> TfToolsError:
    """An error of ``kind`` with ``args``, its constructor not called (pickle then restores its attributes)."""
    error = kind.__new__(kind, *args)
    error.args = args
    return error


class FleetUnavailableError(TfToolsError):
    """A fleet's engine cannot run: Dask's distributed package is not installed (``address`` None), or the
    scheduler at ``address`` is not one, or cannot be reached (``problem`` says which)."""

    def __init__(self, address: str | None, problem: str, hint: str = "") -> None:
        super().__init__(problem if address is None else f"{address}: {problem}")
        self.address = address
        self.problem = problem
        self.hint = hint


class InvalidTransformError(TfToolsError):
    """A transform that cannot be given to tf2 (empty or equal frames, numbers not finite, a zero quaternion),
    or that a recording already has (``recording``: where)."""

    def __init__(self, problem: str, hint: str = "", *, child: str = "", recording: str = "") -> None:
        super().__init__(problem)
        self.problem = problem
        self.hint = hint
        self.child = child
        self.recording = recording


class TransformError(TfToolsError):
    """A lookup failed: tf2's ``TransformException``."""


class UnknownFrameError(TransformError):
    """A frame is not in the buffer, or the graph loops: tf2's ``LookupException``. One someone asked for
    (``absent``) carries the facts: the ``frame`` given and the ``frames`` there are, closest first."""

    frame: str = ""
    frames: tuple[str, ...] = ()

    @classmethod
    def absent(cls, frame: str, frames: tuple[str, ...]) -> UnknownFrameError:
        shown = ", ".join(frames[:20]) + (", ..." if len(frames) > 20 else "")
        error = cls(f"frame {frame!r} does not exist")
        error.frame, error.frames = frame, frames
        # none at all: the transforms were refused (or absent), which a list of frames cannot say
        error.hint = f"frames: {shown}" if frames else "no frame at all: tf2 kept no transform"
        return error

    @classmethod
    def missing(cls, frame: str, argument: str) -> UnknownFrameError:
        return cls(f'"{frame}" passed to {argument} does not exist. ')

    @classmethod
    def loop(cls, frames_as_string: str) -> UnknownFrameError:
        return cls("The tf tree is invalid because it contains a loop.\n" + frames_as_string + "\n")


class ConnectivityError(TransformError):
    """The two frames are in different trees: tf2's ``ConnectivityException``."""

    @classmethod
    def between(cls, target: str, source: str) -> ConnectivityError:
        return cls(
            f"Could not find a connection between '{target}' and '{source}' because they are "
            "not part of the same tree.Tf has two or more unconnected trees."
        )


class ExtrapolationError(TransformError):
    """The time is outside an edge's history: tf2's ``ExtrapolationException``."""


# ROS 2's tf2 (Jazzy and later) raises these subclasses; ROS 1's and Humble's raise the base class.
class ForwardExtrapolationError(ExtrapolationError):
    """Later than an edge's newest sample: ROS 2's ``ForwardExtrapolationException``."""


class BackwardExtrapolationError(ExtrapolationError):
    """Earlier than an edge's oldest sample: ROS 2's ``BackwardExtrapolationException``."""


class NoDataForExtrapolationError(ExtrapolationError):
    """Not the time of an edge's only sample: ROS 2's ``NoDataForExtrapolationException``."""


class InvalidArgumentError(TransformError):
    """An empty frame id or one with a leading slash: tf2's ``InvalidArgumentException`` (its texts:
    ``semantics.Dialect``)."""


class InvalidTimeError(TfToolsError):
    """A time asked of a recording that cannot be one: ``text`` as given (``"+99999"``), ``role`` which time
    of the question it is (``"at"``, ``"start"``, ``"end"``), ``reason`` what is wrong with it, ``span`` the
    recording's tf span on the asked frames' clock (ns), None where the text is not a time at all."""

    def __init__(self, text: str, span: tuple[int, int] | None, reason: str, role: str = "time") -> None:
        super().__init__(f"{role} {text}: {reason}")
        self.text, self.span, self.reason, self.role = text, span, reason, role


class TimeRangeError(TfToolsError):
    """A time range with nothing in it: its end before its start (``span`` None), or outside the recording's
    tf, whose ``span`` (ns) it carries."""

    def __init__(self, span: tuple[int, int] | None = None) -> None:
        super().__init__("the time range is empty" if span is None else "the time range is outside the recording")
        self.span = span


class TooManyLinesError(TfToolsError):
    """An echo over a range at a rate that would give more than ``limit`` lookups (``lines`` of them over
    ``length`` seconds at ``rate`` a second)."""

    def __init__(self, lines: int, rate: float, length: float, limit: int) -> None:
        super().__init__(f"{lines:,} lookups over {length:.3f} s at {rate:g} a second: at most {limit:,}")
        self.lines, self.rate, self.length, self.limit = lines, rate, length, limit
