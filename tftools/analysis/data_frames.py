"""What a recording without transforms says of the tree its data needs: the frames its stamped topics name
(their headers, as ``tfx wtf`` reads them anyway: no further read), and the topics whose poses could have
been broadcast as tf. ``no_tf`` says it (the AUV's ros2_db3_auv_real_sbg_dvl_ping_no_tf_humble_2026:
/ping1d/range in range_link; the Crazyflie's ros2_mcap_crazyflie_real_vicon_no_tf_p4_2025: poses in
vicon/world on a PoseStamped topic)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from tftools.sources.codecs.types import known_type, rosidl_name
from tftools.sources.contents import StampedMessages

#: Types that carry a pose of one frame in their header's: what a broadcaster could have turned into tf.
_POSES = frozenset(
    {
        "nav_msgs/msg/Odometry",
        "geometry_msgs/msg/PoseStamped",
        "geometry_msgs/msg/PoseWithCovarianceStamped",
        "geometry_msgs/msg/TransformStamped",
    }
)
#: Topics named per frame, and frames named, at most: more are said with "and N more".
_MOST, _PARTS = 3, 8


@dataclass(frozen=True, slots=True)
class DataFrames:
    """The ``frames`` a recording's stamped data is in (in the order first seen), each topic's (``figures``:
    topic to its frame_ids, "" for an empty one), what the message and the hint add (``said``, ``hint``)."""

    frames: tuple[str, ...] = ()
    figures: dict[str, str] = field(default_factory=dict)
    said: str = ""
    hint: str = ""


def data_frames(streams: Sequence[StampedMessages], topics: Mapping[str, str]) -> DataFrames:
    """What ``streams`` (the headers a recording was read with) say of the tree their data needs, and which
    of the recording's other ``topics`` (topic to type) are of types tfx knows no definition of, whose
    frames it cannot tell; nothing when neither."""
    from tftools.analysis.wtf.scene import listed  # not at import: wtf's checks import this module

    figures: dict[str, str] = {}
    recorded = {s.topic: s.type for s in streams}  # as the recording spells it, ROS 1's or ROS 2's
    kinds = {t: rosidl_name(kind) for t, kind in recorded.items()}
    mounted: dict[str, list[str]] = {}  # the frames of sensor data, with their topics: each needs placing
    posed: dict[str, list[str]] = {}  # the frames poses are given in, with their topics: each needs a broadcaster
    unframed = []
    for stream in (s for s in streams if len(s)):
        figures[stream.topic] = ", ".join(stream.frame_ids)
        frames = posed if kinds[stream.topic] in _POSES else mounted
        for frame in stream.frame_ids:
            if frame:
                frames.setdefault(frame, []).append(stream.topic)
            else:
                unframed.append(stream.topic)
    parts = [f"{frame} ({listed(named, _MOST)})" for frame, named in mounted.items()]
    parts += [f"{frame} (poses on {listed(named, _MOST)})" for frame, named in posed.items()]
    if unframed:
        parts.append(f"an empty frame_id ({listed(unframed, _MOST)}), which a tree cannot hold")
    read = {s.topic for s in streams}
    unknown = sorted(t for t, kind in topics.items() if t not in read and not known_type(kind))
    said = f"; its data is stamped in {listed(parts, _PARTS)}" if parts else ""
    if unknown:
        types = ", ".join(dict.fromkeys(rosidl_name(topics[t]) for t in unknown))
        said += f"; the frames of {listed(unknown, _PARTS)} are not told ({types}: types tfx has no definition of)"
    needs = []
    if mounted:
        them = "them" if len(mounted) > 1 else "it"
        needs.append(
            f"a tree for its data must hold {listed(list(mounted), _PARTS)}: what places {them} "
            "(robot_state_publisher's mounts, a static_transform_publisher, odometry's broadcaster) did not run "
            "or was not recorded"
        )
    if posed:
        carriers = [f"{t} as {recorded[t]}" for t in dict.fromkeys(t for named in posed.values() for t in named)]
        needs.append(
            f"the poses on {listed(carriers, _MOST)} become tf only through a node that broadcasts them: "
            "missing or not recorded"
        )
    hint = f"; {'; '.join(needs)}" if needs else ""
    return DataFrames(tuple(dict.fromkeys([*mounted, *posed])), figures, said, hint)
