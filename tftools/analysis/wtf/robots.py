"""Robots whose nodes send the same frame names: one node (MAVROS, a driver) run in each robot's namespace without
a prefix for its frames, so tf2 holds one frame for all of them (two real drones' /uav_2/mavros and /uav_3/mavros
each sending fcu -> lidarlite_laser, 3d-SWAP's flights of 2017)."""

from __future__ import annotations

from collections.abc import Sequence

from tftools.analysis.wtf.scene import and_joined, edge


def robots_of(publishers: Sequence[str]) -> tuple[str, ...] | None:
    """The namespaces of ``publishers`` (node names) where each is the same node in another namespace:
    ("/uav_2", "/uav_3") of /uav_2/mavros and /uav_3/mavros. None where they are different nodes (/ekf_se and
    /cartographer_node), one node, or a node outside any namespace (/mavros beside /uav_2/mavros)."""
    parts = [p.rsplit("/", 1) for p in publishers]
    if len(parts) < 2 or any(len(p) != 2 or not p[0] or not p[1] for p in parts):
        return None
    spaces = [space for space, _ in parts]
    if len({name for _, name in parts}) != 1 or len(set(spaces)) != len(spaces):
        return None
    return tuple(sorted(spaces))


def robots_said(robots: Sequence[str]) -> str:
    """ "the same node in the namespaces of 2 robots, /uav_2 and /uav_3" """
    return f"the same node in the namespaces of {len(robots)} robots, {and_joined(list(robots))}"


def prefix_hint(robots: Sequence[str], frames: tuple[str, str], ros2: bool) -> str:
    """How to give each robot its own frames: a prefix per robot, set where the node names its frames."""
    first = robots[0].strip("/").replace("/", "_")
    where = "robot_state_publisher's frame_prefix" if ros2 else "robot_state_publisher's tf_prefix"
    return (
        f"tf2 holds one {edge(*frames)} for {_all(len(robots))} robots, whichever sent it last: name each robot's "
        f"frames with its own prefix ({first}/{frames[0]}) in the parameters where the node names them (its frame_id "
        f"parameters, {where}), and attach them to that robot's frames"
    )


def _all(count: int) -> str:
    return "both" if count == 2 else f"all {count}"
