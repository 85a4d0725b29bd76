"""``Names``: names interned as integer ids (a batch's and the rejection log's frames and publishers; a
buffer's are its compiled core's, tf2's ids from 1); ``frame_name``, the one rule of a frame's leading ``/``;
``known_frame``, a frame someone asked for."""

from __future__ import annotations

from collections.abc import Sequence

# The core's id 0, tf2's "no parent": a frame's parent is never 0.
from tftools.core._kernels import NO_PARENT as NO_PARENT
from tftools.core.errors import UnknownFrameError


def frame_name(given: str) -> str:
    """``given`` as tf2 keys the frame: one leading ``/`` dropped (tf's tools and ROS 1's tf dropped it;
    tf2's lookups refuse it: ``Buffer``'s ``validateFrameId``)."""
    return given.removeprefix("/")


def base_name(frame: str) -> str:
    """``frame`` without a namespace prefix (``robot1/odom`` -> ``odom``)."""
    return frame.rsplit("/", 1)[-1]


def known_frame(frames: Sequence[str], frame: str) -> str:
    """``frame`` as tf2 keys it (``frame_name``), which must be one of ``frames``: else an
    ``UnknownFrameError`` with the frames there are, the closest first."""
    name = frame_name(frame)
    if name not in frames:
        import difflib  # an unknown frame's error only: ~2 ms of a load's imports spared

        close = difflib.get_close_matches(name, frames, n=3, cutoff=0.4)
        raise UnknownFrameError.absent(frame, (*close, *sorted(set(frames) - set(close))))
    return name


class Names:
    """Names to ids and back: ids follow first insertion, after the ``reserved`` names (never interned)."""

    def __init__(self, reserved: Sequence[str] = ()) -> None:
        self._ids: dict[str, int] = {}
        self.names: list[str] = list(reserved)

    def __contains__(self, name: object) -> bool:
        return name in self._ids

    def intern(self, name: str) -> int:
        index = self._ids.get(name)
        if index is None:
            index = self._ids[name] = len(self.names)
            self.names.append(name)
        return index
