"""Sensor data heard live beside tf, what ``tfx filter`` replays: each message's header, decoded by the
parsers bags use, and its arrival time on the capture's clock: the same ``StampedMessages`` as a bag gives."""

from __future__ import annotations

from collections.abc import Sequence

from tftools.core.semantics import Semantics
from tftools.sources.headers import StampedRead
from tftools.sources.live.base import LiveSource
from tftools.sources.live.capture import capture
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
