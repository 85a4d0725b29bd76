"""Checks against the robot's description (``tfx wtf --urdf robot.urdf``, or a recorded /robot_description):
joints tf lacks, fixed joints moved, moving joints not where /joint_states puts them, frames and joint
states the URDF does not know. Each finding names the joint, its link and the likely cause."""

from __future__ import annotations

import math
from collections.abc import Iterator

from tftools.analysis.description import (
    JointCheck,
    Robot,
    Verdict,
    check_joints,
    frames_not_described,
    joint_states_unfollowed,
    links_unseen,
    states_missing,
)
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.registry import declare, register
from tftools.analysis.wtf.scene import Scene, and_joined, base_name, listed
from tftools.analysis.wtf.topics import WORLD_FRAMES
from tftools.core.rotation import Quat, Vec3, rpy_rebuilding
from tftools.sources.urdf import Joint

RSP = "robot_state_publisher"


def _robot(scene: Scene) -> Robot | None:
    return scene.robot


def _checks(scene: Scene, robot: Robot) -> list[JointCheck]:
    return scene.shared("urdf_joints", lambda: check_joints(robot, scene.buffer, scene.tree))


def _joint(robot: Robot, name: str) -> Joint:
    return robot.description.joint(name)


def _about(joint: Joint) -> str:
    return f"joint {joint.name} ({joint.type}, {joint.parent} -> {joint.child})"


def _pose(xyz: Vec3, rotation: Quat) -> str:
    rpy = ", ".join(f"{round(math.degrees(a), 2) + 0.0:.2f}" for a in rpy_rebuilding(rotation))  # no -0.00
    return f"xyz [{', '.join(f'{v:.4f}' for v in xyz)}] m rpy [{rpy}]°"


def _from(robot: Robot) -> str:
    return robot.description.source


@register(
    "urdf_missing",
    Severity.error,
    "a joint of the robot's description that tf never carries (with a robot description)",
)
def urdf_missing(scene: Scene) -> Iterator[Finding]:
    robot = _robot(scene)
    if robot is None:
        return
    checks = _checks(scene, robot)
    missing = [c.joint for c in checks if c.verdict is Verdict.missing]
    if not missing:
        return
    joints = [_joint(robot, name) for name in missing]
    every = robot.description.joints
    recorded = robot.messages.joint_topic in robot.messages.recorded_topics
    if len(missing) == len(every) and len(every) > 1:
        yield Finding(
            Severity.error,
            "urdf_missing",
            f"none of the {len(every)} joints of {_from(robot)} is on tf: "
            f"{listed([f'{j.name} ({j.child})' for j in joints])}",
            f"{RSP} did not run (or its /tf and /tf_static were not recorded): start it with this URDF "
            f"({'ros2 launch' if scene.ros2 else 'roslaunch'} ... {RSP})",
            frames=tuple(dict.fromkeys(f for j in joints for f in (j.parent, j.child))),
        )
        return
    all_moving = [j for j in every if j.type != "fixed" and j.moving]
    if not robot.live and len(all_moving) > 1 and all(j.name in missing for j in all_moving):
        yield _publisher_absent(scene, robot, joints, recorded)
        return
    fixed = [j for j in joints if j.type == "fixed"]
    all_fixed = [j for j in every if j.type == "fixed"]
    if fixed and len(fixed) == len(all_fixed) and len(all_fixed) > 1:
        yield Finding(
            Severity.error,
            "urdf_missing",
            f"none of the {len(all_fixed)} fixed joints of {_from(robot)} is on /tf_static, though its moving "
            f"joints are on /tf: {listed([f'{j.name} ({j.child})' for j in fixed])}",
            f"{RSP} publishes them on /tf_static once, at its start: "
            + (
                "was /tf_static recorded, with transient local durability (ros2 bag record "
                f"--qos-profile-overrides-path)? A recording that subscribes volatile after {RSP} started misses them"
                if scene.ros2
                else "was /tf_static recorded (rosbag record /tf_static)? It is latched: a recording started later "
                "gets it too"
            ),
            frames=tuple(dict.fromkeys(f for j in fixed for f in (j.parent, j.child))),
        )
    else:
        for j in fixed:
            yield Finding(
                Severity.error,
                "urdf_missing",
                f"{_about(j)} of {_from(robot)} is not on tf: link {j.child} is never named",
                f"{RSP} publishes every fixed joint of the URDF it was given on /tf_static: it runs another URDF "
                f"(an older one, without {j.name}?), or another node meant to publish {j.child} did not run",
                frames=(j.parent, j.child),
            )
    moving = [j for j in joints if j.type != "fixed"]
    without = set(states_missing(robot, [j.name for j in moving if j.moving]))
    for j in moving:
        if not j.moving:
            cause = f"a {j.type} joint is placed by another node (localization, odometry): did it run?"
        elif robot.live:
            cause = (
                f"does a node publish {j.name}'s state on {robot.messages.joint_topic} (joint_state_publisher, the "
                f"driver: {'ros2 topic echo' if scene.ros2 else 'rostopic echo'} {robot.messages.joint_topic}), and "
                f"is {RSP} running?"
            )
        elif not recorded:
            cause = (
                f"{robot.messages.joint_topic} was not recorded: record it to tell whether joint_state_publisher "
                f"(or the driver) published {j.name}, or whether {RSP} did not run"
            )
        elif j.name in without:
            leader = f" (it mimics {j.mimic[0]})" if j.mimic is not None else ""
            cause = (
                f"no message on {robot.messages.joint_topic} names {j.name}{leader}: the node that should publish its "
                f"state (joint_state_publisher, a driver, a controller) does not, so {RSP} cannot place {j.child}"
            )
        else:
            cause = f"{robot.messages.joint_topic} names {j.name}, yet tf lacks it: is {RSP} running with this URDF?"
        yield Finding(
            Severity.error,
            "urdf_missing",
            f"{_about(j)} of {_from(robot)} is not on tf: link {j.child} is never named",
            cause,
            frames=(j.parent, j.child),
        )


