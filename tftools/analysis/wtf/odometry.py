"""nav_msgs/Odometry against tf: each message states the transform from its header's frame to its child_frame_id,
which tf should hold too."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from tftools.analysis.edges import chain_moving_edges
from tftools.analysis.expected import Tolerances
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import Scene, edge
from tftools.core.figures import apart, median_ns
from tftools.core.frames import frame_name
from tftools.sources.contents import StampedMessages

#: Odometry and tf within these at every stamp compared agree (``Tolerances``' defaults, 1 mm and 0.1°, within
#: which ``tfx diff`` finds two values the same): the same estimate sent twice, as a driver's /odom beside its
#: own tf (a simulated Kobuki's re-sent stamps, 14 um and 0.01° from the first one tf2 keeps).
AGREE = Tolerances()


@register("odometry", Severity.warning, "nav_msgs/Odometry whose child frame tf lacks, or whose pose tf's differs from")
def odometry(scene: Scene) -> Iterator[Finding]:
    for s in scene.streams:
        if not s.states_transforms:
            continue
        for parent, child in _stated_edges(s):
            yield from _against_tf(scene, s, parent, child)


def _stated_edges(s: StampedMessages) -> list[tuple[str, str]]:
    """The (header frame, child frame) pairs ``s``'s messages state, as they first come; named ones only."""
    pairs = np.stack([s.frame, s.child], axis=1)[s.child >= 0]
    _, first = np.unique(pairs, axis=0, return_index=True)
    found = [(s.frame_ids[int(pairs[k, 0])], s.child_ids[int(pairs[k, 1])]) for k in np.sort(first).tolist()]
    return [(parent, child) for parent, child in found if parent and child and parent != child]


def _against_tf(scene: Scene, s: StampedMessages, parent: str, child: str) -> Iterator[Finding]:
    buffer = scene.buffer
    mine = (np.asarray(s.frame_ids, object)[s.frame] == parent) & (s.child >= 0)
    mine &= np.asarray(s.child_ids, object)[np.maximum(s.child, 0)] == child
    count = int(np.count_nonzero(mine))
    said = f"{s.topic}: {count} {s.type} messages state {edge(parent, child)}"
    if not buffer.has_frame(frame_name(parent)):
        return  # the header's frame tf lacks: sensor_frame's
    if not buffer.has_frame(frame_name(child)):
        yield Finding(
            Severity.warning,
            "odometry",
            f"{said}; tf has {parent} but no frame {child}",
            f"a node using this odometry's twist (in {child}) or comparing its pose with tf cannot look {child} up: "
            "set the odometry's child_frame_id (its node's base frame parameter) to the robot's base frame in tf, or "
            f"publish {child} in tf",
            (parent, child),
            count=count,
        )
        return
    stamps = s.stamp[mine]
    values = s.pose[mine]
    usable = (stamps > 0) & np.isfinite(values).all(axis=1)
    for hist in chain_moving_edges(buffer, frame_name(parent), frame_name(child)).values():
        usable &= np.isin(stamps, hist.stamps)  # at its own stamps: no interpolation between tf's samples
    if not usable.any():
        return
    looked = buffer.lookup_many(frame_name(parent), frame_name(child), stamps[usable])
    found = looked.valid
    compared = int(np.count_nonzero(found))
    if not compared:
        return
    theirs = np.concatenate([looked.translations[found], looked.rotations[found]], axis=1)
    metres, degrees = apart(values[usable][found], theirs)
    if metres.max() * 1000 <= AGREE.translation_mm and degrees.max() <= AGREE.rotation_deg:
        return
    at = stamps[usable][found]
    far, turned = int(np.argmax(metres)), int(np.argmax(degrees))
    typical = median_ns((metres * 1e9).astype(np.int64)) / 1e9
    yield Finding(
        Severity.info,
        "odometry",
        f"{said}; at the {compared} of their stamps tf has samples at too, tf's value is up to {metres[far]:.3f} m "
        f"({_at(scene, int(at[far]))}) and {degrees[turned]:.2f}° ({_at(scene, int(at[turned]))}) apart from "
        f"theirs (median {typical:.3f} m)",
        f"tf's {edge(parent, child)} and this topic are two estimates of the robot's motion (an EKF's or a "
        "localizer's on tf beside the wheels' odometry, say): a node reading this topic's pose and one looking up "
        "tf see the robot in different places; if both should come from one node, check which node sends the tf",
        (parent, child),
        first_time=int(at.min()),
        last_time=int(at.max()),
        count=compared,
        figures={"apart_m_max": float(metres[far]), "apart_deg_max": float(degrees[turned]), "compared": compared},
    )


def _at(scene: Scene, stamp: int) -> str:
    said = scene.rel(stamp)
    return said if said.startswith("at ") else f"at {said}"
