"""Checks of sensor data against tf: frames not in the tree, streams that wait for tf, messages lost for good."""

from __future__ import annotations

import difflib
import shlex
from collections.abc import Iterator, Sequence

from tftools.analysis.filter.fates import TF_LOST, parent_that_joins
from tftools.analysis.filter.namesakes import renamed_in_words
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.targets import (
    WORLD_FRAMES,
    is_odometry,
    odometry_tf_unpublished,
    world_frame_unpublished,
    world_pose_unpublished,
)
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import Scene, and_joined, base_name, duration, edge, listed
from tftools.core.figures import (
    INSTANT,
    kept_in_words,
    timeout_s,
    under_tick,
    wait_in_words,
    within_in_words,
)
from tftools.core.frames import frame_name
from tftools.core.time import NS_PER_S, from_sec
from tftools.sources.codecs.types import TF1_MESSAGE
from tftools.sources.contents import global_name, is_static_topic
from tftools.sources.errors import record_command

#: A stream "mostly needs a wait" when more than this share of its messages does.
WAITING_SHARE = 0.5
#: A stream loses messages for good worth a warning past this share.
LOST_SHARE = 0.001


def _target(scene: Scene) -> str:
    report = scene.sensors
    return f"{report.target} ({report.target_reason})"


#: How alike (difflib's ratio) a name must be to a frame of the tree to be said a misspelling of it: 'camra' and
#: 'kamera' of 'camera' (0.91, 0.83), not a TurtleBot3's lidar frame 'base_scan' of 'base_link' (0.67: a real
#: scanner's frame sharing a prefix, okoslam's cartographer bags, was asked "did you mean 'base_link'?").
TYPO_CUTOFF = 0.8


@register("sensor_frame", Severity.error, "sensor data in a frame not in the tf tree, or not connected to it")
def sensor_frame(scene: Scene) -> Iterator[Finding]:
    """One finding per missing frame, however many topics name it: one cause (e.g. the localization that
    publishes map -> odom not recorded: a MiR's /initialpose and /landmark_list in map), said once."""
    unknown_by_frames: dict[tuple[str, ...], list[tuple[str, int, int, int]]] = {}
    renamed: dict[tuple[str, ...], dict[tuple[str, str, str | None], None]] = {}  # namesakes, in order, once
    odometry: dict[tuple[str, ...], bool] = {}
    children: dict[tuple[str, ...], tuple[str, ...]] = {}  # the child frames odometry in them states
    fused: dict[tuple[str, ...], str] = {}
    for s in scene.sensors.streams:
        unknown = s.reasons.get("unknown_frame", 0)
        apart = s.reasons.get("not_connected", 0)
        if not unknown and not apart:
            continue
        missing = tuple(f for f in s.frame_ids if f and not scene.buffer.has_frame(frame_name(f)))
        if unknown:
            unknown_by_frames.setdefault(missing, []).append((s.topic, unknown, apart, s.messages))
            renamed.setdefault(missing, {}).update(dict.fromkeys(s.namesakes))
            odometry[missing] = odometry.get(missing, True) and is_odometry(s.type)
            children[missing] = tuple(dict.fromkeys(children.get(missing, ()) + s.children))
            fused[missing] = s.unplaced if s.fused and fused.get(missing, s.unplaced) == s.unplaced else ""
            continue
        # Frames tf knows, in a tree of their own: the recording's trees are apart (``disconnected``, which
        # explains this); lookups within that tree work, only those into the target fail.
        frames = listed(list(s.frame_ids), 3)
        joins = [j for f in s.frame_ids if (j := parent_that_joins(scene.buffer, scene.sensors.target, f))]
        if joins:  # at other stamps they reach the target: tf2 answered a frame on the way under its other parent
            (switching, parent), *_ = joins
            message = (
                f"{s.topic}: {apart} of {s.messages} messages are in {frames} at stamps where tf2 answers {switching} "
                f"under another parent than {parent}, in a tree apart from {_target(scene)}"
            )
            hint = (
                f"{switching} has two parents (multiple_parents): lookups and MessageFilters of this data into "
                f"{scene.sensors.target} fail where tf2 answers it under the other; one parent for it mends them"
            )
        else:
            message = f"{s.topic}: {apart} of {s.messages} messages are in {frames}, in a tree apart from "
            message += _target(scene)
            roots = and_joined(list(dict.fromkeys(scene.tree.root_of(frame_name(f)) for f in s.frame_ids if f)))
            target_root = scene.tree.root_of(scene.sensors.target)
            hint = (
                f"join {roots}'s tree to {target_root}'s, where the data's frames hang already (a transform between "
                f"them: a static_transform_publisher {target_root} -> {roots} where they are fixed to each other, "
                "localization where one moves in the other): every lookup and MessageFilter of this data into "
                f"{scene.sensors.target} fails (within its own tree they work)"
            )
        yield Finding(Severity.error, "sensor_frame", message, hint, count=apart, figures={"in_a_tree_apart": 1})
    for missing, topics in unknown_by_frames.items():
        close = {f: difflib.get_close_matches(f, scene.buffer.frames, n=1, cutoff=TYPO_CUTOFF) for f in missing}
        named = listed([f"'{f}'" + (f" (did you mean '{c[0]}'?)" if c else "") for f, c in close.items()], 3)
        if len(topics) == 1:
            ((topic, unknown, _, messages),) = topics
            where = f"{topic}: {unknown} of {messages} messages are"
        else:
            where = listed([f"{topic} ({unknown} of {messages} messages)" for topic, unknown, _, messages in topics], 3)
            where = f"{where} are"
        if fused[missing]:
            # A real PR2 (jsk_pr2eus's pr1012_sensors.bag): /base_odometry/odom in 'odom', child_frame_id empty,
            # robot_pose_ekf sending odom_combined -> base_footprint: an error told to turn the odometry's tf on.
            severity, hint = Severity.info, f"no transform names it: {fused[missing]}; lookups of this data fail"
        else:
            hint = _unknown_frame_hint(
                scene, list(missing), any(close.values()), odometry[missing], children[missing], list(renamed[missing])
            )
            severity, hint = Severity.error, hint + ": every tf lookup and MessageFilter on this data fails"
        yield Finding(
            severity,
            "sensor_frame",
            f"{where} in frame {named}, which no transform names",
            hint,
            missing,
            count=sum(unknown + apart for _, unknown, apart, _ in topics),
        )


