"""The robot's description against its tf: which of the URDF's joints tf carries, where, and as the joint
states say; which links tf never names, which frames the URDF lacks, which joint states no tf edge follows.

robot_state_publisher turns the URDF's fixed joints into /tf_static and its moving joints, with the
positions ``/joint_states`` gives (joint_state_publisher's, or a driver's), into /tf; odometry and
localization publish the frames above the robot (odom, map). Each ``JointCheck`` says what tf did with
one joint, for ``analysis.wtf.description`` to word as findings.
"""

from __future__ import annotations

import contextlib
import enum
import math
import os
from collections import Counter
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from tftools.analysis.differences import Change, Difference, rotation_angle_deg
from tftools.analysis.expected import FrameShape, Tolerances, TreeShape
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.frames import FrameTree
from tftools.core.buffer import Buffer
from tftools.core.errors import TfToolsError
from tftools.core.rotation import Quat, Vec3
from tftools.sources.bag.robot import DESCRIPTION_TOPIC, ROBOT_TOPICS, RobotMessages
from tftools.sources.recording import Recording, read_recording
from tftools.sources.urdf import RobotDescription, UrdfError, parse_urdf, with_prefix

#: Joint states compared with tf, at most, spread evenly over the recording.
MAX_COMPARED = 200


class Verdict(str, enum.Enum):
    """What tf did with one of the URDF's joints."""

    fine = "fine"
    missing = "missing"  # its child link never on tf
    parent = "parent"  # on tf, under another parent
    moved = "moved"  # a fixed joint whose tf value is not the URDF's origin
    not_static = "not_static"  # a fixed joint published on /tf (it works, but costs)
    frozen = "frozen"  # a moving joint published on /tf_static only
    disagrees = "disagrees"  # a moving joint whose tf is not where its joint state puts it


@dataclass(frozen=True)
class Robot:
    """A description and what the recording says of the robot (its joint states), ready to check."""

    description: RobotDescription
    messages: RobotMessages = field(default_factory=RobotMessages)
    tolerances: Tolerances = field(default_factory=Tolerances)
    live: bool = False  # checked against a live system: its joint states are not heard

    @cached_property
    def joint_names(self) -> set[str]:
        """Every joint named in a recorded joint state."""
        return {name for state in self.messages.joint_states for name in state.positions}


@dataclass(frozen=True)
class JointCheck:
    """One joint as tf showed it: the verdict, tf's parent of its child, how far off it was (mm,
    degrees: the latest static value, or the median over the joint states compared), and when."""

    joint: str
    verdict: Verdict
    tf_parent: str | None = None
    translation_mm: float = 0.0
    rotation_deg: float = 0.0
    compared: int = 0
    stamp: int = 0  # a moment it was off (ns), 0: none
    value: tuple[Vec3, Quat] | None = None  # tf's (the latest static one)


def check_joints(robot: Robot, buffer: Buffer, tree: FrameTree) -> list[JointCheck]:
    """Each of the URDF's joints, in its order, as tf showed it."""
    states = _positions_over_time(robot)
    return [
        _joint(robot, joint_name, buffer, tree, states) for joint_name in (j.name for j in robot.description.joints)
    ]


def _joint(
    robot: Robot, name: str, buffer: Buffer, tree: FrameTree, states: tuple[np.ndarray, dict[str, np.ndarray]]
) -> JointCheck:
    joint = robot.description.joint(name)
    shown = tree.frames.get(joint.child)
    if shown is None or shown.parent is None:
        return JointCheck(name, Verdict.missing)
    if shown.parent != joint.parent:
        return JointCheck(name, Verdict.parent, shown.parent)
    hist = buffer.history(joint.child)
    if joint.type == "fixed":
        if hist is None or not len(hist):
            return JointCheck(name, Verdict.missing)
        latest = int(np.argmax(hist.sequence))
        t = tuple(float(v) for v in hist.translations[latest])
        q = tuple(float(v) for v in hist.rotations[latest])
        value = ((t[0], t[1], t[2]), (q[0], q[1], q[2], q[3]))
        mm = 1000.0 * math.dist(value[0], joint.xyz)
        deg = rotation_angle_deg(value[1], joint.rotation)
        tol = robot.tolerances
        if mm > tol.translation_mm or deg > tol.rotation_deg:
            return JointCheck(name, Verdict.moved, shown.parent, mm, deg, stamp=int(hist.stamps[latest]), value=value)
        if not shown.static:
            return JointCheck(name, Verdict.not_static, shown.parent, mm, deg, value=value)
        return JointCheck(name, Verdict.fine, shown.parent, mm, deg, value=value)
    if not joint.moving:
        return JointCheck(name, Verdict.fine, shown.parent)  # floating, planar: placed by another node
    if shown.static:
        return JointCheck(name, Verdict.frozen, shown.parent)
    return _follows(robot, joint.name, buffer, states)


