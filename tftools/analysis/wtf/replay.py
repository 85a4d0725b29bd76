"""Checks of how a recording's static transforms survive a replay: offered durably (latched in ROS 1,
transient local in ROS 2) so a late subscriber gets them, and present past the first seconds."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.registry import CheckSkippedError, register
from tftools.analysis.wtf.scene import Scene, duration, edge, listed
from tftools.core.time import NS_PER_S
from tftools.sources.contents import IN_METADATA, OfferedQos

#: A recording this long (s) is one people play from the middle, split or filter.
LONG_RECORDING_S = 60.0
#: Statics whose last message came within this many seconds of the start came "only at the start".
EARLY_S = 10.0
#: rosbag2's durability policy, as metadata.yaml writes it: a number (Humble and before) or a name.
TRANSIENT_LOCAL = (1, "transient_local")
#: Statics re-sent at least this often (s of record time) from the recording's start to its end reach a
#: late subscriber of a volatile /tf_static within that time: as often as ``tfx static --repair`` repeats them.
REPEATED_EVERY_S = 5.0


def repair_hint(ros2: bool) -> str:
    """What ``tfx static --repair`` makes of a copy, in the words of the recording's ROS: ROS 1 latches
    /tf_static, ROS 2 offers it with transient local durability (QoS)."""
    durable = "offered transient local (QoS durability)" if ros2 else "latched"
    return f"tfx static --repair -b IN -o OUT writes a copy whose statics are complete, {durable} and repeated"


@register(
    "static_volatile", Severity.warning, "/tf_static offered volatile: ros2 bag play never gives it to late subscribers"
)
def static_volatile(scene: Scene) -> Iterator[Finding]:
    """rosbag2 plays a topic with the QoS its publishers offered (metadata.yaml's offered_qos_profiles, or a
    bare file's own: ``OfferedQos.source``):
    transient local only when every profile was; none recorded plays its default, volatile. Only
    recordings read from bags are replayed: one assembled in memory has no QoS to check."""
    rows = scene.rows
    if not rows.static.any() or _repeated_through(scene):
        return
    for file in scene.recording.contents.files:
        qos = scene.recording.qos.get(file.path)
        if not file.format.startswith(("rosbag2", "mcap")) or qos is None:  # "mcap": a ros2 one given alone
            continue
        for topic, profiles in _static_qos(file.path, qos).items():
            if profiles and all(_durability(p) in TRANSIENT_LOCAL for p in profiles):
                continue
            offered = "records no QoS for it" if not profiles else "offers it volatile"
            yield Finding(
                Severity.warning if profiles else Severity.info,  # none recorded: a conversion, most likely
                "static_volatile",
                f"{file.path} {offered} ({topic}, {qos.source}'s offered_qos_profiles): ros2 bag play publishes "
                f"it volatile, so a node that subscribes after its first message never gets the static transforms",
                f"{repair_hint(True)}; or play with --qos-profile-overrides-path naming {topic} "
                "durability: transient_local",
                tuple(f for pair in _static_edges(scene) for f in pair),
                (topic,),
                count=len(profiles),
            )


def _repeated_through(scene: Scene) -> bool:
    """Every static transform re-sent at least every ``REPEATED_EVERY_S`` from the recording's start to its end
    (CompRobo's Neato driver in 2022 re-sent them at 20 Hz): played volatile, a late subscriber still gets
    each of them within that time."""
    rows, every = scene.rows, REPEATED_EVERY_S * NS_PER_S
    for _, _, which in rows.by_edge(rows.static):
        times = np.concatenate(([scene.start], np.sort(rows.record_time[which]), [scene.end]))
        if np.diff(times).max() > every:
            return False
    return True


def _static_qos(path: str, qos: OfferedQos) -> dict[str, list[object]]:
    """Each static topic's offered QoS profiles, as the bag directory's metadata.yaml says (read with the bag), or
    a bag without one its files' topics tables or channels (none: a topic they keep no QoS for, said as
    metadata.yaml's empty ``offered_qos_profiles`` is; nothing where they hold no static topic)."""
    if qos.problem and qos.source != IN_METADATA:
        raise CheckSkippedError(
            f"{path}: {qos.source} does not say the QoS of /tf_static ({qos.problem})",
            "give tfx the bag directory, with its metadata.yaml, if the file has one",
        )
    if qos.problem:
        raise CheckSkippedError(
            f"{path}/metadata.yaml does not say the QoS of /tf_static ({qos.problem})",
            "repair or regenerate metadata.yaml",
        )
    return qos.profiles


def _durability(profile: object) -> object:
    value = profile.get("durability") if isinstance(profile, dict) else None
    return value.lower() if isinstance(value, str) else value


def _last_static(after_start_ns: int) -> str:
    """When the last static came, in words: a millisecond is below what ``duration`` shows (never "0.000 s")."""
    if after_start_ns < NS_PER_S // 1000:
        return "all in its first millisecond"
    return f"the last {duration(after_start_ns / NS_PER_S)} into it"


# A note, not a warning: a healthy recording holds its statics once, at the start (latched in ROS 1,
# transient local in ROS 2).
@register("statics_early", Severity.info, "static transforms only in the first seconds of a long recording")
def statics_early(scene: Scene) -> Iterator[Finding]:
    """Playing from later on (rosbag play -s, ros2 bag play --start-offset), a split's later files
    and a filter by time lose them, and every lookup through them fails."""
    rows = scene.rows
    records = rows.record_time[rows.static]
    if scene.recording.contents.live or not len(records) or not (records > 0).all():
        return
    length = (scene.end - scene.start) / NS_PER_S
    last = int(records.max())
    if length < LONG_RECORDING_S or last - scene.start > EARLY_S * NS_PER_S:
        return
    who = scene.authorities_of(np.flatnonzero(rows.static))
    statics = _static_edges(scene)
    # Findings' times are on the stamps' clock (``Scene.ros_times``); the message and figures say them from the
    # recording's start.
    first_time, last_time = scene.ros_times([scene.start, last])
    yield Finding(
        Severity.info,
        "statics_early",
        f"the static transforms{scene.by(who)} ({listed([edge(*e) for e in statics])}) were recorded only at the "
        f"start of {duration(length)}, {_last_static(last - scene.start)}: played from later on, split or filtered "
        "by time, the copy has none and lookups through them fail",
        f"{repair_hint(scene.ros2)} through the recording; or play it from its start ("
        + ("ros2 bag play without --start-offset)" if scene.ros2 else "rosbag play without -s)"),
        tuple(f for pair in statics for f in pair),
        who,
        first_time,
        last_time,
        int(rows.static.sum()),
        figures={"recording_s": length, "last_static_after_start_s": (last - scene.start) / NS_PER_S},
    )


def _static_edges(scene: Scene) -> list[tuple[str, str]]:
    rows = scene.rows
    return [(parent, child) for parent, child, _ in rows.by_edge(rows.static)]
