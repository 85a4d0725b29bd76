"""Sensor data heard live beside tf, what ``tfx filter`` replays: each message's header, decoded by the
parsers bags use, and its arrival time on the capture's clock: the same ``StampedMessages`` as a bag gives;
``capture_live``, tf and them in one recording."""

from __future__ import annotations

from collections.abc import Sequence

from tftools.core.semantics import Semantics
from tftools.sources.contents import StampedRead
from tftools.sources.live.base import LiveSource
from tftools.sources.live.capture import capture
from tftools.sources.live.errors import NoTransformsHeardError
from tftools.sources.live.header_store import HeaderStore
from tftools.sources.recording import Recording


def capture_stamped(
    source: LiveSource,
    duration: float = 5.0,
    topics: Sequence[str] | None = None,
    *,
    semantics: Semantics | None = None,
) -> tuple[Recording, StampedRead]:
    """Listen ``duration`` wall seconds to ``source`` (not yet started; closed on return) as
    ``capture`` does, and meanwhile to the sensor ``topics`` of its system (default: every one
    whose messages start with a header, but /tf, /tf_static and /clock): the recording, and each
    topic's headers with their arrival times on the recording's record clock."""
    store = HeaderStore(source.clock, topics, source.notice)
    with source:  # capture closes it, but not when the listener failed first
        listener = source.header_listener(store)
        try:
            listener.start()
            recording = capture(source, duration, semantics=semantics, on_jump=store.forget)
        finally:
            listener.close()
    return recording, store.read()


def capture_live(
    source: LiveSource,
    duration: float = 5.0,
    headers: Sequence[str] | None = None,
    *,
    semantics: Semantics | None = None,
    require_tf: bool = True,
) -> Recording:
    """What ``source`` (not yet started; closed on return) says in ``duration`` wall seconds, as one
    recording, the way ``read_recording`` reads a bag: tf, and with ``headers``, the headers of the sensor
    data on those topics (none named: every topic whose messages start with a header) in its
    ``Recording.stamped`` (what a bag read with headers has). Hearing no
    transform is a ``NoTransformsHeardError``, unless not ``require_tf``."""
    if headers is None:
        recording = capture(source, duration, semantics=semantics)
    else:
        recording, stamped = capture_stamped(source, duration, headers or None, semantics=semantics)
        recording.contents.stamped = stamped
    if require_tf and not recording.transform_count:
        raise NoTransformsHeardError(recording.contents.topics, source.describe(), duration, source.ros2)
    return recording
