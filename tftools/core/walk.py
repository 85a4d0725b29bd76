"""What tf2 says of the walk over the frame tree: its failures as tf2's errors, and its lists of frames.

There is one walk, tf2's ``walkToTopParent`` and ``getLatestCommonTime``, compiled in
``native/walk.hpp``: it serves every lookup, ``can_transform``, chain and latest common time, and
where it fails it reports why (a ``Failure``), which is worded here, tf2's messages being made in
this one place because users compare our errors with theirs.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import NamedTuple

# What made a walk fail (the core's codes): nothing, more than tf2's ``MAX_GRAPH_DEPTH`` edges (a
# loop), two trees, a time outside an edge's history.
from tftools.core._kernels import EXTRAPOLATION as EXTRAPOLATION
from tftools.core._kernels import LOOP as LOOP
from tftools.core._kernels import NO_FAILURE as NO_FAILURE
from tftools.core._kernels import UNCONNECTED as UNCONNECTED
from tftools.core.errors import ConnectivityError, TransformError, UnknownFrameError
from tftools.core.history import EdgeHistory, Extrapolation
from tftools.core.semantics import Dialect
from tftools.core.time import duration_to_sec, to_sec

#: A walk's report (``BufferCore.chain``'s): what failed, and for an extrapolation the ``Extrapolation``'s
#: kind, time and stamp.
Failure = tuple[int, int, int, int]


class Tree(NamedTuple):
    """What tf2's texts read: each frame's history (None for a root), the frame names, and the tf2
    whose words they are in."""

    histories: Sequence[EdgeHistory | None]
    names: Sequence[str]
    dialect: Dialect


def error(
    failure: Failure, target_frame: str, source_frame: str, dialect: Dialect, tree: Callable[[], Tree]
) -> TransformError:
    """tf2's error, in ``dialect``'s words, for a walk from ``source_frame`` to ``target_frame`` that
    failed as ``failure`` says; ``tree`` gives the frames a loop's message lists (made only then)."""
    what, *extrapolation = failure
    if what == LOOP:
        return UnknownFrameError.loop(frames_as_string(tree()))
    if what == EXTRAPOLATION:
        kind, time, stamp = extrapolation
        return dialect.extrapolation(Extrapolation(kind, time, stamp), source_frame, target_frame)
    return ConnectivityError.between(target_frame, source_frame)


def frames_as_string(tree: Tree) -> str:
    """tf2's ``allFramesAsString``."""
    lines = []
    for frame_id, hist in enumerate(tree.histories):
        if hist is not None:
            lines.append(f"Frame {tree.names[frame_id]} exists with parent {tree.names[hist.latest_parent]}.\n")
    return "".join(lines)


#: allFramesAsYAML's broadcaster of a frame no publisher is recorded for.
NO_AUTHORITY = "no recorded authority"


def frames_as_yaml(tree: Tree, broadcasters: Mapping[int, str]) -> str:
    """tf2's ``allFramesAsYAML``: parent, latest broadcaster, rate and time span per child frame.

    ``broadcasters`` names, per frame id, who sent the frame's last accepted sample; ROS 2's
    listener names none (``Dialect.listener_authority``).
    """
    ros2 = tree.dialect.ros2
    if len(tree.names) == 1:  # no frame at all
        return "[]" if ros2 else "{}"
    lines = []
    for frame_id, hist in enumerate(tree.histories):
        if hist is None or not len(hist):
            continue
        latest, oldest = (0, 0) if hist.static else (hist.latest_stamp, hist.oldest_stamp)
        count = 1 if hist.static else len(hist)
        if ros2:
            rate = count * 1e9 / max(latest - oldest, 100_000)
            newest_text, oldest_text = tree.dialect.seconds(latest), tree.dialect.seconds(oldest)
            length = duration_to_sec(latest - oldest)
        else:
            rate = count / max(to_sec(latest) - to_sec(oldest), 0.0001)
            newest_text, oldest_text = f"{to_sec(latest):.3f}", f"{to_sec(oldest):.3f}"
            length = to_sec(latest - oldest)
        lines += [
            f"{tree.names[frame_id]}: ",
            f"  parent: '{tree.names[hist.latest_parent]}'",
            f"  broadcaster: '{tree.dialect.listener_authority or broadcasters.get(frame_id, NO_AUTHORITY)}'",
            f"  rate: {rate:.3f}",
            f"  most_recent_transform: {newest_text}",
            f"  oldest_transform: {oldest_text}",
            f"  buffer_length: {length:.3f}",
        ]
    return "\n".join(lines) + "\n" if lines else ""
