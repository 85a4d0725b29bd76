"""Checks of clocks, on the recording's timeline: frames stamped on another clock than the rest or than
``/clock`` (the use_sim_time mistake), and ``/clock`` itself (jumps back, pauses, tf before it began)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import Scene, and_joined, duration, edge, listed, transforms
from tftools.core.figures import same_base
from tftools.core.time import EPOCH_FLOOR, NS_PER_S
from tftools.sources.edge_clocks import EdgeClock, clock_groups, stamps_behind
from tftools.sources.errors import play_command, record_command
from tftools.sources.timeline import Reference

#: /clock silent this long (record clock) while the recording goes on: ROS time stood still.
CLOCK_PAUSE = 1 * NS_PER_S
#: tf arriving this long before the first /clock message is worth a note.
BEFORE_CLOCK = 1 * NS_PER_S
#: A stamp below this is ROS time before any /clock (0, or 0 plus a post-dating such as AMCL's
#: transform_tolerance): the node had no simulated time yet.
NO_TIME_YET = 1 * NS_PER_S


def _hint(kind: str, ros2: bool) -> str:
    """What to do about frames stamped on another clock (``kind``), in the words of the recording's ROS."""
    now = "the node's clock (node->now())" if ros2 else "ros::Time::now()"
    play = play_command(ros2)
    return {
        "boot": "the publisher stamps with a clock other than ROS time (time since boot, a steady or sensor clock), "
        f"or runs with use_sim_time while nothing publishes /clock: stamp with {now} and set use_sim_time the "
        "same for every node",
        "simulated": "the other frames run on simulated time (use_sim_time, /clock) but this publisher stamps "
        f"wall-clock time: set use_sim_time true for it too (and replay bags with {play})",
        "behind": f"stamps from an older time: a bag replayed without --clock while nodes run on wall time (use "
        f"{play} with use_sim_time true), or this publisher's machine clock is behind: sync the clocks "
        "(chrony/NTP)",
        "ahead": "this publisher's clock runs ahead of the others': sync the clocks (chrony/NTP), or set "
        "use_sim_time the same for every node",
        "device": "no lookup combines the two clocks (the trees are apart): lookups within each tree work. To look "
        "the device's frames up with the simulated ones, put both on one clock (the device's driver on use_sim_time, "
        "stamping the simulation's time, and a transform joining its tree to the robot's), or keep the two trees "
        "apart and look each up on its own clock",
        "described": "robot_state_publisher (and the joint states it follows) runs without use_sim_time beside the "
        f"simulation: set use_sim_time true for it too (and replay bags with {play})",
        "joined": "lookups combining these frames with the simulated ones fail with extrapolation errors: put them "
        "on one clock. A node of the simulation: set use_sim_time true for it "
        f"too (and replay bags with {play}). A real device beside the simulation, whose driver stamps the wall "
        "clock: stamp its messages with the simulation's time (its driver, or a bridge node restamping them, on "
        "use_sim_time), or keep its frames a tree of their own, joined to no simulated frame, and look each tree up "
        "on its own clock",
        "bases": "the record times time nothing, so the bytes do not tell which clock each publisher keeps (a "
        "simulation's time, time since boot, or the wall clock of a node without use_sim_time): record with "
        f"{record_command(ros2)}, which stores when each message arrived, and /clock with them to tell them apart "
        "(the frames following /clock are on the simulation's time, those keeping time with the record clock on the "
        "wall clock). To look them up together, stamp every publisher on one clock (use_sim_time the same for every "
        "node)",
        "zero": "no /clock was recorded: if these are a simulation's frames (Gazebo, Webots and Stage stamp their "
        f"own time), record /clock with them ({record_command(ros2)} /clock ...) so that "
        "their time can be read; frames stamped on the wall clock (a real device's) combine with them only once both "
        f"are on one clock. If a driver stamps time since boot (a steady or sensor clock), stamp with {now}",
    }[kind]


_CONSEQUENCE = "; until then lookups combining these with other frames fail with extrapolation errors"
_APART = (
    "; these frames are a tree of their own, apart from the frames on the other clock (disconnected), so no "
    "lookup combines the two clocks: lookups within each tree work"
)