def _publisher_absent(scene: Scene, robot: Robot, joints: list[Joint], recorded: bool) -> Finding:
    """Every moving joint of the description missing from tf, where tf carries some of its other joints (another
    broadcaster's: a recorder that sends only its base, Franka teleop's world -> base -> fr3_link0): one absent
    robot_state_publisher, not one finding per joint."""
    every = robot.description.joints
    shown = [j.name for j in every if j.name not in {m.name for m in joints}]
    moving = [j for j in joints if j.type != "fixed" and j.moving]
    named = [j.name for j in moving if j.name not in set(states_missing(robot, [m.name for m in moving]))]
    topic = robot.messages.joint_topic
    launch = f"{'ros2 launch' if scene.ros2 else 'roslaunch'} ... {RSP}"
    if not recorded:
        states = f"and {topic} was not recorded"
        hint = (
            f"record {topic} to tell whether joint_state_publisher (or the driver) published their states, or "
            f"whether {RSP} did not run ({launch})"
        )
    elif named:
        states = f"though {topic} names {'each' if len(named) == len(moving) else f'{len(named)} of them'}"
        hint = (
            f"{RSP} did not run with this URDF (or its /tf and /tf_static were not recorded); the joints tf carries "
            f"come from another broadcaster: start {RSP} ({launch})"
        )
    else:
        states = f"and no message on {topic} names them"
        hint = (
            f"the node that should publish their states (joint_state_publisher, a driver, a controller) does not, "
            f"so {RSP} cannot place their links; is {RSP} running ({launch})?"
        )
    return Finding(
        Severity.error,
        "urdf_missing",
        f"none of the {len(moving)} moving joints of {_from(robot)} is on tf, {states}; of its {len(every)} joints "
        f"tf carries only {and_joined(shown)}, {len(joints)} are missing: "
        f"{listed([f'{j.name} ({j.child})' for j in joints])}",
        hint,
        frames=tuple(dict.fromkeys(f for j in joints for f in (j.parent, j.child))),
    )


def _judged(scene: Scene, *verdicts: Verdict) -> Iterator[tuple[Robot, JointCheck, Joint]]:
    """The joints tf showed with one of ``verdicts``: the robot, the check, the joint."""
    robot = _robot(scene)
    if robot is None:
        return
    for c in _checks(scene, robot):
        if c.verdict in verdicts:
            yield robot, c, _joint(robot, c.joint)


def _on(j: Joint, severity: Severity, code: str, message: str, hint: str, stamp: int = 0) -> Finding:
    """A finding about joint ``j``'s edge (at ``stamp``, if known)."""
    return Finding(severity, code, message, hint, frames=(j.parent, j.child), first_time=stamp, last_time=stamp)


