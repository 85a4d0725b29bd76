"""A small healthy robot, and one recording per problem the checker knows, each showing exactly that problem."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tests.bags import BagFormat, ClockMessage, TfMessage, write_bag
from tftools.core.batch import BatchBuilder
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.bag.contents import BagContents, BagFileInfo
from tftools.sources.contents import DEFAULT_TOPICS, ClockSamples, StampedMessages, is_static_topic
from tftools.sources.recording import Recording, recording_of

START = 1_700_000_000 * NS_PER_S
SECONDS = 10.0
MS = 1_000_000
DELAY = 2 * MS  # how long after its stamp each healthy message is recorded

Make = Callable[[int], list[Transform]]


def _t(parent: str, child: str, stamp: int, x: float = 0.0, yaw: float = 0.0) -> Transform:
    return Transform.from_rpy((x, 0.0, 0.1), (0.0, 0.0, yaw), stamp, parent, child)


def _s(stamp: int) -> float:
    return (stamp - START) / NS_PER_S


def periodic(
    publisher: str,
    hz: float,
    make: Make,
    *,
    topic: str = "/tf",
    start: float = 0.0,
    end: float = SECONDS,
    phase: float = 0.0,
    delay: int = DELAY,
    stamp: Callable[[int], int] = lambda t: t,
    skip: tuple[float, float] | None = None,
) -> list[TfMessage]:
    """``make(stamp)`` every 1/``hz`` s over [start, end) after START (+ ``phase``), recorded
    ``delay`` after its true time; ``stamp`` maps the true time to the stamp sent."""
    messages = []
    for i in range(round((end - start) * hz)):
        seconds = start + phase + i / hz
        if skip and skip[0] <= seconds < skip[1]:
            continue
        t = START + round(seconds * NS_PER_S)
        messages.append(TfMessage(topic, t + delay, make(stamp(t)), publisher))
    return messages


def map_odom(stamp: int) -> list[Transform]:
    return [_t("map", "odom", stamp, 1.0 + 0.01 * _s(stamp), 0.002 * _s(stamp))]


def odom_base(stamp: int) -> list[Transform]:
    return [_t("odom", "base_link", stamp, 0.4 * _s(stamp), 0.1 * _s(stamp))]


def wheel(stamp: int) -> list[Transform]:
    return [
        Transform.from_rpy((0.0, 0.2, 0.0), (0.0, 4.0 * _s(stamp) % (2 * math.pi), 0.0), stamp, "base_link", "wheel")
    ]


def statics(record: int = START + DELAY, laser_x: float = 0.2) -> TfMessage:
    return TfMessage(
        "/tf_static", record, [_t("base_link", "laser", START, laser_x), _t("base_link", "camera", START, 0.1)], "/rsp"
    )


#: A recording long enough to be played from the middle, split or filtered (statics_early).
LONG = 70.0


def _odometry_reset(stamp: int) -> list[Transform]:
    """odom -> base_link starting again from zero 5 s in (2 m further along by then)."""
    s = _s(stamp) - (5.0 if _s(stamp) >= 5.0 else 0.0)
    return [_t("odom", "base_link", stamp, 0.4 * s, 0.1 * s)]


def amcl(**kw: object) -> list[TfMessage]:
    return periodic("/amcl", 10, map_odom, **kw)  # type: ignore[arg-type]  # periodic's keywords, passed on


def ekf(**kw: object) -> list[TfMessage]:
    return periodic("/ekf", 50, odom_base, **kw)  # type: ignore[arg-type]  # periodic's keywords, passed on


def wheels(**kw: object) -> list[TfMessage]:
    return periodic("/rsp", 20, wheel, **kw)  # type: ignore[arg-type]  # periodic's keywords, passed on


def healthy(**parts: list[TfMessage]) -> list[TfMessage]:
    """The robot: map -> odom (/amcl 10 Hz), odom -> base_link (/ekf 50 Hz), base_link -> wheel
    (/rsp 20 Hz), base_link -> laser, camera (/rsp, /tf_static); ``parts`` replace any of amcl, ekf,
    wheels, statics."""
    chosen = {"statics": [statics()], "amcl": amcl(), "ekf": ekf(), "wheels": wheels(), **parts}
    return sorted((m for group in chosen.values() for m in group), key=lambda m: m.record_time)


#: Simulated time at START: a simulation recorded on wall-clock receive times stamps around 100 s.
SIM_START = 100 * NS_PER_S


def sim(t: int) -> int:
    """The simulated time at wall time ``t`` (a simulator running at real time since START)."""
    return t - START + SIM_START


def simulated(**parts: list[TfMessage]) -> list[TfMessage]:
    """The robot in a simulator, every node on its time, recorded on wall-clock receive times (``ros2 bag
    record`` without ``--use-sim-time``); ``parts`` replace any of amcl, ekf, wheels, statics."""
    stamped = {"amcl": amcl(stamp=sim), "ekf": ekf(stamp=sim), "wheels": wheels(stamp=sim)}
    return healthy(**{**stamped, **parts})


def sim_clock(hz: float = 100.0, back: tuple[float, float] | None = None) -> ClockSamples:
    """The simulator's /clock as recorded on wall time: ``hz`` messages a second over the recording; with
    ``back=(at, by)``, from ``at`` seconds on it reads ``by`` seconds less (a reset)."""
    wall = START + np.round(np.arange(round(SECONDS * hz)) * NS_PER_S / hz).astype(np.int64)
    clock = wall - START + SIM_START
    if back is not None:
        clock[wall >= START + round(back[0] * NS_PER_S)] -= round(back[1] * NS_PER_S)
    return ClockSamples("/clock", wall + MS, clock)


def sensor(topic: str, frame: str, hz: float, delay: int, *, phase: float = 0.0, start: float = 0.0) -> StampedMessages:
    """A sensor stamped every 1/``hz`` s from ``start`` (+ ``phase``), arriving ``delay`` after its stamps."""
    seconds = start + phase + np.arange(round((SECONDS - start) * hz)) / hz
    stamps = START + np.round(seconds * NS_PER_S).astype(np.int64)
    return StampedMessages(
        topic, "sensor_msgs/msg/Any", stamps + delay, stamps, np.zeros(len(stamps), np.int32), [frame]
    )


def with_extra(*extra: list[TfMessage], **parts: list[TfMessage]) -> list[TfMessage]:
    messages = healthy(**parts)
    for group in extra:
        messages.extend(group)
    return sorted(messages, key=lambda m: m.record_time)


def _swap_pairs(messages: list[TfMessage], every: int) -> list[TfMessage]:
    """Every ``every``-th pair of messages sent in the wrong order (record times kept)."""
    out = list(messages)
    for i in range(every, len(out) - 1, every):
        a, b = out[i], out[i + 1]
        out[i] = TfMessage(a.topic, a.record_time, b.transforms, a.publisher)
        out[i + 1] = TfMessage(b.topic, b.record_time, a.transforms, b.publisher)
    return out


def _twice(messages: list[TfMessage]) -> list[TfMessage]:
    return [
        m
        for message in messages
        for m in (
            message,
            TfMessage(message.topic, message.record_time + MS // 2, message.transforms, message.publisher),
        )
    ]


def _second_estimate(stamp: int) -> list[Transform]:
    """A second odometry of the same motion, 5 cm off the first: two estimates taking turns."""
    return [_t("odom", "base_link", stamp, 0.4 * _s(stamp) + 0.05, 0.1 * _s(stamp))]


def _nan_and_zero_rotation(stamp: int) -> list[Transform]:
    s = _s(stamp)
    if 3.0 <= s < 3.2:
        return [Transform((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "odom", "base_link")]
    if 6.0 <= s < 6.1:
        return [Transform((0.4 * s, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), stamp, "odom", "base_link")]
    return odom_base(stamp)


@dataclass(frozen=True)
class Problem:
    """A recording showing one problem: the code it must raise, and what the finding must name."""

    code: str
    make: Callable[[], list[TfMessage]]
    frames: tuple[str, ...]  # frames the finding must name
    publisher: str | None = None  # the ROS1 publisher it must name
    severity: str = "error"
    topics: tuple[str, ...] | None = None
    words: tuple[str, ...] = ()  # words the message (or hint) must hold
    clock: Callable[[], ClockSamples] | None = None  # the recorded /clock, if any
    ros1_only: bool = False  # a problem under ROS 1's tf2 only (ROS 2 bags answer as ROS 2's)
    ros2_code: str | None = None  # what a ROS 2 bag (no publishers named) shows instead, if anything
    streams: Callable[[], list[StampedMessages]] | None = None  # sensor data, for the checks of data against tf


PROBLEMS = {
    "cycle": Problem(
        "cycle",
        lambda: with_extra(periodic("/rogue", 10, lambda t: [_t("base_link", "map", t, _s(t))], phase=0.05)),
        ("map", "odom", "base_link"),
        "/rogue",
        words=("loop",),
    ),
    "disconnected": Problem(
        "disconnected",
        lambda: with_extra(
            [TfMessage("/tf_static", START + 3 * MS, [_t("world", "rig", START)], "/rig_rsp")],
            periodic("/rig", 10, lambda t: [_t("rig", "cam", t, _s(t))]),
        ),
        ("map", "world"),
        words=("2 separate trees", "rig", "cam"),
    ),
    "multiple_parents": Problem(
        "multiple_parents",
        lambda: with_extra(periodic("/rogue", 10, lambda t: [_t("map", "base_link", t, _s(t))], start=5.0, phase=0.01)),
        ("base_link", "odom", "map"),
        "/rogue",
    ),
    "multiple_authorities": Problem(
        "multiple_authorities",
        lambda: with_extra(periodic("/ekf2", 50, odom_base, phase=0.01, topic="/tf_alt")),
        ("odom", "base_link"),
        "/ekf2",
        severity="warning",
        topics=("/tf", "/tf_alt", "/tf_static"),
    ),
    "multiple_authorities_one_topic": Problem(
        "multiple_authorities",
        lambda: with_extra(periodic("/ekf2", 50, _second_estimate, phase=0.003)),  # taking turns: 3 ms, 17 ms...
        ("odom", "base_link"),
        "/ekf2",
        severity="warning",
    ),
    "stale": Problem("stale", lambda: healthy(ekf=ekf(end=4.0)), ("odom", "base_link"), "/ekf", words=("stopped",)),
    "clock": Problem(
        "clock",
        lambda: healthy(ekf=ekf(stamp=lambda t: t - START + 1234 * NS_PER_S)),
        ("odom", "base_link"),
        "/ekf",
        words=("time since boot", "no /clock was recorded"),
    ),
    "clock_replay": Problem(
        "clock",
        lambda: healthy(
            amcl=amcl(stamp=lambda t: t - 3 * 86400 * NS_PER_S), ekf=ekf(stamp=lambda t: t - 3 * 86400 * NS_PER_S)
        ),
        ("map", "odom", "base_link"),
        "/ekf",
        words=("3.0 days", "--clock"),
    ),
    "clock_wall_among_sim": Problem(
        "clock",
        lambda: simulated(ekf=ekf()),
        ("odom", "base_link"),
        "/ekf",
        words=("wall-clock", "/clock", "use_sim_time"),
        clock=sim_clock,
    ),
    "clock_two_clocks": Problem(
        "clock",
        lambda: simulated(ekf=ekf(stamp=lambda t: sim(t) + 500 * NS_PER_S)),
        ("odom", "base_link"),
        "/ekf",
        words=("two clocks",),
    ),
    "sim_clock": Problem(
        "sim_clock",
        simulated,
        (),
        severity="warning",
        words=("/clock went back 1 time", "0.490 s"),
        clock=lambda: sim_clock(back=(6.0, 0.5)),
    ),
    "sensor_frame": Problem(
        "sensor_frame",
        healthy,
        ("camra",),
        words=("'camra'", "did you mean 'camera'?", "frame_id"),
        streams=lambda: [sensor("/camera/image_raw", "camra", 10, 5 * MS)],
    ),
    "sensor_wait": Problem(
        "sensor_wait",
        lambda: with_extra(periodic("/tilt", 2, lambda t: [_t("base_link", "tilt_laser", t, yaw=_s(t))], phase=0.01)),
        ("base_link", "tilt_laser"),
        severity="warning",
        words=("/scan", "waiting", "MessageFilter"),  # a tilting laser's tf comes twice a second, its scans 20 times
        streams=lambda: [sensor("/scan", "tilt_laser", 20, 5 * MS, phase=0.007)],
    ),
    "sensor_lost": Problem(
        "sensor_lost",
        lambda: healthy(amcl=amcl(end=30.0), ekf=ekf(end=30.0), wheels=wheels(end=30.0)),
        (),
        severity="warning",
        words=("/points", "older than the 10 s cache", "a cache of 15 s"),
        streams=lambda: [sensor("/points", "laser", 2, 12 * NS_PER_S, start=0.5)],  # stamped 12 s before arrival
    ),
    "future": Problem(
        "future",
        lambda: healthy(amcl=amcl(stamp=lambda t: t + 3 * NS_PER_S)),
        ("map", "odom"),
        "/amcl",
        words=("3.0 s",),
    ),
    "delay": Problem(
        "delay", lambda: healthy(ekf=ekf(delay=500 * MS)), ("odom", "base_link"), "/ekf", "warning", words=("late",)
    ),
    "rate": Problem(
        "rate", lambda: healthy(amcl=amcl(skip=(3.0, 6.0))), ("map", "odom"), "/amcl", "warning", words=("silent",)
    ),
    "stall": Problem(
        "stall",
        lambda: healthy(
            amcl=amcl(skip=(3.0, 5.0)), ekf=ekf(skip=(3.2, 5.0)), wheels=wheels(skip=(3.4, 5.0)), statics=[statics()]
        ),
        ("map", "odom", "base_link", "wheel"),
        severity="warning",
        words=(
            "all 3 moving edges went silent within 0.450 s of each other, from 1700000002.900 (+2.9 s), for 1.6 s to "
            "2.1 s",
            "the recorder received no transform on /tf for 1.6 s: everything on /tf stopped at once",
        ),
    ),
    "invalid_values": Problem(
        "invalid_values",
        lambda: healthy(ekf=periodic("/ekf", 50, _nan_and_zero_rotation)),
        ("odom", "base_link"),
        "/ekf",
        words=("NaN in 10", "length 0 in 5", "w=1"),
    ),
    "self_transform": Problem(
        "self_transform",
        lambda: with_extra(periodic("/rogue", 5, lambda t: [_t("base_link", "base_link", t)])),
        ("base_link",),
        "/rogue",
    ),
    "empty_frame_id": Problem(
        "empty_frame_id",
        lambda: with_extra(periodic("/rogue", 5, lambda t: [_t("", "sonar", t)])),
        ("sonar",),
        "/rogue",
    ),
    "leading_slash": Problem(
        "leading_slash",
        lambda: healthy(ekf=periodic("/ekf", 50, lambda t: [_t("/odom", "/base_link", t, 0.4 * _s(t))])),
        ("odom", "base_link"),
        "/ekf",
        "warning",
        words=("/odom", "/base_link"),
    ),
    "time_backwards": Problem(
        "time_backwards",
        lambda: healthy(ekf=_swap_pairs(ekf(), 25)),
        ("odom", "base_link"),
        "/ekf",
        "warning",
        words=("arrived out of order",),
    ),
    "time_jump": Problem(
        "time_backwards",
        lambda: healthy(ekf=ekf(stamp=lambda t: t - 3 * NS_PER_S if t >= START + 5 * NS_PER_S else t)),
        ("odom", "base_link"),
        "/ekf",
        words=("went back 1 time, by up to 3.0 s", "time jumped back"),
    ),
    "time_repeated": Problem(
        "time_backwards",
        lambda: healthy(ekf=_twice(ekf())),
        ("odom", "base_link"),
        "/ekf",
        "warning",  # ROS 1's tf2 logs each at WARN level and answers every lookup as before
        words=("TF_REPEATED_DATA", "nothing is lost"),
        ros1_only=True,  # ROS 2's tf2 takes an identical sample again silently,
        ros2_code="multiple_authorities",  # and a ROS 2 bag, naming no publisher, shows two identical ones
    ),
    "static_on_dynamic": Problem(
        "static_on_dynamic",
        lambda: with_extra(periodic("/sonar_tf", 10, lambda t: [_t("base_link", "sonar", t, 0.3)], phase=0.013)),
        ("base_link", "sonar"),
        "/sonar_tf",
        "warning",
        words=("/tf_static",),
    ),
    "dynamic_on_static": Problem(
        "dynamic_on_static",
        lambda: with_extra([statics(START + 5 * NS_PER_S, laser_x=0.35)]),
        ("base_link", "laser"),
        "/rsp",
        words=("2 different values",),
    ),
    "static_conflict": Problem(
        "static_conflict",
        lambda: with_extra([TfMessage("/tf_static", START + 5 * NS_PER_S, statics(laser_x=0.35).transforms, "/rsp2")]),
        ("base_link", "laser"),
        "/rsp2",
        words=("150.0 mm", "agree on 1 other", "publish each frame from one of them"),
        ros1_only=True,  # two publishers apart: a ROS 2 bag shows one topic whose static changed
        ros2_code="dynamic_on_static",
    ),
    "mixed_static": Problem(
        "mixed_static",
        lambda: with_extra(periodic("/laser_driver", 10, lambda t: [_t("base_link", "laser", t, 0.2 + 0.01 * _s(t))])),
        ("laser",),
        "/laser_driver",
    ),
    "statics_early": Problem(
        "statics_early",
        lambda: healthy(amcl=amcl(end=LONG), ekf=ekf(end=LONG), wheels=wheels(end=LONG)),
        ("base_link", "laser", "camera"),
        "/rsp",
        "info",
        words=("only at the start", "tfx static --repair"),
    ),
    "jump": Problem(
        "jump",
        lambda: healthy(ekf=periodic("/ekf", 50, _odometry_reset)),
        ("odom", "base_link"),
        "/ekf",
        "warning",  # lookups through it work: a jump is never an error (issue 39)
        words=("REP 105", "1.992 m", "28.5° in 0.020 s"),
    ),
    "map_corrections": Problem(
        "map_corrections",
        lambda: healthy(amcl=periodic("/amcl", 10, lambda t: [_t("map", "odom", t, 1.0 + 0.2 * (_s(t) // 2))])),
        ("map", "odom"),
        "/amcl",
        "info",
        words=("corrected 4 times", "0.200 m"),
    ),
    "rep105": Problem(
        "rep105",
        lambda: healthy(
            ekf=periodic("/localizer", 50, lambda t: [_t("map", "base_link", t, 0.4 * _s(t), 0.1 * _s(t))])
        ),
        ("odom", "base_link"),
        severity="warning",
        words=("map -> base_link",),
    ),
    "no_tf": Problem(
        "no_tf",
        lambda: [
            TfMessage("/robot/odom_tf", START + i * 100 * MS, odom_base(START + i * 100 * MS), "/ekf")
            for i in range(20)
        ],
        (),
        words=("/robot/odom_tf",),
    ),
}


#: Every bag format tftools writes and reads.
FORMATS = list(BagFormat)


def write(
    directory: Path, name: str, fmt: BagFormat, messages: list[TfMessage], clock: ClockSamples | None = None
) -> Path:
    """The messages (and a /clock) as a bag of ``fmt`` in ``directory``."""
    ticks = [ClockMessage(int(r), int(c)) for r, c in zip(clock.record_time, clock.clock, strict=True)] if clock else []
    path = directory / (f"{name}.bag" if fmt is BagFormat.ros1 else f"{name}_{fmt.value}")
    return write_bag(path, messages, fmt, ticks)


def recording(
    messages: list[TfMessage],
    topics: tuple[str, ...] | None = None,
    ros1: bool = True,
    clock: ClockSamples | None = None,
) -> Recording:
    """The messages as a recording without a file: a ROS1 bag's (publishers named) or a ROS2 bag's
    (the topic stands in for the publisher), with a recorded /clock if given."""
    chosen = topics or DEFAULT_TOPICS
    builder = BatchBuilder()
    for m in messages:
        if m.topic not in chosen:
            continue
        for t in m.transforms:
            builder.add(
                t.frame_id, t.child_frame_id, t.stamp, t.translation, t.rotation,
                static=is_static_topic(m.topic), record_time=m.record_time, authority=m.publisher if ros1 else m.topic,
            )  # fmt: skip
    batch = builder.take()
    times = [m.record_time for m in messages]
    info = BagFileInfo(
        "memory.bag" if ros1 else "memory_db3",
        "ros1" if ros1 else "rosbag2-sqlite3",
        min(times, default=0),
        max(times, default=0),
        len(messages),
        {m.topic: "tf2_msgs/msg/TFMessage" for m in messages},
        len(batch),
    )
    contents = BagContents([batch] if len(batch) else [], [info], chosen, clock or ClockSamples.empty())
    return recording_of(contents)