def _consequence(scene: Scene, edges: Sequence[EdgeClock]) -> str:
    """What the other clock does to lookups: those combining ``edges``' frames with the others fail, unless
    they are a tree apart from every frame on the other clock (then no lookup combines the two)."""
    return _APART if _tree_apart(scene, edges) else _CONSEQUENCE


def _tree_apart(scene: Scene, edges: Sequence[EdgeClock]) -> bool:
    """Whether ``edges``' frames are a tree (or trees) apart from every other moving frame's."""
    root_of = {frame: root for root, members in scene.tree.trees().items() for frame in members}
    theirs = {root_of.get(e.child) for e in edges}
    mine = {e.child for e in edges}
    others = {root_of.get(e.child) for e in scene.timeline.edges if e.child not in mine}
    return bool(others) and None not in theirs | others and not theirs & others


def _wall_kind(scene: Scene, edges: Sequence[EdgeClock]) -> str:
    """What ``edges``, stamped on wall-clock time beside frames on /clock, are: where their stamps keep time with
    the record clock (each arriving within ``same_clock`` of its stamp, as a live publisher's on the wall clock),
    a device's on purpose when they are a tree of their own (``device``), as a real sensor's driver stamps beside a
    simulation; in the simulated tree, a publisher on the wall clock joined to it (``joined``): a node that forgot
    use_sim_time or a real device's driver, which the bytes do not tell apart. Else ``simulated``."""
    near = scene.timeline.same_clock
    if not all(abs(e.offset_record) <= near for e in edges):
        return "simulated"
    if _described(scene, edges):
        return "described"
    return "device" if _tree_apart(scene, edges) else "joined"


def _described(scene: Scene, edges: Sequence[EdgeClock]) -> bool:
    """Whether ``edges`` are all joints of the robot's description (robot_state_publisher's, not a device's)."""
    robot = scene.robot
    if robot is None:
        return False
    joints = {(j.parent, j.child) for j in robot.description.joints}
    return all((_parent(scene, e.child), e.child) in joints for e in edges)


def _zero_kind(scene: Scene, kind: str) -> str:
    """``kind``, or ``zero`` for stamps counting from zero (``boot``) beside frames on the wall clock where no
    /clock was recorded: a simulation's time (its /clock not recorded) or a clock since boot, which the bytes do
    not tell apart (a real Neato's driver stamps time since boot at a pace 0.3% off the wall clock, as Gazebo's
    real-time factor does)."""
    return "zero" if kind == "boot" and not len(scene.timeline.clock) else kind


@register("clock", Severity.error, "frames stamped on another clock than the others or /clock (use_sim_time)")
def clock(scene: Scene) -> Iterator[Finding]:
    timeline = scene.timeline
    if timeline.reference is Reference.NONE:
        yield from _without_reference(scene)
        return
    against = timeline.reference is Reference.CLOCK
    on = [e for e in timeline.edges if e.child not in timeline.off_reference]
    off = [e for e in timeline.edges if e.child in timeline.off_reference and not _stood_still(e, on)]
    groups: dict[str, list[EdgeClock]] = {}
    for e in off:
        groups.setdefault(_kind(_offset(e, against), e.median_stamp, _reference_time(e, against)), []).append(e)
    for kind, edges in groups.items():
        said = _wall_kind(scene, edges) if kind == "simulated" else _zero_kind(scene, kind)
        yield _disagreeing(scene, said, edges, on, against)
    if timeline.reference is Reference.RECORD and len(timeline.clock) and on:
        yield _ignoring_clock(scene, on)
    if timeline.reference is Reference.CLOCK:
        yield from _wall_receive_times(scene)


def _stood_still(e: EdgeClock, others: Sequence[EdgeClock]) -> bool:
    """Whether ``e``'s stamps stood still (one stamp, re-sent or not) behind the ``others`` on their time base:
    an old stamp (``stale`` reports it), no evidence of another clock; one stamp on another time base
    (epoch time among simulated time) or ahead of the others still is."""
    moving = [o for o in others if o is not e and o.last_stamp > o.first_stamp]
    if e.last_stamp > e.first_stamp or not moving:
        return False
    newest = max(o.last_stamp for o in moving)
    return same_base(e.last_stamp, newest) and e.last_stamp <= newest


