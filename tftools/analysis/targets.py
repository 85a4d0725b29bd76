"""The target frame of a question several commands ask (``tfx filter``'s, ``tfx wtf``'s sensor checks): the
frame sensor data is transformed into, asked for or chosen by REP 105."""

from __future__ import annotations

from collections.abc import Collection, Sequence

import numpy as np

from tftools.analysis.frames import FrameTree
from tftools.core.frames import base_name, frame_name
from tftools.sources.contents import DEFAULT_TOPICS, StampedMessages

#: Why sensor data has no target frame: the recording holds no transform, so no tree (the AUV's and the
#: Crazyflie's recordings); its target is "" (said as null in JSON: no frame).
NO_TREE = "no transforms, so no tree to transform it into"


def default_target(tree: FrameTree) -> tuple[str, str]:
    """The frame sensor data is usually transformed into: ``odom`` or ``map`` where REP 105's frames
    exist (odom, where both do: what a costmap or a scan matcher asks for), or the one robot's namespaced
    ones (``cf0/odom``: aerostack2's Crazyflie, whose Gazebo model tree is the larger), else the largest
    tree's root; "" where there is no tree (``NO_TREE``). Several robots' (``robot_0/odom``, ``robot_1/odom``)
    name no one frame: the largest tree's root, as where there is none. Where the trees are apart and some
    move, a REP 105 frame in a smaller tree where nothing moves is no robot's (a real UR5's laser tracker under a
    tf1 static_transform_publisher's ``map -> tracker_frame``, beside the arm's moving tree under world)."""
    trees = tree.trees()
    largest = max(sorted(trees), key=lambda root: len(trees[root])) if trees else ""
    moving = {root for root, members in trees.items() if any(_moves(tree, f) for f in members)}
    roots = {frame: root for root, members in trees.items() for frame in members}

    def robots(frame: str) -> bool:  # a robot parked (nothing moving) in a tree as large as any is still one
        root = roots.get(frame)
        return root is not None and (not moving or root in moving or len(trees[root]) >= len(trees[largest]))

    for frame in ("odom", "map"):
        if robots(frame):
            return frame, f"REP 105's {frame} frame"
    prefixes = {name.rpartition("/")[0] for name in tree.frames if base_name(name) in ("odom", "map")}
    if len(prefixes) == 1 and (robot := prefixes.pop()):
        for frame in (f"{robot}/odom", f"{robot}/map"):
            if robots(frame):
                return frame, f"REP 105's {base_name(frame)} frame of the one robot"
    if not trees:
        return "", NO_TREE
    return largest, "the root of the largest tree"


def _moves(tree: FrameTree, frame: str) -> bool:
    summary = tree.frames[frame]
    return summary.parent is not None and not summary.static and not summary.held


def tied_to_tf(stream: StampedMessages) -> bool:
    """Whether some message of ``stream`` names a frame (a header with an empty frame_id only is not tf's)."""
    return any(stream.frame_ids)


def is_odometry(msgtype: str) -> bool:
    """Whether ``msgtype`` is odometry's (nav_msgs/Odometry, nav_msgs/msg/Odometry in ROS 2)."""
    return msgtype.rsplit("/", 1)[-1] == "Odometry"


def stated_children(stream: StampedMessages) -> tuple[str, ...]:
    """The child frames ``stream``'s messages state a transform to (nav_msgs/Odometry's child_frame_id, as its
    codec reads it: ``StampedMessages.child``), named ones, as they first come; () for other types."""
    ids = stream.child[stream.child >= 0]
    _, first = np.unique(ids, return_index=True)
    return tuple(n for n in (stream.child_ids[int(ids[k])] for k in np.sort(first).tolist()) if n)


def odometry_tf_unpublished(named: str, children: Sequence[str] = ()) -> str:
    """Why odometry in frames ``named`` (worded: ``'odom_enc'``) no transform names is lost, and what to do:
    its own transform is not on tf, not a mount to publish nor a frame_id to set (frand08/ramon_slam's
    cartographer bag: /odom_enc in odom_enc, child base_footprint in the tree); ``children``, the child frames
    its messages state (``stated_children``), named where known. ``tfx wtf``'s and ``tfx filter``'s words for it."""
    child = f"to {', '.join(children)}, the messages' child_frame_id" if children else "to the messages' child_frame_id"
    return (
        f"{named} is the frame of odometry (nav_msgs/Odometry), and its transform to the robot ({child}) is not on "
        "tf: turn on the odometry node's tf (e.g. a controller's enable_odom_tf, a publish_tf parameter), or "
        "record it"
    )


def fused_edge(tree: FrameTree, missing: Collection[str], children: Sequence[str]) -> tuple[str, str, str] | None:
    """Where odometry in frames ``missing`` that no transform names has the robot placed on tf by another
    odometry (parent, child, its publishers; "" unnamed): its child_frame_id's moving edge from another frame, or,
    where it names no child (a PR2's /base_odometry/odom: child_frame_id empty), the tree's one moving edge from
    a frame named as odometry's (robot_pose_ekf's odom_combined -> base_footprint); None where neither is. Its
    publishers are "" where the recording names none (a ROS 2 bag, a ROS 1 bag without callerids)."""
    gone = {frame_name(f) for f in missing}

    def placed(child: str) -> tuple[str, str, str] | None:
        summary = tree.frames.get(frame_name(child))
        if summary is None or summary.parent is None or summary.static or summary.parent in gone:
            return None
        named = [a for a in summary.authorities if a not in DEFAULT_TOPICS]  # a bag naming no node: its topic
        return summary.parent, summary.frame, ", ".join(named)

    given = [edge for child in children if child and (edge := placed(child)) is not None]
    if given or any(children):
        return given[0] if given else None
    odometries = [
        edge
        for name, summary in tree.frames.items()
        if summary.parent is not None and "odom" in base_name(summary.parent) and (edge := placed(name)) is not None
    ]
    return odometries[0] if len(odometries) == 1 else None