def _positions_over_time(robot: Robot) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The joint states' stamps (at most ``MAX_COMPARED``, evenly spread) and each joint's position
    at them (NaN where a message did not name it)."""
    states = robot.messages.joint_states
    if not states:
        return np.zeros(0, np.int64), {}
    chosen = np.unique(np.linspace(0, len(states) - 1, min(len(states), MAX_COMPARED)).round().astype(np.int64))
    stamps = np.array([states[i].stamp for i in chosen.tolist()], np.int64)
    positions: dict[str, np.ndarray] = {}
    for k, i in enumerate(chosen.tolist()):
        for joint, q in states[i].positions.items():
            positions.setdefault(joint, np.full(len(chosen), np.nan))[k] = q if math.isfinite(q) else math.nan
    return stamps, positions


def _follows(robot: Robot, name: str, buffer: Buffer, states: tuple[np.ndarray, dict[str, np.ndarray]]) -> JointCheck:
    """A moving joint: tf's transform at each joint state's stamp, against where that state puts it
    (a mimic joint: where its leader's state puts it). robot_state_publisher stamps each transform with
    its joint state's stamp: where tf has samples at those stamps, only they are compared (between two
    samples, a joint turning more than half a turn would be interpolated the short way round)."""
    joint = robot.description.joint(name)
    stamps, positions = states
    leader, multiplier, offset = joint.mimic if joint.mimic is not None else (joint.name, 1.0, 0.0)
    given = positions.get(leader)
    if given is None:
        return JointCheck(name, Verdict.fine, joint.parent)  # nothing to compare with (said elsewhere)
    known = ~np.isnan(given)
    hist = buffer.history(joint.child)
    if hist is not None and np.isin(stamps[known], hist.stamps).any():
        known &= np.isin(stamps, hist.stamps)
    looked = buffer.lookup_many(joint.parent, joint.child, stamps[known])
    with np.errstate(over="ignore", invalid="ignore"):  # a mimic's multiplier of 1e308: no position, no warning
        qs = given[known][looked.valid] * multiplier + offset
    usable = np.isfinite(qs)
    qs = qs[usable]
    if not len(qs):
        return JointCheck(name, Verdict.fine, joint.parent)
    translations, rotations = looked.translations[looked.valid][usable], looked.rotations[looked.valid][usable]
    mms, degs = [], []
    for q, t, r in zip(qs.tolist(), translations, rotations, strict=True):
        xyz, quat = joint.transform_at(q)
        mms.append(1000.0 * math.dist(xyz, t.tolist()))
        degs.append(rotation_angle_deg(quat, (float(r[0]), float(r[1]), float(r[2]), float(r[3]))))
    mm, deg = float(np.median(mms)), float(np.median(degs))
    tol = robot.tolerances
    # tf interpolates between its samples, a joint state stands alone: a looser bound than for statics
    off = mm > max(tol.translation_mm, 5.0) or deg > max(tol.rotation_deg, 1.0)
    worst = int(np.argmax(degs if deg > max(tol.rotation_deg, 1.0) else mms))
    when = int(looked.stamps[looked.valid][usable][worst])
    return JointCheck(
        name,
        Verdict.disagrees if off else Verdict.fine,
        joint.parent,
        mm,
        deg,
        compared=len(qs),
        stamp=when if off else 0,
    )


def links_unseen(robot: Robot, tree: FrameTree) -> list[str]:
    """The URDF's links that tf never names (as a parent or a child)."""
    return [link for link in robot.description.links if link not in tree.frames]


@dataclass(frozen=True)
class Extra:
    """A frame tf has that the URDF lacks: ``above`` the robot (odom, map: odometry's and localization's,
    fine), or under one of its links (a driver's own frame, or a link missing from the URDF)."""

    frame: str
    parent: str | None
    above: bool
    authorities: tuple[str, ...]


def frames_not_described(robot: Robot, tree: FrameTree) -> list[Extra]:
    """tf's frames that are not links of the URDF, the frames above the robot's root first."""
    links = set(robot.description.links)
    roots = [link for link in robot.description.links if robot.description.joint_of(link) is None]
    above: set[str] = set()
    for root in roots:
        frame: str | None = tree.frames[root].parent if root in tree.frames else None
        while frame is not None and frame not in above and frame not in links:
            above.add(frame)
            frame = tree.frames[frame].parent if frame in tree.frames else None
    extras = [
        Extra(name, f.parent, name in above, f.authorities) for name, f in tree.frames.items() if name not in links
    ]
    return sorted(extras, key=lambda e: not e.above)


def joint_states_unfollowed(robot: Robot) -> list[str]:
    """Joints named in /joint_states that the URDF does not have: no tf edge follows them."""
    described = {j.name for j in robot.description.joints}
    return sorted(robot.joint_names - described)