def _offset(e: EdgeClock, against_clock: bool) -> int:
    offset = e.offset(against_clock)
    return e.offset_record if offset is None else offset


def _reference_time(e: EdgeClock, against_clock: bool) -> int:
    return e.median_stamp + _offset(e, against_clock)


def _kind(offset: int, stamp: int, reference: int) -> str:
    """How stamps relate to the clock they should follow: from boot, wall among simulated, behind, ahead."""
    if stamp < EPOCH_FLOOR <= reference:
        return "boot"
    if reference < EPOCH_FLOOR <= stamp:
        return "simulated"
    return "behind" if offset > 0 else "ahead"


def _disagreeing(
    scene: Scene, kind: str, edges: Sequence[EdgeClock], agreeing: Sequence[EdgeClock], against_clock: bool
) -> Finding:
    stamp = float(np.median([e.median_stamp for e in edges])) / NS_PER_S
    reference = float(np.median([_reference_time(e, against_clock) for e in edges])) / NS_PER_S
    offset = float(np.median([_offset(e, against_clock) for e in edges])) / NS_PER_S
    clock_name = scene.timeline.clock.topic if against_clock else "the recording's clock"
    source = scene.robot.description.source if scene.robot else ""
    names = [e.child for e in agreeing]
    named = and_joined(names) if len(names) <= 3 else listed(names, 3)
    following = f" (which {named} follow{'s' if len(agreeing) == 1 else ''})"
    following = following if agreeing else ""  # "behind the recording's clock and odom" read as two things
    on_wall_clock = (
        f"stamped with wall-clock time ({stamp:.1f} s), arriving {_after(edges)} after their stamps by the record "
        f"clock, while {clock_name}{following} runs on simulated time ({reference:.1f} s)"
    )
    said = {
        "boot": f"stamped around {stamp:.1f} s, a clock counting from boot or a simulation's start, while "
        f"{clock_name}{following} reads {reference:.1f} s (epoch time)",
        "simulated": f"stamped with wall-clock time ({stamp:.1f} s) while {clock_name}{following} runs on simulated "
        f"time ({reference:.1f} s)",
        "device": f"{on_wall_clock}; a tree of their own: a device on the wall clock beside the simulation",
        "described": f"{on_wall_clock}: joints of {source}, robot_state_publisher's",
        "joined": f"{on_wall_clock}, in one tree with them ({_tree_of(scene, edges)}): a publisher on the wall "
        "clock (a node without use_sim_time, or a real device's driver) joined to the simulated frames",
        "zero": f"stamped around {stamp:.1f} s, on a clock counting from zero (a simulation's time or time since "
        f"boot: no /clock was recorded to tell which), while {clock_name}{following} reads {reference:.1f} s "
        "(epoch time)",
        "behind": f"stamped {duration(offset)} behind {clock_name}{following}: another clock",
        "ahead": f"stamped {duration(-offset)} ahead of {clock_name}{following}: another clock",
    }[kind]
    return _two_clocks(scene, kind, edges, f"{said} (median of {transforms(sum(e.arrivals for e in edges))})")


def _after(edges: Sequence[EdgeClock]) -> str:
    """How long after their stamps ``edges``' transforms were recorded (the median), in the unit a person reads."""
    seconds = float(np.median([e.offset_record for e in edges])) / NS_PER_S
    return f"{seconds * 1000:.1f} ms" if abs(seconds) < 1 else duration(seconds)


def _tree_of(scene: Scene, edges: Sequence[EdgeClock]) -> str:
    """Where ``edges``' frames are in the tree: under which root ("under odom")."""
    root_of = {frame: root for root, members in scene.tree.trees().items() for frame in members}
    roots = sorted({root_of[e.child] for e in edges if e.child in root_of})
    return f"under {and_joined(roots)}" if roots else "in a loop"