def odometry_fused(named: str, edge: tuple[str, str, str]) -> str:
    """Why odometry in frames ``named`` (worded: ``'odom'``) that no transform names need not be on tf, where
    another odometry places the robot there (``fused_edge``): it is that estimate's input (a real PR2,
    jsk_pr2eus's pr1012_sensors.bag: /base_odometry/odom in 'odom' beside robot_pose_ekf's odom_combined ->
    base_footprint). ``tfx wtf``'s and ``tfx filter``'s words for it."""
    parent, child, publishers = edge
    by = f" from {publishers}" if publishers else ""
    return (
        f"{named} is this odometry's own frame: the robot's odometry on tf is {parent} -> {child}{by}, another "
        "estimate this one likely feeds (robot_pose_ekf and robot_localization fuse odometry and send their own): "
        f"nothing needs {named} on tf, and turning this odometry's tf on would give {child} a second parent; "
        "read its poses as they are"
    )


#: REP 105's world frames: a pose in one of them is a robot's place in the world, not an odometry's own frame.
WORLD_FRAMES = frozenset({"map", "world", "earth"})


def world_pose_unpublished(named: str, has_odom: bool) -> str:
    """Why nav_msgs/Odometry in a world frame (``named``, worded: ``'map'``; ``WORLD_FRAMES``) that no transform
    names is lost: a robot's pose in the world, as a simulator's ground truth (Gazebo's p3d plugin: no tf, an
    empty child_frame_id) or a localizer's estimate, has no odometry tf to turn on (corpus33's Guardian in Gazebo:
    /base_pose_ground_truth in 'map' at 1 kHz, child_frame_id empty). ``has_odom``: whether the tree has an odom
    frame to hang the world frame on. ``tfx wtf``'s and ``tfx filter``'s words for it."""
    parent = "map -> odom" if has_odom else "the world frame's transform to the tree"
    return (
        f"{named} is a world frame (REP 105) and these are nav_msgs/Odometry: the robot's pose in the world, as a "
        "simulator's ground truth (Gazebo's p3d plugin, which sends no tf) or a localizer's estimate gives, not an "
        f"odometry's own frame with a tf to turn on; a lookup into it needs {parent} (a localizer's, e.g. amcl or "
        "a SLAM node: run it with this data or record it; for a ground truth, read its poses as they are)"
    )


def world_frame_unpublished(named: Collection[str], has_odom: bool, root: str, ros2: bool) -> str | None:
    """Why sensor data in REP 105's frames ``named`` (base names: 'map', 'odom') that no transform names is
    lost, and what to do (None for other frames): ``has_odom``, whether the tree has an odom frame; ``root``,
    the frame the data is transformed into; ``ros2``, for the command to name. ``tfx wtf``'s (sensor_frame)
    and ``tfx filter``'s words for it."""
    named = set(named)
    if named == {"map"} and not has_odom:
        # CyberShip Voyager's motion capture (corpus ros2-cybership-voyager-mocap-basin-2025-mcap): mocap4r2's
        # /markers in 'map', the ship's pose on tf as world -> base_link: no odom, so no localization is missing
        static = f"{'ros2 run' if ros2 else 'rosrun'} tf2_ros static_transform_publisher"
        return (
            f"no transform names it, and with no odom frame 'map' is not localization's (REP 105) here: the tree's "
            f"fixed frame is '{root}'; if 'map' is the same place, set the driver's frame_id parameter to '{root}', "
            f"or publish the transform between them ({static} with {root} as parent and map as child)"
        )
    if named == {"map"}:
        # ruvu/mcl's MiR bag: the input of a localization under test, its map -> odom deliberately not recorded
        return (
            "no transform names it: 'map' is localization's frame (REP 105), and the node that publishes map -> "
            "odom (amcl, a SLAM or localization node) did not run, was not recorded or does not publish tf (a "
            "publish_tf / tf_broadcast parameter): run it with this data, or record it"
        )
    if named and named <= {"odom", "map"}:
        return (
            "no transform names it: the node that publishes it (odometry's odom -> base_link, localization's "
            "map -> odom) did not run or does not publish tf (e.g. a controller's enable_odom_tf, a publish_tf "
            "parameter): turn it on, or record it"
        )
    return None


def choose_target(tree: FrameTree, asked: str | None = None) -> tuple[str, str]:
    """The target frame and why it was chosen: ``asked`` where it is a frame of ``tree``, else
    ``default_target`` (saying that ``asked`` is not there: a fleet's robots may differ)."""
    if asked is None:
        return default_target(tree)
    if frame_name(asked) in tree.frames:  # a leading '/' dropped, as tf's tools do
        return frame_name(asked), "asked for"
    target, reason = default_target(tree)
    return target, f"{reason}: '{asked}', asked for, is not a frame of this recording"