@register(
    "urdf_parent",
    Severity.error,
    "a link under another parent on tf than in the description (with a robot description)",
)
def urdf_parent(scene: Scene) -> Iterator[Finding]:
    """Frames: tf's parent, the links, the description's parent (the joint tf skips, if it lacks it); times:
    when the /tf_static value tf2 keeps arrived (another description's message), if one is static. The links
    one parent holds on tf and another in the description are one finding: one layout (a diff-drive plugin
    publishing both wheels under base_footprint), never one link explaining another."""
    moved: dict[tuple[str, str], list[tuple[Robot, Joint, int]]] = {}
    for robot, c, j in _judged(scene, Verdict.parent):
        tf_parent = c.tf_parent or j.parent
        moved.setdefault((tf_parent, j.parent), []).append((robot, j, _kept_static_arrival(scene, tf_parent, j.child)))
    for (tf_parent, parent), links in moved.items():
        robot = links[0][0]
        children = [j.child for _, j, _ in links]
        sent = max(at for _, _, at in links)
        said = f"link {children[0]} is a child" if len(links) == 1 else f"links {and_joined(children)} are children"
        joints = ", ".join(_about(j) for _, j, _ in links)
        yield Finding(
            Severity.error,
            "urdf_parent",
            f"{said} of {tf_parent} on tf, of {parent} in {_from(robot)} ({joints})",
            f"another node publishes {and_joined(children)} (a driver's own tf, a simulator's plugin, a "
            f"static_transform_publisher in a launch file): let {RSP} alone publish the robot's links, or fix the URDF",
            frames=(tf_parent, *children, parent),
            first_time=sent,
            last_time=sent,
        )


def _kept_static_arrival(scene: Scene, parent: str, child: str) -> int:
    """When the value of static edge ``parent -> child`` that tf2 keeps (the last) arrived; 0 if not static."""
    rows = scene.rows
    for p, c, mine in rows.by_edge(rows.usable & rows.static):
        if (p, c) == (parent, child):
            return int(scene.arrival(mine[-1:])[0])
    return 0


@register(
    "urdf_moved", Severity.error, "a fixed joint whose tf is not the description's origin (with a robot description)"
)
def urdf_moved(scene: Scene) -> Iterator[Finding]:
    for robot, c, j in _judged(scene, Verdict.moved):
        assert c.value is not None
        yield _on(
            j,
            Severity.error,
            "urdf_moved",
            f"{_about(j)}: tf puts {j.child} {c.translation_mm:.1f} mm and {c.rotation_deg:.2f}° from the "
            f"origin in {_from(robot)} ({_pose(*c.value)} on tf, {_pose(j.xyz, j.rotation)} in the URDF)",
            "the URDF was edited (or recalibrated) after this recording, or a static_transform_publisher with "
            f"other values publishes {j.child}: check which is right (tfx echo {j.parent} {j.child} --format urdf "
            "prints tf's as a joint)",
            _kept_static_arrival(scene, j.parent, j.child) or c.stamp,  # a static's stamp can be hours older
        )


@register(
    "urdf_joint_state", Severity.warning, "a moving joint not where /joint_states puts it (with a robot description)"
)
def urdf_joint_state(scene: Scene) -> Iterator[Finding]:
    for robot, c, j in _judged(scene, Verdict.disagrees):
        yield _on(
            j,
            Severity.warning,
            "urdf_joint_state",
            f"{_about(j)}: tf is {c.translation_mm:.1f} mm and {c.rotation_deg:.2f}° (median of {c.compared} "
            f"joint states) from where {robot.messages.joint_topic} and {_from(robot)} put {j.child}",
            f"{RSP} runs another URDF than this one (its origin or axis differ), or another node publishes {j.child}",
            c.stamp,
        )


@register(
    "urdf_kind",
    Severity.warning,
    "a fixed joint on /tf, or a moving joint only on /tf_static (with a robot description)",
)
def urdf_kind(scene: Scene) -> Iterator[Finding]:
    for _, c, j in _judged(scene, Verdict.not_static, Verdict.frozen):
        if c.verdict is Verdict.not_static:
            said = f"{_about(j)} is fixed, but {j.child} comes on /tf, not /tf_static"
            hint = "an old robot_state_publisher (ROS 1 before Kinetic), or another broadcaster: publish fixed joints "
            yield _on(j, Severity.warning, "urdf_kind", said, hint + "on /tf_static")
        else:
            said = f"{_about(j)} moves, but {j.child} comes only on /tf_static: it never moves on tf"
            hint = f"a static_transform_publisher stands in for the joint, or the URDF given to {RSP} calls it fixed"
            yield _on(j, Severity.warning, "urdf_kind", said, hint + ": check which is right")