def states_missing(robot: Robot, joints: Sequence[str]) -> list[str]:
    """Of ``joints`` (moving ones), those no recorded joint state names (mimic joints: by their leader)."""
    named = robot.joint_names
    missing = []
    for name in joints:
        joint = robot.description.joint(name)
        leader = joint.mimic[0] if joint.mimic is not None else name
        if leader not in named:
            missing.append(name)
    return missing


def robot_of(
    paths: Sequence[str | os.PathLike[str]],
    recording: Recording,
    urdf: RobotDescription | None,
    tolerances: Tolerances | None = None,
) -> tuple[Robot | None, Finding | None]:
    """The robot to check ``recording`` (read from ``paths``) against: the ``urdf`` given, else the
    recorded /robot_description; None where there is neither. A recorded description that cannot be
    used is a finding (``urdf_unread``), not an error: the other checks still run."""
    topics = {t for f in recording.contents.files for t in f.topics}
    if urdf is None and DESCRIPTION_TOPIC not in topics:
        return None, None
    if recording.contents.live:
        if urdf is None:
            return None, None
        return Robot(_prefixed(urdf, recording), tolerances=tolerances or Tolerances(), live=True), None
    messages = RobotMessages()
    if any(w.topic in ROBOT_TOPICS for w in recording.contents.whole):  # read with the transforms
        messages = recording.robot
    elif set(ROBOT_TOPICS) & topics:
        with contextlib.suppress(TfToolsError):  # the transforms were read: the joints are checked without states
            messages = read_recording(paths, ROBOT_TOPICS, allow_empty=True, whole=ROBOT_TOPICS).robot
    if urdf is None:
        if not messages.description:
            return None, None
        try:
            urdf = parse_urdf(messages.description, f"the recorded {DESCRIPTION_TOPIC}")
        except UrdfError as error:
            return None, Finding(
                Severity.warning,
                "urdf_unread",
                f"{error}: the robot's description is not checked",
                f"{error.hint} (tfx wtf --urdf FILE checks against a URDF file instead)",
            )
    return Robot(_prefixed(urdf, recording), messages, tolerances or Tolerances()), None


def _prefixed(description: RobotDescription, recording: Recording) -> RobotDescription:
    return with_prefix(description, frame_prefix(description, set(recording.buffer.frames)))


def frame_prefix(description: RobotDescription, frames: Collection[str]) -> str:
    """The prefix tf's names of the robot's links have (``robot1/`` of ``robot1/base_link``: a namespaced
    robot_state_publisher's ``frame_prefix``), "" where tf names more of them as the URDF does."""
    links = set(description.links)
    counts: Counter[str] = Counter()
    for frame in frames:
        prefix, slash, base = frame.rpartition("/")
        if slash and base in links:
            counts[prefix + slash] += 1
    if not counts:
        return ""
    prefix, most = counts.most_common(1)[0]
    return prefix if most > sum(link in frames for link in links) else ""


def description_shape(description: RobotDescription) -> TreeShape:
    """The description as a tree's shape (``tfx diff robot.urdf run.bag``): each link under its joint's
    parent, fixed joints static at their origin, moving ones at any rate."""
    frames: dict[str, FrameShape] = {}
    for link in description.links:
        joint = description.joint_of(link)
        if joint is None:
            frames[link] = FrameShape(link, None)
        elif joint.type == "fixed":
            frames[link] = FrameShape(link, joint.parent, static=True, translation=joint.xyz, rotation=joint.rotation)
        else:
            frames[link] = FrameShape(link, joint.parent)
    return TreeShape(frames, description.source)


def above_the_robot(description: RobotDescription, tree: TreeShape) -> set[str]:
    """The frames of ``tree`` above the description's roots (odom, map): odometry's and localization's."""
    above: set[str] = set()
    for link in description.links:
        if description.joint_of(link) is not None or link not in tree.frames:
            continue
        frame = tree.frames[link].parent
        while frame is not None and frame not in above and frame in tree.frames:
            above.add(frame)
            frame = tree.frames[frame].parent
    return above


def described_differences(
    differences: Sequence[Difference], description: RobotDescription, tree: TreeShape
) -> list[Difference]:
    """``differences`` between a description's shape and a recording's ``tree`` but those every healthy
    robot has: the robot's root under odom, the frames above it, and rates (a URDF has none)."""
    above = above_the_robot(description, tree)
    return [
        d
        for d in differences
        if d.change is not Change.rate
        and not (
            d.change is Change.reparented
            and d.before is not None
            and d.before.parent is None
            and (d.after is None or d.after.parent in above)
        )
        and not (
            d.change is Change.reparented
            and d.after is not None
            and d.after.parent is None
            and d.before is not None
            and d.before.parent in above
        )
        and not (d.change in (Change.added, Change.lost) and d.frame in above)
    ]