def _two_clocks(scene: Scene, kind: str, edges: Sequence[EdgeClock], said: str) -> Finding:
    """The error that ``edges`` are stamped on another clock (``kind``), as ``said``; with how long after
    their stamps they arrived (``arrival_minus_stamp_s``), which tells the clock they are on."""
    authorities = _authorities(scene, [e.child for e in edges])
    return Finding(
        Severity.error,
        "clock",
        f"{listed([edge(_parent(scene, e.child), e.child) for e in edges], 4)}{scene.by(authorities)}: {said}",
        _hint(kind, scene.ros2) + ("" if kind in ("device", "joined") else _consequence(scene, edges)),
        tuple(f for e in edges for f in (_parent(scene, e.child), e.child)),
        authorities,
        count=sum(e.arrivals for e in edges),
        # record times that are no clock time no arrival: no figure (it read -1731467407.96 s)
        figures={}
        if scene.timeline.record_clock_void
        else {"arrival_minus_stamp_s": float(np.median([e.offset_record for e in edges])) / NS_PER_S},
    )


def _without_reference(scene: Scene) -> Iterator[Finding]:
    """No frame follows the record clock or /clock: the frames agreeing with most others are the tf clock
    (a note on what cannot be measured); those on yet another clock disagree with them (an error)."""
    edges = scene.timeline.edges
    moving = [e for e in edges if not _stood_still(e, edges)]
    if scene.timeline.record_clock_void:  # offsets from no clock tell nothing: only the time bases differ
        bases = (
            [e for e in moving if e.median_stamp < EPOCH_FLOOR],
            [e for e in moving if e.median_stamp >= EPOCH_FLOOR],
        )
        clusters = [base for base in bases if base]
    else:
        clusters = clock_groups(moving, scene.timeline.same_clock)
    main = max(clusters, key=len)
    for cluster in clusters:
        if cluster is not main:
            void = scene.timeline.record_clock_void
            yield _two_bases(scene, cluster, main) if void else _disagreeing_with_others(scene, cluster, main)
    if scene.timeline.record_clock_void:
        hint = (
            "record with ros2 bag record, which stores when each message arrived; a script writing a bag "
            "(rosbag2_py) must give each message its receive time in nanoseconds"
            if scene.ros2
            else "record with rosbag record, which stores when each message arrived"
        )
        yield Finding(Severity.info, "clock", scene.timeline.reason, hint, count=sum(e.arrivals for e in edges))
        return
    yield Finding(
        Severity.info,
        "clock",
        scene.timeline.reason,
        _unmeasured_hint(scene, main) + "; lookups between these frames are not affected",
        count=sum(e.arrivals for e in main),
        figures={"arrival_minus_stamp_s": stamps_behind(edges) / NS_PER_S},  # said in the unit a person reads
    )


#: Epoch stamps this far behind the record clock are no simulation's nor a boot clock's: an earlier run's.
REPLAYED_BEHIND = 86_400 * NS_PER_S


def _unmeasured_hint(scene: Scene, main: Sequence[EdgeClock]) -> str:
    """What puts the tf clock apart from the record clock: a simulation or a boot clock (stamps counting from
    zero), or, for epoch stamps days behind, an earlier recording replayed without its clock (CougUV's AUV,
    6 days; foxglove-wizard's drone flight of 2018 recorded in 2024)."""
    epoch = float(np.median([e.median_stamp for e in main])) >= EPOCH_FLOOR
    if epoch and stamps_behind(main) > REPLAYED_BEHIND:
        play = play_command(scene.ros2)
        record = (
            "with ros2 bag record --use-sim-time"
            if scene.ros2
            else "under /use_sim_time true (rosbag record then follows /clock)"
        )
        return (
            f"a replay of an earlier recording, recorded without its clock: play it with {play} and record it "
            f"{record}, so the copy keeps the original times; or a computer whose clock was not synchronized "
            "(NTP, chrony)"
        )
    return (
        "a simulation: record it with ros2 bag record --use-sim-time, or record /clock too"
        if scene.ros2
        else "a simulation: record it with /use_sim_time true (rosbag record then follows /clock), or record /clock too"
    ) + "; a driver stamping on its own clock (time since boot): stamp with the ROS time of the computer that records"