@register("urdf_unseen", Severity.error, "a link of the description that tf never names (with a robot description)")
def urdf_unseen(scene: Scene) -> Iterator[Finding]:
    """Links no joint check covers (a joint's child is said by ``urdf_missing``): a root, or a link joined to
    nothing."""
    robot = _robot(scene)
    if robot is None:
        return
    children = {j.child for j in robot.description.joints}
    parents = {j.parent for j in robot.description.joints}
    for link in links_unseen(robot, scene.tree):
        if link in children:
            continue
        if link in parents:
            hint = f"the robot's root: {RSP} did not run, or this recording is of another robot"
        else:
            hint = f"a link joined to nothing: {RSP} cannot place it; add a joint for it in the URDF"
        yield Finding(
            Severity.error, "urdf_unseen", f"link {link} of {_from(robot)} is never named on tf", hint, frames=(link,)
        )


@register("urdf_extra", Severity.info, "frames on tf that the description lacks (with a robot description)")
def urdf_extra(scene: Scene) -> Iterator[Finding]:
    robot = _robot(scene)
    if robot is None:
        return
    extras = frames_not_described(robot, scene.tree)
    above = [e for e in extras if e.above]
    under = sorted((e for e in extras if not e.above), key=lambda e: len(scene.tree.ancestors(e.frame)))  # tops first
    if above:
        yield Finding(
            Severity.info,
            "urdf_extra",
            f"{listed([e.frame for e in above])}: above the robot's links on tf, not in {_from(robot)}",
            f"fine: odometry and localization (odom, map, world) publish the frames above the robot, not {RSP}",
            frames=tuple(e.frame for e in above),
        )
    # REP 105's odometry frame above the robot, or heading a tree apart from its links (a namespace kept: robot1/odom)
    odometry = {e.frame for e in extras if (e.above or e.parent is None) and base_name(e.frame) == "odom"}
    for e in under:
        by = scene.by(e.authorities)
        summary = scene.tree.frames.get(e.frame)
        if e.parent is None and base_name(e.frame) in WORLD_FRAMES:
            # the e-Yantra Hologlyph bags: Gazebo's odometry heads odom -> base_footprint beside the URDF's tree
            hint = (
                f"fine: REP 105's {base_name(e.frame)} frame is published by odometry or localization, not a link "
                f"{RSP} places; here it heads none of the robot's links (a tree apart from them)"
            )
        elif e.parent in odometry and summary is not None and not summary.static:
            # the real create3 (ros2_db3_create3_real_two_urdfs): its odometry moves base_footprint beside base_link
            hint = (
                f"fine: a frame moving under {e.parent} is the robot's base as its odometry publishes it (REP 105: "
                f"{e.parent} -> base_footprint or base_link), not a link {RSP} places"
            )
        else:
            hint = (
                "fine if another node owns it (a camera or lidar driver's own frames); if it is part of the robot, "
                "add it to the URDF as a link with a fixed joint"
            )
        yield Finding(
            Severity.info,
            "urdf_extra",
            f"{e.frame} ({f'a child of {e.parent}' if e.parent else 'a root'}{by}) is not a link of {_from(robot)}",
            hint,
            frames=(e.parent, e.frame) if e.parent else (e.frame,),
            authorities=e.authorities,
        )


@register(
    "urdf_joint_states", Severity.warning, "joints in /joint_states that no tf edge follows (with a robot description)"
)
def urdf_joint_states(scene: Scene) -> Iterator[Finding]:
    robot = _robot(scene)
    if robot is None:
        return
    unknown = joint_states_unfollowed(robot)
    if unknown:
        yield Finding(
            Severity.warning,
            "urdf_joint_states",
            f"{robot.messages.joint_topic} names {listed(unknown)}, which {_from(robot)} does not have: no tf edge "
            "follows them",
            f"the URDF given to {RSP} is out of date, or those joints belong to another robot (a gripper, a "
            "second arm): add them, or give that robot's URDF too",
            count=len(unknown),
        )


declare("urdf_unread", Severity.warning, "a recorded /robot_description that is not a URDF tfx reads")
