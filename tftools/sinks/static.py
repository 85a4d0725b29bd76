"""``tfx static``'s work: static transforms made from static_transform_publisher's numbers and checked as tf2
wants them, then published on a live system (``publish_static``, through ``open_static_broadcaster``), or written
into a copy of a recording (``copy_with_statics(source, output, StaticQuery)``: added, or the recording's own made
safe to replay). The input is never modified."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from tftools.core.errors import InvalidTransformError
from tftools.core.frames import frame_name
from tftools.core.transform import Transform
from tftools.sources.errors import NoTransformsError, PartOfBagError
from tftools.sources.storage.locations import is_url

if TYPE_CHECKING:
    from tftools.sinks.broadcaster import StaticBroadcaster
    from tftools.sources.live.notices import OnNotice


def static_transform(values: Sequence[float], frame: str, child: str, *, degrees: bool = False) -> Transform:
    """static_transform_publisher's numbers as a transform from ``frame`` to ``child``: ``x y z yaw pitch roll``
    (radians, or ``degrees``) or ``x y z qx qy qz qw``; not yet ``checked``."""
    if len(values) == 6:
        x, y, z, yaw, pitch, roll = values
        roll, pitch, yaw = (math.radians(angle) if degrees else angle for angle in (roll, pitch, yaw))
        return Transform.from_rpy((x, y, z), (roll, pitch, yaw), 0, frame, child)
    if len(values) == 7:
        x, y, z, qx, qy, qz, qw = values
        return Transform((x, y, z), (qx, qy, qz, qw), 0, frame, child)
    raise ValueError(f"{len(values)} numbers: expected 6 (x y z yaw pitch roll) or 7 (x y z qx qy qz qw)")


def checked(t: Transform) -> Transform:
    """``t`` as tf2 wants it: frames named by tf2's rule (``frame_name``), two different ones, finite numbers,
    the quaternion normalized (tf2 would refuse a denormalized one); else an ``InvalidTransformError``."""
    frame, child = frame_name(t.frame_id), frame_name(t.child_frame_id)
    if not frame or not child:
        raise InvalidTransformError("frame ids cannot be empty", f"got {t.frame_id!r} -> {t.child_frame_id!r}")
    if frame == child:
        raise InvalidTransformError(
            f"the frame and the child frame are the same ({frame}): this cannot work", "name two frames"
        )
    values = (*t.translation, *t.rotation)
    if not all(math.isfinite(v) for v in values):
        raise InvalidTransformError(f"{frame} -> {child}: not a finite number in {values}", "check the numbers")
    norm = math.sqrt(sum(q * q for q in t.rotation))
    if norm < 1e-9:
        raise InvalidTransformError(
            f"{frame} -> {child}: the quaternion is zero", "the identity is qx 0 qy 0 qz 0 qw 1"
        )
    return Transform(t.translation, tuple(q / norm for q in t.rotation), 0, frame, child)  # type: ignore[arg-type]


def copyable(bag: str) -> None:
    """A ``PartOfBagError`` unless ``bag`` is a recording tfx can copy with transforms added: a ROS 1 .bag, a ROS 2
    bag directory, a bare .mcap or .db3 file, but not one of the files a ROS 2 bag directory's metadata.yaml
    lists (one renamed since, which it does not list, is a recording of its own; a URL is judged once fetched)."""
    path = Path(bag)
    if is_url(bag) or not path.is_file() or path.suffix not in (".mcap", ".db3"):
        return
    from tftools.sources.bag.rosbag2 import listed_in_bag  # a .bag's copy needs no rosbag2 code

    if listed_in_bag(path):
        raise PartOfBagError(bag, str(path.parent))


@dataclass(frozen=True)
class StaticQuery:
    """What a copy with static transforms holds (``copy_with_statics``): ``transforms`` (``checked``) added on
    /tf_static at its start, as if a static_transform_publisher had run while it was recorded; or with
    ``repair``, the recording's own static transforms made complete, durable (latched / transient local) and
    repeated through it. ``force`` replaces an earlier output (never the input)."""

    transforms: tuple[Transform, ...] = ()
    repair: bool = False
    force: bool = False

    def __post_init__(self) -> None:
        if self.repair and self.transforms:
            raise ValueError("a repair repeats the recording's own static transforms: it takes none")


@dataclass(frozen=True)
class StaticCopy:
    """The copy written (``path``) and the static transforms it holds for the query: those added, or with
    ``repair`` those repeated (the latest value of each)."""

    path: Path
    transforms: tuple[Transform, ...]
    undescribed: tuple[str, ...] = ()  # types it holds messages of but no definition (``Copied``)


def copy_with_statics(source: str, output: str | Path, query: StaticQuery) -> StaticCopy:
    """``tfx static``'s work on a recording: write ``output``, a copy of ``source`` (a path or URL: a ROS 1 .bag,
    a ROS 2 bag directory, a bare .db3 or .mcap) with the static transforms ``query`` asks for. An added frame
    the recording already has is refused (tf2 would see two values for it), as is an existing ``output``
    unless ``query.force``. The input is never modified."""
    from tftools.sinks.static_bag import copy_adding, copy_repairing
    from tftools.sources.storage import local_recording

    added = [checked(t) for t in query.transforms]
    copyable(source)
    with local_recording(source) as local:
        if query.repair:
            written, statics = copy_repairing(local, output, force=query.force)
            return StaticCopy(written.path, tuple(statics), written.undescribed)
        _refuse_present(local, added)
        copied = copy_adding(local, output, added, force=query.force)
        return StaticCopy(copied.path, tuple(added), copied.undescribed)


def _refuse_present(bag: Path, transforms: Sequence[Transform]) -> None:
    """Refuse a transform whose child frame the bag already has: tf2 would see two values (or two
    parents) for it, and a check would fail the copy."""
    from tftools.sources.recording import read_recording

    try:
        buffer = read_recording([bag]).buffer
    except NoTransformsError:
        return
    given = {t.child_frame_id for t in transforms}
    for child, history in buffer.histories():
        if child not in given:
            continue
        parents = sorted({buffer.frame_name(p) for p in history.parents.tolist()})
        kind = "a static transform" if history.static else "a moving transform"
        wanted = next(t for t in transforms if t.child_frame_id == child)
        raise InvalidTransformError(
            f"{bag} already has {child}, {kind} of {', '.join(parents)}: adding {wanted.frame_id} -> {child} "
            "would give tf2 two values for it",
            "add only frames the bag lacks",
            child=child,
            recording=str(bag),
        )


def open_static_broadcaster(
    ros: str | None = None, *, master_uri: str | None = None, on_notice: OnNotice | None = None
) -> StaticBroadcaster:
    """A static transform publisher on the system ``choose_ros`` picks (ROS1: a node registered
    with the master at ``master_uri`` or ``ROS_MASTER_URI``, latched ``/tf_static``; ROS2: a DDS
    writer on ``rt/tf_static``, transient local, keep last 1)."""
    from tftools.sources.live import choose_ros

    chosen = "ros1" if master_uri else choose_ros(ros)
    if chosen == "ros2":
        from tftools.sources.live.ros2 import require_cyclonedds

        require_cyclonedds()
        from tftools.sinks.ros2_broadcaster import Ros2StaticBroadcaster

        return Ros2StaticBroadcaster(on_notice)
    from tftools.sinks.ros1_broadcaster import Ros1StaticBroadcaster

    return Ros1StaticBroadcaster(master_uri, on_notice)


def publish_static(
    transforms: Sequence[Transform],
    ros: str | None = None,
    duration: float | None = None,
    *,
    on_notice: OnNotice | None = None,
    on_start: Callable[[str], None] | None = None,
) -> None:
    """``tfx static``: publish ``transforms`` (``checked``), stamped now, in one latched
    /tf_static message (ROS 1) or transient local (ROS 2) on the system ``open_static_broadcaster`` picks,
    for ``duration`` seconds (None: until Ctrl-C) or until the broadcaster stops. ``on_start`` is told to whom
    once they are sent."""
    sent = [checked(t) for t in transforms]
    stamp = time.time_ns()
    with open_static_broadcaster(ros, on_notice=on_notice) as broadcaster:
        broadcaster.send([replace(t, stamp=stamp) for t in sent])
        if on_start is not None:
            on_start(broadcaster.describe())
        deadline = None if duration is None else time.monotonic() + duration
        try:
            while not broadcaster.finished and (deadline is None or time.monotonic() < deadline):
                time.sleep(0.1)
        except KeyboardInterrupt:
            pass