def statics_missing(scene: Scene, what: str, also: str = "", renamed: str = "") -> str | None:
    """Why the tree holds no static transform where /tf_static was asked for: it was not recorded (``what``, the
    transforms it would carry, were not recorded or never sent: the bytes hold neither), or recorded empty; None
    where static transforms were recorded. ``renamed``, the other remedy where a tf1 recording's mounts all came
    on /tf and were recorded (data in a frame the publisher names otherwise)."""
    statics = [t for t in scene.recording.contents.topics if is_static_topic(t)]
    if scene.rows.static.any() or not statics:
        return None
    recorded = {t for f in scene.recording.contents.files for t in f.topics}
    if not recorded & set(statics):
        if _tf1_only(scene):
            # PlotJuggler's tilt_laser.bag (2012): tf1's /tf carries its mounts (tf's static_transform_publisher at
            # 10 Hz) and was recorded, /tf_static did not exist yet: the missing one was never sent
            return (
                f"this recording's /tf is tf1's ({TF1_MESSAGE}), from before /tf_static: {what} come on /tf (tf's "
                "static_transform_publisher, robot_state_publisher), which was recorded: nothing published the "
                f"missing ones; run their publisher{also or renamed}"
            )
        record = record_command(scene.ros2)
        # A real Pioneer 3-DX (murillo-teixeira/monte-carlo-localization's test1.bag, `rosbag record -a`): no
        # /tf_static because nothing published base_link -> laser (its authors add it when they replay).
        return (
            _no_topic(statics, f"{what} (robot_state_publisher's fixed joints, static_transform_publisher)", record)
            + also
            + _added_to_a_copy(scene)
        )
    return f"{and_joined(statics)}{_RECORDED_EMPTY}: {_DID_NOT_RUN}{also}"


