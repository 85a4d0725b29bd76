"""The MessageFilter replay against the real tf2 fed the same tf in record order, message by message."""

from __future__ import annotations

import json
import subprocess
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tests.oracle import ROS_PYTHON
from tftools.analysis.filter.fates import NEVER, Fate, message_fates
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.contents import StampedMessages

HARNESS = Path(__file__).parents[1] / "oracle" / "filter_harness.py"
MS = 1_000_000
START = 100 * NS_PER_S  # small times: tf2_py's doubles are exact to the nanosecond there
SECONDS = 20


def _t(parent: str, child: str, stamp: int, x: float) -> Transform:
    return Transform.from_rpy((x, 0.0, 0.1), (0.0, 0.0, 0.01 * x), stamp, parent, child)


def _periodic(
    hz: float, delay: int, make: Callable[[int], list[Transform]], seconds: float = SECONDS
) -> list[TfMessage]:
    times = START + np.round(np.arange(round(seconds * hz)) * NS_PER_S / hz).astype(np.int64)
    return [TfMessage("/tf", int(t) + delay, make(int(t)), "/node") for t in times]


def robot() -> list[TfMessage]:
    """odom -> base_link 50 Hz (2 ms late), base_link -> laser 20 Hz (30 ms late), map -> odom 10 Hz,
    static imu and camera, and a second tree world -> rig."""
    messages = [
        *_periodic(50, 2 * MS, lambda t: [_t("odom", "base_link", t, (t - START) / NS_PER_S)]),
        *_periodic(20, 30 * MS, lambda t: [_t("base_link", "laser", t, 0.2 + 0.001 * ((t - START) // MS % 7))]),
        *_periodic(10, 5 * MS, lambda t: [_t("map", "odom", t, 1.0 + (t - START) / NS_PER_S / 100)]),
        TfMessage(
            "/tf_static", START + MS, [_t("base_link", "imu", START, 0.05), _t("base_link", "camera", START, 0.1)]
        ),
        TfMessage("/tf_static", START + MS, [_t("world", "rig", START, 0.0)]),
    ]
    return sorted(messages, key=lambda m: m.record_time)


def sensors() -> StampedMessages:
    """A laser waiting for its tf, an IMU that is fine, a misspelt camera, clouds older than the cache,
    a frame in the other tree, and one message stamped after the recording ends."""
    rows: list[tuple[int, str, int]] = []  # (arrival, frame, stamp)
    for i in range(1, 390):
        stamp = START + i * 50 * MS + 7 * MS
        rows.append((stamp + 5 * MS, "laser", stamp))
        rows.append((stamp + 25 * MS, "imu", stamp))  # after the odometry around its stamp
    for i in range(1, 19):
        stamp = START + i * NS_PER_S
        rows.append((stamp + 3 * MS, "camra", stamp))
        rows.append((stamp + 3 * MS, "rig", stamp))
        rows.append((stamp + 11 * NS_PER_S, "base_link", stamp))  # arrives 11 s after its stamp
        rows.append((stamp + 3 * MS, "/base_link", stamp))  # a leading slash, as ROS 1 drivers send
    rows.append((START + 5 * NS_PER_S, "base_link", START + 40 * NS_PER_S))  # from the future
    rows.append((START + 5 * NS_PER_S, "odom", 0))  # stamp 0: the latest
    rows.sort()
    frames = sorted({f for _, f, _ in rows})
    return StampedMessages(
        "/sensors",
        "sensor_msgs/msg/Mixed",
        np.array([r for r, _, _ in rows], np.int64),
        np.array([s for _, _, s in rows], np.int64),
        np.array([frames.index(f) for _, f, _ in rows], np.int32),
        frames,
    )


def oracle(tf: list[TfMessage], messages: StampedMessages, target: str, cache_s: float) -> list[int | None]:
    rows = [
        [m.record_time, t.frame_id, t.child_frame_id, *divmod(t.stamp, NS_PER_S), *t.translation, *t.rotation,
         m.topic == "/tf_static"]
        for m in tf for t in m.transforms
    ]  # fmt: skip
    asked = [
        [int(r), messages.frame_ids[f], *divmod(int(s), NS_PER_S)]
        for r, f, s in zip(messages.record_time, messages.frame, messages.stamp, strict=True)
    ]
    request = {"cache_s": cache_s, "target": target, "tf": rows, "messages": asked}
    done = subprocess.run([ROS_PYTHON, str(HARNESS)], input=json.dumps(request), capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    ready: list[int | None] = json.loads(done.stdout)["ready"]
    return ready


@pytest.mark.parametrize("cache_s", [10.0, 0.5])
@pytest.mark.parametrize("target", ["odom", "map"])
def test_each_message_becomes_transformable_when_tf2_says_so(tf2_available: None, target: str, cache_s: float) -> None:
    tf, messages = robot(), sensors()
    fates = message_fates(recording(tf).buffer, messages, target, round(cache_s * NS_PER_S))
    expected = np.array([NEVER if r is None else r for r in oracle(tf, messages, target, cache_s)], np.int64)
    mismatched = np.flatnonzero(fates.ready != expected)
    assert not len(mismatched), [
        (messages.frame_ids[messages.frame[i]], int(messages.stamp[i]), int(fates.ready[i]), int(expected[i]))
        for i in mismatched[:5]
    ]
    assert ((fates.fate == Fate.ON_ARRIVAL) == (fates.ready == messages.record_time)).all()


def test_each_message_says_why_it_waited_or_was_lost() -> None:
    messages = sensors()
    fates = message_fates(recording(robot()).buffer, messages, "odom")

    def of(frame: str) -> np.ndarray:
        fate: np.ndarray = fates.fate[messages.frame == messages.frame_ids.index(frame)]
        return fate

    assert (of("laser") == Fate.LATER).all()  # a scan stamped 7 ms after a laser transform arrives 5 ms later:
    laser = np.flatnonzero(messages.frame == messages.frame_ids.index("laser"))  # it needs the next one (43 ms
    np.testing.assert_array_equal(fates.ready[laser] - messages.record_time[laser], 68 * MS)  # on, 30 ms late)
    assert {fates.edge[int(i)] for i in laser} == {("base_link", "laser")}
    assert (of("imu") == Fate.ON_ARRIVAL).all() and (of("/base_link") == Fate.ON_ARRIVAL).all()
    assert (of("camra") == Fate.UNKNOWN_FRAME).all() and (of("rig") == Fate.NOT_CONNECTED).all()
    base = of("base_link")  # stamped 1..18 s in, arriving 11 s later: the cache holds 10 s behind the newest tf
    assert (base == Fate.TOO_OLD_ON_ARRIVAL).sum() == 9 and (base == Fate.ON_ARRIVAL).sum() == 9  # (to 20 s)
    assert (base == Fate.NEEDS_NEWER_TF).sum() == 1  # stamped after the recording's tf ends
    assert (of("odom") == Fate.ON_ARRIVAL).all()  # stamp 0 (the latest) of the target itself


def test_the_default_target_is_odom_else_the_root_of_the_largest_tree() -> None:
    from tftools.analysis.frames import frame_tree
    from tftools.analysis.targets import default_target

    assert default_target(frame_tree(recording(robot()))) == ("odom", "REP 105's odom frame")
    trees = [
        TfMessage("/tf_static", START, [_t("world", "arm", START, 0.1), _t("arm", "hand", START, 0.1)]),
        TfMessage("/tf_static", START, [_t("rig", "camera", START, 0.1)]),
    ]
    assert default_target(frame_tree(recording(trees))) == ("world", "the root of the largest tree")


def test_a_message_recorded_at_its_tfs_instant_meets_it_in_the_order_the_recording_replays_them() -> None:
    """Issue 39 (Kobuki, use_sim_time): a message and the tf that makes it transformable share one record
    time. Where the reader says the message comes first (``tf_before``), it waits and passes at that instant,
    as the real filter does; where it comes after, it passes on arrival; unsaid, the tf counts as first."""
    from tftools.core.buffer import Buffer

    buffer = Buffer(cache_time=None)
    ticks = [START + i * 10 * MS for i in range(10)]
    for stamp in ticks:  # odom -> base_link recorded at its stamp: the i-th transform read is at ticks[i]
        buffer.set_transform(_t("odom", "base_link", stamp, 0.0), "/gazebo", record_time=stamp)
    times = np.array(ticks[2:], np.int64)

    def sensed(tf_before: list[int]) -> StampedMessages:
        frames = np.zeros(len(times), np.int32)
        return StampedMessages("/imu", "sensor_msgs/msg/Imu", times, times, frames, ["base_link"], np.array(tf_before))

    first = message_fates(buffer, sensed([i for i in range(2, 10)]), "odom")  # each before its instant's tf
    assert first.fate.tolist() == [Fate.LATER] * 8 and first.ready.tolist() == times.tolist()
    after = message_fates(buffer, sensed([i + 1 for i in range(2, 10)]), "odom")
    assert after.fate.tolist() == [Fate.ON_ARRIVAL] * 8
    unsaid = message_fates(buffer, sensed([]), "odom")
    assert unsaid.fate.tolist() == [Fate.ON_ARRIVAL] * 8