def _disagreeing_with_others(scene: Scene, edges: list[EdgeClock], main: list[EdgeClock]) -> Finding:
    kind = _kind(edges[0].offset_record - main[0].offset_record, edges[0].median_stamp, main[0].median_stamp)
    stamp = float(np.median([e.median_stamp for e in edges])) / NS_PER_S
    theirs = float(np.median([e.median_stamp for e in main])) / NS_PER_S
    said = (
        f"stamped around {stamp:.1f} s while {listed([e.child for e in main], 3)} are stamped around "
        f"{theirs:.1f} s: two clocks in one tree"
    )
    return _two_clocks(scene, kind, edges, said)


def _two_bases(scene: Scene, edges: list[EdgeClock], main: list[EdgeClock]) -> Finding:
    """``edges`` stamped on another time base than ``main`` (epoch time against time counted from zero) where the
    record times are no clock: what the stamps show, and nothing of which clock a publisher keeps."""

    def base(stamp: float) -> str:
        return "epoch time" if stamp * NS_PER_S >= EPOCH_FLOOR else "counting from zero"

    stamp = float(np.median([e.median_stamp for e in edges])) / NS_PER_S
    theirs = float(np.median([e.median_stamp for e in main])) / NS_PER_S
    said = (
        f"stamped around {stamp:.1f} s ({base(stamp)}) while {listed([e.child for e in main], 3)} are stamped "
        f"around {theirs:.1f} s ({base(theirs)}): two time bases, and no record clock to tell which clock each keeps"
    )
    return _two_clocks(scene, "bases", edges, said)


def _ignoring_clock(scene: Scene, on: Sequence[EdgeClock]) -> Finding:
    clock = scene.timeline.clock
    value = float(np.median(clock.clock)) / NS_PER_S
    return Finding(
        Severity.warning,
        "clock",
        f"{clock.topic} was recorded (around {value:.1f} s) but no frame follows it: tf is stamped on the record "
        f"clock ({listed([e.child for e in on], 3)})",
        "if a simulator publishes /clock, every node should run with use_sim_time true; a node on wall time "
        "cannot be combined with the simulator's sensor data",
        count=len(clock),
    )


def _wall_receive_times(scene: Scene) -> Iterator[Finding]:
    """tf follows /clock while the record clock does not: ``ros2 bag record`` without ``--use-sim-time``."""
    timeline = scene.timeline
    if all(abs(e.offset_record) <= timeline.same_clock for e in timeline.edges):
        return
    clock = timeline.clock
    sim = int(clock.clock[-1] - clock.clock[0])
    wall = int(clock.record_time[-1] - clock.record_time[0])
    speed = f", the simulation running at {sim / wall:.2f}x real time" if wall > 0 and sim > 0 else ""
    unavailable = timeline.delays_unavailable
    measured = f"{'ages are' if unavailable else 'ages and delays are'} measured against {clock.topic} at arrival"
    measured += f"; {unavailable}" if unavailable else ""
    yield Finding(
        Severity.info,
        "clock",
        f"received times are on another clock than tf and {clock.topic} (wall time: recorded without "
        f"{'--use-sim-time' if scene.ros2 else '/use_sim_time true'}){speed}: {measured}",
        "nothing to fix; "
        + (
            "ros2 bag record --use-sim-time records on simulated time"
            if scene.ros2
            else "rosbag record with /use_sim_time true records on simulated time"
        ),
        count=len(clock),
    )