def _added_to_a_copy(scene: Scene) -> str:
    """Where the statics were not recorded in a file: how to read it with them all the same (a copy with them added:
    e-Yantra's Krishi Bot's four trees, a scout's, joined one mount at a time); nothing for a live system."""
    files = [f.path for f in scene.recording.contents.files if not f.format.endswith("-live") and f.format != "buffer"]
    if len(files) != 1:
        return ""
    return (
        "; to read this one as if they had been: tfx static X Y Z YAW PITCH ROLL PARENT CHILD -b "
        f"{shlex.quote(files[0])} -o COPY adds one to a copy (--from FILE.yaml several)"
    )


#: ``statics_missing``'s words where /tf_static was recorded without a transform, and the publishers it blames,
#: which ``_not_described`` replaces where the description has no such link.
_RECORDED_EMPTY = " was recorded but holds no transform"
_DID_NOT_RUN = (
    "its publishers (robot_state_publisher, static_transform_publisher) sent nothing while recorded; "
    "check that they ran"
)


def _not_described(scene: Scene, missing: list[str], unrecorded: str) -> str:
    """Why /tf_static holds no mount of ``missing`` where the robot's description has no such link: nothing to
    send, not a publisher that failed to run (``unrecorded``'s words otherwise). A student's disc-robot simulator
    (PlaidTrack/CSCE-452-Project-4, project4c test1): a URDF of base_link alone, robot_state_publisher's one
    /tf_static message empty, its scans in 'laser'."""
    robot = scene.robot
    if robot is None or not unrecorded.endswith(_DID_NOT_RUN) or set(missing) & set(robot.description.links):
        return unrecorded
    return (
        f"{unrecorded.removesuffix(': ' + _DID_NOT_RUN)}, and {robot.description.source} has no link "
        f"{listed([repr(f) for f in missing], 3)} "
        f"(its links: {listed(list(robot.description.links), 5)}): robot_state_publisher had no mount of it to "
        "send; add the link and a fixed joint to it to the URDF, or publish the mount with static_transform_publisher"
    )


def _tf1_only(scene: Scene) -> bool:
    """Whether every moving tf topic recorded is tf1's ``tf/tfMessage`` (a ROS 1 system before Hydro)."""
    moving = {global_name(t) for t in scene.recording.contents.topics if not is_static_topic(t)}
    types = {kind for f in scene.recording.contents.files for t, kind in f.topics.items() if global_name(t) in moving}
    return types == {TF1_MESSAGE}


def _no_topic(topics: list[str], what: str, record: str) -> str:
    """Where the recording holds none of tf's ``topics`` (no such topic in its files): ``what`` they would carry was
    not recorded, or nothing published it; a bag without the topic cannot say which, so both, each with its
    remedy."""
    return (
        f"this recording holds no {and_joined(topics)} (no such topic in it): {what} were not recorded, or nothing "
        f"published them; record them with the rest ({record} /tf /tf_static), or run their publisher if none ran"
    )


