"""Reading the recording a command is given, with a progress bar, and saying what could not be read; without
bags, listening to the live system (``cli.live``)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, TypeVar

from tftools.cli.common import progress_bar, warn
from tftools.core.semantics import Semantics

if TYPE_CHECKING:  # the readers load when a command reads: its --help needs none of them (nor numpy)
    from tftools.sources import Recording
    from tftools.sources.bag import ProgressCallback
    from tftools.sources.stream import StreamedRecording


def open_recording(
    bags: Sequence[str] | None,
    topics: Sequence[str] | None,
    semantics: Semantics | None = None,
    ros1: bool | None = None,
    use_sim_time: bool | None = None,
    duration: float = 5.0,
    headers: Sequence[str] | None = None,
    whole: Sequence[str] = (),
) -> Recording:
    """Read the bags into one recording (and with ``headers``, its sensor data's headers on them, and the
    messages of the ``whole`` topics, in the same pass: ``read_recording``), with a progress bar; report
    what could not be read.

    Without bags: what the live system says in ``duration`` seconds (``tftools.cli.live``)."""
    if not bags:
        from tftools.cli.live import capture_live  # the live modules load only when listening

        return capture_live(ros1, use_sim_time, duration, topics, semantics, headers)
    from tftools.sources import read_recording

    return _read(
        bags, lambda progress: read_recording(bags, topics, progress, semantics=semantics, headers=headers, whole=whole)
    )


def open_stream(bags: Sequence[str], topics: Sequence[str] | None, semantics: Semantics | None) -> StreamedRecording:
    """The bags as a stream to replay (``stream_recording``), with a progress bar over the first pass;
    report what could not be read."""
    from tftools.sources.stream import stream_recording  # only a replay streams

    return _read(bags, lambda progress: stream_recording(bags, topics, progress, semantics=semantics))


Read = TypeVar("Read", "Recording", "StreamedRecording")


def _read(bags: Sequence[str], read: Callable[[ProgressCallback | None], Read]) -> Read:
    with progress_bar(bags) as progress:
        recording = read(progress)
    for problem in recording.problems:
        warn(problem)
    return recording