@register("sim_clock", Severity.warning, "/clock going back, pausing, or starting after tf")
def sim_clock(scene: Scene) -> Iterator[Finding]:
    clock = scene.timeline.clock
    if len(clock) < 2:
        return
    # Its times are ROS time at arrival (``Scene.ros_times``), as every finding's: under /clock, its readings
    # then; the message says them on that clock.
    steps = np.diff(clock.clock)
    back = np.flatnonzero(steps < 0)
    if len(back):
        first = int(clock.record_time[back[0] + 1])
        first_time, last_time = scene.ros_times([first, int(clock.record_time[back[-1] + 1])])
        yield Finding(
            Severity.warning,
            "sim_clock",
            f"{clock.topic} went back {counted(len(back), 'time')}, by up to "
            f"{duration(-float(steps[back].min()) / NS_PER_S)}, first at {_when(scene, first)}",
            f"a looped replay ({'ros2 bag' if scene.ros2 else 'rosbag'} play --loop) or a reset simulation: listeners "
            "clear their tf buffers at each jump back, and lookups across it mix two timelines",
            first_time=first_time,
            last_time=last_time,
            count=len(back),
        )
    pauses = np.diff(clock.record_time)
    long = np.flatnonzero(pauses > CLOCK_PAUSE)
    # A pause over before any transform arrived is the simulator starting (a TurtleBot3 walker's Gazebo loading
    # its plugins: /clock 0.093 then 0.169 s, 1.02 s of record time apart, its first tf 33 ms later): no
    # lookup or timer waited on a clock nothing had been stamped on yet.
    long = long[clock.record_time[long + 1] > _first_tf_arrival(scene)]
    if len(long):
        i = int(long[np.argmax(pauses[long])])
        first_time, last_time = scene.ros_times([int(clock.record_time[long[0]]), int(clock.record_time[long[-1] + 1])])
        yield Finding(
            Severity.warning,
            "sim_clock",
            f"{clock.topic} paused {counted(len(long), 'time')} while the recording went on, the longest for "
            f"{duration(float(pauses[i]) / NS_PER_S)} (record clock) from {_when(scene, int(clock.record_time[i]))}",
            "ROS time stands still for every node with use_sim_time while /clock is silent (a paused or stalled "
            "simulator): timers and lookups at 'now' wait",
            first_time=first_time,
            last_time=last_time,
            count=len(long),
        )
    yield from _before_clock(scene)


def _first_tf_arrival(scene: Scene) -> int:
    """The record time of the first moving transform with a known one (0: none known)."""
    rows = scene.rows
    records = rows.record_time.whole()
    known = records[(records > 0) & ~rows.static]
    return int(known.min()) if len(known) else 0


def _when(scene: Scene, record_time: int) -> str:
    """When a /clock message arrived, saying the clock: ROS time where known, else the record clock's."""
    ros, known = scene.timeline.ros_time(np.array([record_time], np.int64))
    return f"{scene.at(int(ros[0]))} in ROS time" if known[0] else scene.at_arrival(record_time)


def _before_clock(scene: Scene) -> Iterator[Finding]:
    clock = scene.timeline.clock
    rows = scene.rows
    records = rows.record_time.whole()
    early = np.flatnonzero((records > 0) & (records < clock.record_time[0] - BEFORE_CLOCK) & ~rows.static)
    del records
    # Stamped on the simulation's time (a TurtleBot3 in Gazebo: 319.7 s, /clock first recorded 2.3 s later
    # at 320.9 s), they say the nodes had that time: the recorder only got /clock later. ROS time 0 is
    # what a node with use_sim_time stamps before any /clock.
    early = early[rows.stamp[early] < min(NO_TIME_YET, int(clock.clock[0]))]
    if scene.timeline.reference is not Reference.CLOCK or not len(early):
        return
    yield Finding(
        Severity.info,
        "sim_clock",
        f"{transforms(len(early))} arrived before the first {clock.topic} (up to "
        f"{duration((clock.record_time[0] - int(rows.record_time[early].min())) / NS_PER_S)} before), stamped "
        f"no later than {int(rows.stamp[early].max()) / NS_PER_S:.3f} s: nodes with use_sim_time had no time yet "
        "(ROS time 0)",
        f"start the simulator (or {'ros2 bag' if scene.ros2 else 'rosbag'} play --clock) before the nodes that stamp "
        "with its time",
        first_time=int(rows.stamp[early].min()),
        last_time=int(rows.stamp[early].max()),
        count=len(early),
    )


def _parent(scene: Scene, child: str) -> str:
    return scene.buffer.parent(child) or "?"


def _authorities(scene: Scene, children: Sequence[str]) -> tuple[str, ...]:
    frames = scene.tree.frames
    return tuple(dict.fromkeys(a for child in children if child in frames for a in frames[child].authorities))