def _unknown_frame_hint(
    scene: Scene,
    missing: list[str],
    typo: bool,
    odometry: bool = False,
    children: tuple[str, ...] = (),
    namesakes: Sequence[tuple[str, str, str | None]] = (),
) -> str:
    """What is missing where sensor data names a frame no transform names: its mount under another name (a frame
    of the tree named like it, ``namesakes``); the moving transforms, not recorded or sent empty; else a typo (a
    frame of the tree is close) or the transform's publisher (of odometry, to the ``children`` it states)."""
    rows = scene.rows
    moving = [t for t in scene.recording.contents.topics if not is_static_topic(t)]
    recorded = {t for f in scene.recording.contents.files for t in f.topics}
    record = record_command(scene.ros2)
    if namesakes and not typo and not odometry:
        # A real mapping robot of 2018 (alexbk22/robo_lape, 2018-09-20-19-57-08.bag): /scan in 'laser' and /imu/data
        # in '/imu' while its static publishers mount 'base_laser' and 'base_imu', no /tf recorded: told to record
        # /tf, where its next bag shows the fix, both sides renamed laser_frame and imu_frame.
        return renamed_in_words(namesakes)
    if not (~rows.static).any() and moving:
        if not recorded & set(moving):
            # 1hada/rosbag-merge's TurtleBot3 Waffle (TB3_WAFFLE_SLAM_odom_tf_static.bag): /odom in odom, /tf_static,
            # no /tf topic at all: cut away, or never published, the bag cannot tell.
            return _no_topic(moving, "the moving transforms (odometry's odom -> base_link, the joints)", record)
        return (
            f"{and_joined(moving)} was recorded but holds no transform: their publishers (odometry, "
            "robot_state_publisher) sent nothing while recorded; check that they ran and had their input"
        )
    if odometry and {base_name(f) for f in missing} <= WORLD_FRAMES:
        worded = listed([repr(f) for f in missing], 3)
        return "no transform names it: " + world_pose_unpublished(worded, scene.buffer.has_frame("odom"))
    if odometry:
        # frand08/ramon_slam's cartographer_records/test5.bag: /odom_enc in odom_enc (child base_footprint, in the
        # tree) and no odom_enc -> base_footprint on /tf; a mount to publish or a frame_id to set would be wrong.
        # Before the statics' words: a Clearpath Husky of 2013 (ros-planning/navigation's gps_data.bag, tf1, no
        # /tf_static yet) has /encoder in odom_combined, robot_pose_ekf's frame, which no mount would ever name.
        return "no transform names it: " + odometry_tf_unpublished(listed([repr(f) for f in missing], 3), children)
    # REP 105's frames before the mounts' words: a real Guardian's goals in 'map' (dynamic_robot_localization_tests'
    # guardian_controller_2.bag, no /tf_static, no localization recorded) were blamed on unrecorded sensor mounts,
    # while `tfx filter` named the missing map -> odom.
    named = {base_name(f) for f in missing}
    world = world_frame_unpublished(named, scene.buffer.has_frame("odom"), scene.sensors.target, scene.ros2)
    if world is not None:
        return world
    also = "; if the frame's name is a typo, set the driver's frame_id parameter instead" if typo else ""
    # Where tf1's /tf carried every mount and was recorded, both remedies, as `tfx filter` words them: a real robot
    # of 2013 (Ansrala/Delta_Project_3's teleop.bag) has its Hokuyo's scans in base_laser while its
    # static_transform_publisher mounts the laser as 'laser'. A TurtleBot3 under AMCL (PabloMatilla/IR2121
    # rosbag2_2023_10_21-21_16_22): /tf_static recorded, 0 messages, /scan in base_scan; the frame is the URDF's,
    # the missing part is its publisher's output, not a frame_id.
    renamed = ", or set the driver's frame_id parameter to the frame of the tree the sensor is at"
    if (unrecorded := statics_missing(scene, "the sensors' mounts", also, renamed)) is not None:
        return _not_described(scene, missing, unrecorded)
    if typo:
        return "set the driver's frame_id parameter to a frame of the tree (a typo?), or publish its transform"
    static = (
        "ros2 run tf2_ros static_transform_publisher" if scene.ros2 else "rosrun tf2_ros static_transform_publisher"
    )
    return (
        f"no transform names it: publish the sensor's mount (robot_state_publisher with a URDF that has the link, "
        f"or {static}), or set the driver's frame_id parameter to a frame of the tree"
    )


@register("sensor_wait", Severity.warning, "sensor data that mostly waits for tf (MessageFilter, waitForTransform)")
def sensor_wait(scene: Scene) -> Iterator[Finding]:
    """A note where the wait is within one tf period or so (data stamped at the present always waits for
    the next transform: what a MessageFilter is for); a warning past the ``delay`` threshold."""
    for s in scene.sensors.streams:
        if s.later <= WAITING_SHARE * s.messages:
            continue
        # the wait ``tfx filter`` suggests too: the timeout keeping KEEP of the messages (none if none does)
        needed = s.wait_needed if s.wait_needed is not None else int(s.wait["max"])
        # loud where most messages wait long (the p99), not where a few in a thousand did (the real boat's
        # /imu/data: 97% wait 18 ms, one 0.318 s)
        long = s.wait["p99"] > from_sec(scene.thresholds.delay)
        wait = timeout_s(needed, s.tick)
        share = kept_in_words(s.messages - sum(s.undecided.values()) - s.reasons.get("before_any_tf", 0))
        kept = f"{share} {within_in_words(needed, s.tick)}" if s.wait_needed is not None else f"at most {wait:.3f} s"
        timeout = f"{wait:.3f} s (it keeps {share} of them)" if s.wait_needed is not None else f"{wait:.3f} s"
        # an instant's wait for the transform of the message's own stamp: both sent together, the message first
        together = s.late_edge is not None and not s.late_after and _instant(s.wait["p99"], s.tick)
        yield Finding(
            Severity.warning if long else Severity.info,
            "sensor_wait",
            f"{s.topic}: {s.later} of {s.messages} messages could not be transformed into {_target(scene)} when they "
            f"arrived, waiting {wait_in_words(s.wait['p50'], s.tick)} ({kept}) for "
            f"{edge(*s.late_edge) + ': ' + s.wait_made_of() if s.late_edge else 'tf'}"
            + (_TOGETHER if together else "")
            + _undecided(s.undecided),
            f"{_at_once(scene, s.frame_ids, s.late_edge)}a node transforming it at once fails with 'extrapolation "
            f"into the future': use a tf2_ros MessageFilter (queue {max(s.queue_needed, 1)}) or "
            f"canTransform/lookupTransform with a timeout of at least {timeout}, or "
            + (
                "send the transform before the message (where one node publishes both)"
                if together
                else "make the late transform come sooner"
            ),
            s.late_edge or (),
            count=s.later,
        )


#: What an instant's wait (``INSTANT``) for the transform of a message's own stamp is, and who it matters to.
_TOGETHER = (
    ". Each waits only for the transform of its own stamp, which comes just after it (sent together, the message "
    "first): a MessageFilter holds it that instant and passes it; only a node that looks the transform up as the "
    "message arrives, without waiting, fails"
)


#: Why the recording cannot tell what became of messages (``StreamReport.undecided``), in words.
_UNDECIDED = {
    "before_recorded_tf": "stamped before the recording's tf of their chain began",
    "after_recorded_tf": "still waiting when the recording ended",
}


def _undecided(undecided: dict[str, int]) -> str:
    """The messages a stream's counts leave out, where the recording cannot tell their fate (a simulated TurtleBot3's
    first 5 IMU messages, stamped before its odometry's first: '5168 of 5280 waited' beside 107 on arrival)."""
    said = [f"{n} {_UNDECIDED.get(reason, reason.replace('_', ' '))}" for reason, n in undecided.items() if n]
    return f" ({'; '.join(said)}: undecided, left out)" if said else ""


def _instant(wait_ns: float, tick: int) -> bool:
    """Whether a wait is an instant (``INSTANT``), on a clock fine enough to tell (not under one ``tick``)."""
    return wait_ns < INSTANT and not under_tick(wait_ns, tick)


def _at_once(scene: Scene, frame_ids: tuple[str, ...], late: tuple[str, str] | None) -> str:
    """Where the data's frames hang from the late edge's child by fixed transforms alone (an IMU's imu_link under
    base_link, which the motion capture's world -> base_link moves): into that child it transforms at once, and only
    a lookup through the late edge waits; "" otherwise (the hint then says what waiting takes)."""
    if late is None:
        return ""
    frames = sorted({frame_name(f) for f in frame_ids if f})
    if not frames or not all(_fixed_under(scene, f, late[1]) for f in frames):
        return ""
    fixed = [f for f in frames if f != late[1]]
    if not fixed:  # data in the late edge's child: that edge is its own frame's, and no frame holds it still
        return ""
    target = scene.sensors.target
    return f"into {late[1]} ({listed(fixed, 3)} fixed to it) it transforms at once, with no wait; into {target}, "


def _fixed_under(scene: Scene, frame: str, above: str) -> bool:
    """Whether ``frame`` is ``above`` or reaches it through static transforms alone."""
    tree = scene.tree.frames
    while frame != above:
        summary = tree.get(frame)
        if summary is None or summary.parent is None or not summary.static:
            return False
        frame = summary.parent
    return True


@register("sensor_lost", Severity.warning, "sensor data a MessageFilter loses for good (tf too late, or too old)")
def sensor_lost(scene: Scene) -> Iterator[Finding]:
    cache_s = scene.sensors.cache_time / NS_PER_S
    for s in scene.sensors.streams:
        lost = sum(s.reasons.get(f.reason, 0) for f in TF_LOST)
        if lost <= LOST_SHARE * s.messages:
            continue
        why = []
        early = min(s.before_tf, lost)
        after = " stamped after tf began" if early or s.stamped_zero else ""
        cache = f" (a cache of {s.cache_needed / NS_PER_S:g} s would keep those{after})" if s.cache_needed else ""
        if s.reasons.get("too_old_on_arrival"):
            old = s.reasons["too_old_on_arrival"]
            why.append(f"{old} already older than the {cache_s:g} s cache when they arrived{cache}")
            cache = ""
        # stamped 0 before their chain existed: dropped as older than the cache, which no cache helps
        if older := s.reasons.get("older_than_cache", 0) - s.stamped_zero:
            why.append(f"{older} older than the {cache_s:g} s cache holds by the time tf reached them{cache}")
        if s.stamped_zero:
            why.append(
                f"{'all' if s.stamped_zero == lost else s.stamped_zero} of them stamped 0 (header.stamp unset) and "
                "arriving before the recording's tf of their chain existed: tf2 reads stamp 0 as the latest "
                "transform only where there is one, and drops a request still waiting with it once tf comes "
                "(time 0 is then older than the cache holds)"
            )
        if early and s.before_any_tf:
            why.append(
                f"{'all' if early == lost else early} of them stamped before the first tf anyone published: the "
                "sensor started before tf; no cache keeps those and there is nothing to record earlier: drop "
                "messages stamped before tf starts"
            )
        elif early:
            why.append(
                f"{'all' if early == lost else early} of them stamped before the recording's tf of their chain "
                "began: no cache keeps those; record tf from before the sensor starts, or drop messages stamped "
                "before tf starts"
            )
        edge_ = edge(*s.lost_edge) if s.lost_edge else "tf"
        if s.clock_apart:  # observed: stamps hours from tf's, each against its arrival; no wait reaches them
            side = "ahead of" if s.clock_apart > 0 else "behind"
            why = [  # the one cause of them all, said instead of each fate's
                f"{'all' if lost == s.messages else lost} stamped {duration(abs(s.clock_apart) / NS_PER_S)} {side} "
                f"{edge_}'s samples, each against when it arrived: the sensor's stamps are on another clock than tf's, "
                "so no wait or cache reaches them"
            ]
        elif s.reasons.get("needs_newer_tf"):
            why.append(f"{s.reasons['needs_newer_tf']} waiting for {edge_}, which stopped before reaching their stamps")
        if s.clock_apart:
            hint = (
                f"tf2 compares stamps on one clock: sync the clocks of the sensor's and tf's machines (chrony/NTP), "
                f"or stamp {s.topic} with the clock tf is stamped on"
            )
        elif s.stamped_zero == lost:
            hint = (
                "a MessageFilter drops these ('earlier than all the data in the transform cache'): set header.stamp "
                "to when the data was measured, or start the tf publishers before this one"
            )
        else:
            hint = (
                "a MessageFilter drops these ('earlier than all the data in the transform cache'), or holds them "
                "until its queue pushes them out: stamp the data when it was measured, and check the clocks and "
                "that every tf publisher keeps publishing"
            )
        yield Finding(
            Severity.warning,
            "sensor_lost",
            f"{s.topic}: {lost} of {s.messages} messages could never be transformed into {_target(scene)}: "
            f"{'; '.join(why)}",
            hint,
            s.lost_edge or s.late_edge or (),
            count=lost,
        )
