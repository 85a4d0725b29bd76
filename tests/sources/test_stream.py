"""A streamed recording: read window by window, it replays the same rows, on the same clock, with the
same timeline as the recording read whole, while holding one window at a time."""

from __future__ import annotations

import dataclasses
import weakref
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.bags import BagFormat, ClockMessage, TfMessage, write_bag
from tests.sources.bag.reading import read_contents
from tftools.analysis.edges import chain_moving_edges
from tftools.core.batch import BatchBuilder, TransformBatch, concat_batches
from tftools.core.buffer import Buffer
from tftools.core.semantics import Semantics
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources import read_recording
from tftools.sources.bag.contents import RecordWindow
from tftools.sources.contents import RecordingContents
from tftools.sources.errors import BagNotFoundError, NoTransformsError
from tftools.sources.replay import Replay, follow
from tftools.sources.stream import (
    CARRIED,
    MAX_WINDOWS,
    SAMPLES_PER_FRAME,
    _Arrivals,
    _halves,
    _recent,
    _Summary,
    _windows,
    stream_recording,
)
from tftools.sources.timeline import Playback, Reference, Timeline

SAMPLES = Path(__file__).resolve().parents[2] / "sample_bags"
WALL = 1_700_000_000 * NS_PER_S  # the record clock of a simulation recorded without --use-sim-time
SIM = 50 * NS_PER_S  # its simulated time when recording began


def _transform(parent: str, child: str, stamp: int, x: float) -> Transform:
    return Transform.from_rpy((x, 0.0, 0.0), (0.0, 0.0, 0.0), stamp, parent, child)


def simulation(path: Path, fmt: BagFormat, seconds: int = 20) -> Path:
    """A simulation recorded with /clock: tf stamped on sim time, received on wall time, a laser
    stamped 0.3 s late, statics latched once at the start."""
    messages = [TfMessage("/tf_static", WALL, [_transform("base_link", "laser", SIM, 0.2)])]
    clock = []
    for tick in range(seconds * 50):
        record, sim = WALL + tick * NS_PER_S // 50 + 1000, SIM + tick * NS_PER_S // 50
        odom = _transform("odom", "base_link", sim, tick / 50)
        messages.append(TfMessage("/tf", record, [odom, _transform("map", "odom", sim, 1.0)]))
        if tick % 5 == 0:
            messages.append(TfMessage("/tf", record + 7, [_transform("base_link", "arm", sim - 3 * SIM // 500, 0.1)]))
    for tick in range(seconds * 100):
        clock.append(ClockMessage(WALL + tick * NS_PER_S // 100, SIM + tick * NS_PER_S // 100))
    return write_bag(path, messages, fmt, clock)


def whole_replay_rows(paths: list[Path]) -> TransformBatch:
    """The rows a replay of the recording read whole delivers: every transform, moved onto the stamps' clock."""
    recording = read_recording(paths)
    transforms = recording.transforms
    return dataclasses.replace(transforms, record_time=Playback(recording.timeline).moved(transforms.record_time))


def assert_same_rows(streamed: TransformBatch, whole: TransformBatch) -> None:
    assert streamed.record_time.tolist() == whole.record_time.tolist()
    assert streamed.stamp.tolist() == whole.stamp.tolist()
    assert [streamed.frame_names[i] for i in streamed.child] == [whole.frame_names[i] for i in whole.child]
    assert [streamed.frame_names[i] for i in streamed.parent] == [whole.frame_names[i] for i in whole.parent]
    np.testing.assert_array_equal(streamed.translation, whole.translation)
    np.testing.assert_array_equal(streamed.rotation, whole.rotation)
    assert streamed.static.tolist() == whole.static.tolist()


def assert_same_timeline(streamed: Timeline, whole: Timeline) -> None:
    assert (streamed.reference, streamed.tf_start, streamed.tf_end) == (whole.reference, whole.tf_start, whole.tf_end)
    assert sorted(streamed.edges, key=lambda e: e.child) == sorted(whole.edges, key=lambda e: e.child)
    assert streamed.off_reference == whole.off_reference
    assert streamed.reason == whole.reason


RECORDINGS = [
    pytest.param([SAMPLES / "robot.bag"], id="sample-ros1"),
    pytest.param([SAMPLES / "robot_db3"], id="sample-db3"),
    pytest.param([SAMPLES / "robot_mcap"], id="sample-mcap"),
]


@pytest.mark.parametrize("paths", RECORDINGS)
def test_a_streamed_sample_bag_replays_the_rows_of_the_whole(paths: list[Path]) -> None:
    streamed = stream_recording(paths, window_messages=100)
    parts = list(streamed.parts())
    assert len(streamed.windows) > 10 and len(parts) > 10
    rows = concat_batches(parts)
    assert_same_rows(rows, whole_replay_rows(paths))
    whole = read_recording(paths)
    assert_same_timeline(streamed.timeline, whole.timeline.played())
    assert sorted(streamed.frames) == sorted(whole.buffer.frames)
    assert streamed.parents == whole_parents(whole.buffer)
    assert streamed.semantics == whole.buffer.semantics
    # each part is about one window's: no part holds much more than its share
    assert max(len(p) for p in parts) <= 4 * len(rows) / len(streamed.windows)


@pytest.mark.parametrize("paths", RECORDINGS)
def test_a_streams_moving_chain_is_the_whole_reads_for_every_pair_of_frames(paths: list[Path]) -> None:
    """``moving_chain`` walks the tree as last seen through the buffer's one walk: for every pair of frames
    the same dynamic edges as ``chain_moving_edges`` on the recording read whole."""
    with stream_recording(paths, window_messages=100) as streamed:
        whole = read_recording(paths).buffer
        frames = sorted(whole.frames)
        for target in frames:
            for source in frames:
                expected = set(chain_moving_edges(whole, target, source))
                assert set(streamed.moving_chain(target, source)) == expected, (target, source)
        assert streamed.moving_chain("base_link", "no_such_frame") == []


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_a_simulation_streams_onto_its_clock(tmp_path: Path, fmt: BagFormat) -> None:
    """Stamps on /clock, record times on wall time: the streamed replay moves each window's rows onto
    /clock exactly as the whole recording's replay does, across window edges."""
    bag = simulation(tmp_path / "sim", fmt)
    streamed = stream_recording([bag], window_messages=300)
    whole = read_recording([bag]).timeline
    assert whole.reference is Reference.CLOCK
    assert_same_timeline(streamed.timeline, whole.played())
    assert_same_rows(concat_batches(list(streamed.parts())), whole_replay_rows([bag]))
    assert streamed.timeline.tf_start == SIM - 3 * SIM // 500


def test_a_replay_of_parts_delivers_what_a_replay_of_the_whole_does(tmp_path: Path) -> None:
    bag = simulation(tmp_path / "sim.bag", BagFormat.ros1)
    streamed = stream_recording([bag], window_messages=300)
    start, end = SIM + 3 * NS_PER_S, SIM + 9 * NS_PER_S

    def played(replay: Replay) -> tuple[list[int], list[int]]:
        """The rows delivered, and the clock after each step of bag time."""
        times: list[int] = []
        clock: list[int] = []
        replay.attach(lambda batch: times.extend(batch.record_time.tolist()))
        for now in range(start, end + NS_PER_S, NS_PER_S // 7):
            replay.advance_to(now)
            clock.append(replay.clock.now())
        assert replay.finished and replay.clock.now() == end
        return times, clock

    whole = played(Replay(whole_replay_rows([bag]), start=start, end=end))
    assert played(streamed.replay(start=start, end=end)) == whole
    assert whole[0][0] < start  # the statics recorded before the start come first


def resending(path: Path, fmt: BagFormat, seconds: int = 6) -> Path:
    """One publisher re-sending, as Webots' diff-drive controller and slam_toolbox do: every stamp of odom
    -> base_link arrives twice, 20 ms apart (ROS 1: the copy's values differ, a repeated stamp; ROS 2:
    identical), and map -> odom is re-sent with one frozen stamp on every 20 ms loop."""
    ros1 = fmt is BagFormat.ros1
    messages = []
    for tick in range(seconds * 25):
        stamp, record = SIM + tick * 40_000_000, WALL + tick * 40_000_000
        for again in (0, 1):
            copy = 0.001 * again if ros1 else 0.0
            sent = [_transform("odom", "base_link", stamp, tick / 25 + copy), _transform("map", "odom", SIM, 1.0)]
            messages.append(TfMessage("/tf", record + again * 20_000_000, sent))
    return write_bag(path, messages, fmt)


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_a_sample_sent_again_in_a_later_window_is_stored_once(tmp_path: Path, fmt: BagFormat) -> None:
    """Issue 39 (e-puck, Kobuki): a re-sent sample is stored once, as tf2 stores it, whichever window each
    copy falls in (windows of 7 messages: most pairs straddle two), not counted as a second arrival."""
    bag = resending(tmp_path / "resent", fmt)
    streamed = stream_recording([bag], window_messages=7)
    assert len(streamed.windows) > 30
    arrivals = {e.child: e.arrivals for e in streamed.timeline.edges}
    assert arrivals == {"base_link": 6 * 25, "odom": 1}  # one per distinct stamp, as written
    assert_same_timeline(streamed.timeline, read_recording([bag]).timeline.played())
    assert_same_rows(concat_batches(list(streamed.parts())), whole_replay_rows([bag]))  # every copy is replayed


def test_re_sends_beside_a_publisher_hours_ahead_are_stored_once_across_windows(tmp_path: Path) -> None:
    """A real SAIL vehicle (corpus ros1-sail-zed-ekf-gps-two-odometries-2022-bag): a ZED re-sends each stamp of
    odom -> base_link while robot_localization's EKF sends the same edge from a machine 5.8 h ahead. What was
    carried to the next window was the last 10 s behind the edge's newest stamp, the EKF's: none of the ZED's,
    so its re-sends in a later window were stored again (5,447 samples where the whole read holds 5,429)."""
    ahead = 5 * 3600 * NS_PER_S
    messages = []
    for tick in range(5 * 25):
        stamp = WALL + tick * 40_000_000
        for again in (0, 1):  # the camera sends each stamp twice, 10 ms apart, the same value
            messages.append(
                TfMessage(
                    "/tf",
                    stamp + (1 + 10 * again) * 1_000_000,
                    [_transform("odom", "base_link", stamp, 1.0)],
                    "/camera",
                )
            )
        if tick % 2 == 0:
            sent = [_transform("odom", "base_link", stamp + ahead, tick / 25)]
            messages.append(TfMessage("/tf", stamp + 5_000_000, sent, "/ekf"))
    bag = write_bag(tmp_path / "two_clocks", messages, BagFormat.ros1)
    streamed = stream_recording([bag], window_messages=7)
    assert {e.child: e.arrivals for e in streamed.timeline.edges} == {"base_link": 125 + 63}  # distinct stamps
    assert_same_timeline(streamed.timeline, read_recording([bag]).timeline.played())


def test_only_the_last_seconds_of_each_edge_are_carried_to_the_next_window() -> None:
    """What the first pass carries from a window to the next is bounded by time, not by the recording: a
    moving edge's last seconds, a static cache's first sample and latest, however many it was sent."""
    buffer = Buffer(cache_time=None, semantics="ros1")
    buffer.set_transform(_transform("base_link", "laser", SIM, 0.2), static=True)
    for tick in range(60 * 50):  # a minute at 50 Hz, the laser's static cache given a value on /tf each time
        buffer.set_transform(_transform("odom", "base_link", SIM + tick * NS_PER_S // 50, tick / 50))
        buffer.set_transform(_transform("base_link", "laser", SIM + tick * NS_PER_S // 50, 0.3))
    carried = _recent(buffer, CARRIED)
    laser = carried.child == carried.frame_names.index("laser")
    assert carried.static[laser].tolist() == [True, False]  # the latched sample, then the /tf one it holds now
    assert carried.stamp[laser].tolist() == [SIM, SIM + (60 * 50 - 1) * NS_PER_S // 50]
    odom = carried.stamp[~laser]
    assert len(odom) == CARRIED // (NS_PER_S // 50) + 1
    history = buffer.history("base_link")
    assert history is not None
    assert odom.tolist() == history.stamps[-len(odom) :].tolist()


def latched_then_on_tf(path: Path, fmt: BagFormat) -> Path:
    """base_link -> laser latched once on /tf_static, then sent on /tf at 20 Hz (tf1's static_transform_publisher
    beside a robot_state_publisher, as on a CompRobo Neato) under an odometry at 20 Hz: the latched message lies
    in the first window only."""
    messages = [TfMessage("/tf_static", WALL, [_transform("base_link", "laser", WALL - 100 * NS_PER_S, 0.2)])]
    for tick in range(1, 200):
        stamp = WALL + tick * NS_PER_S // 20
        sent = [_transform("odom", "base_link", stamp, tick / 20), _transform("base_link", "laser", stamp, 0.3)]
        messages.append(TfMessage("/tf", stamp + 1000, sent))
    return write_bag(path, messages, fmt)


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_a_frames_cache_kind_is_carried_across_windows(tmp_path: Path, fmt: BagFormat) -> None:
    """Issue 39 (ros1-neato-urdf-beside-driver-2018-bag): past the window of the one latched /tf_static message,
    a streamed read took the laser for a moving edge while the whole read kept it in the static cache ROS 1's tf2
    made from its first sample (ROS 2's tf2 makes a new, moving cache on the first /tf sample: moving in both)."""
    bag = latched_then_on_tf(tmp_path / "latched", fmt)
    streamed = stream_recording([bag], window_messages=10)
    assert len(streamed.windows) > 10
    whole = read_recording([bag])
    static = fmt is BagFormat.ros1
    assert (
        streamed.parents
        == whole_parents(whole.buffer)
        == {
            "base_link": ("odom", False),
            "laser": ("base_link", static),
        }
    )
    assert_same_timeline(streamed.timeline, whole.timeline.played())
    assert sorted(e.child for e in streamed.timeline.edges) == (["base_link"] if static else ["base_link", "laser"])
    assert set(streamed.moving_chain("odom", "laser")) == set(chain_moving_edges(whole.buffer, "odom", "laser"))


def whole_parents(buffer: Buffer) -> dict[str, tuple[str, bool]]:
    """Each child's latest parent in a whole read's buffer, and whether its cache is static."""
    return {child: (buffer.frame_name(h.latest_parent), h.static) for child, h in buffer.histories() if len(h)}


def test_a_bag_without_transforms_is_refused(tmp_path: Path) -> None:
    bag = write_bag(tmp_path / "clock.bag", [], BagFormat.ros1, [ClockMessage(WALL, SIM)])
    with pytest.raises(NoTransformsError), stream_recording([bag]):
        pass


def test_a_bag_read_whole_is_streamed_as_one_window(tmp_path: Path) -> None:
    """A ROS1 bag cut before its index was written cannot be read by window: one window, the whole."""
    bag = simulation(tmp_path / "sim.bag", BagFormat.ros1)
    cut = tmp_path / "cut.bag"
    data = bag.read_bytes()
    cut.write_bytes(data[: int(len(data) * 0.9)])
    streamed = stream_recording([cut], window_messages=300)
    assert streamed.windows == (None,)
    assert_same_rows(concat_batches(list(streamed.parts())), whole_replay_rows([cut]))
    assert streamed.problems == read_recording([cut]).problems


def test_arrivals_keep_an_even_sample_of_a_long_recording() -> None:
    rng = np.random.default_rng(1)
    total = 20 * SAMPLES_PER_FRAME + 123
    values = np.arange(total, dtype=np.int64)
    arrivals = _Arrivals()
    at = 0
    while at < total:
        n = int(rng.integers(1, 5000))
        part = values[at : at + n]
        arrivals.add(part, part, part, np.ones(len(part), bool))
        at += n
    kept, *_ = arrivals.kept()
    stride = int(kept[1] - kept[0])
    assert SAMPLES_PER_FRAME // 2 < len(kept) <= SAMPLES_PER_FRAME
    assert kept.tolist() == list(range(0, total, stride))  # every stride-th arrival, from the first
    assert abs(np.median(kept) - np.median(values)) <= stride


def test_arrivals_span_every_stamp_not_only_those_kept() -> None:
    """A 22-minute real recording's odometry (ros2-turtlebot3-real-wifi-outage-2025-db3): its last two stamps
    fell between the kept ones, so --play's timeline ended that frame 0.1 s before the whole read's."""
    total = 4 * SAMPLES_PER_FRAME + 3
    stamps = np.arange(total, dtype=np.int64) * (NS_PER_S // 20)
    arrivals = _Arrivals()
    for part in np.array_split(stamps, 7):
        arrivals.add(part, part, part, np.ones(len(part), bool))
    kept, *_ = arrivals.kept()
    assert kept[-1] < stamps[-1]  # the last stamp is not among those kept
    assert arrivals.span == (0, int(stamps[-1]))


def test_a_long_stream_counts_every_arrival_not_only_those_kept() -> None:
    """Past ``SAMPLES_PER_FRAME`` arrivals a frame's clock is read off every second one, fourth one...;
    its count of arrivals (said in the clock findings) is still every one, as a whole read counts."""
    summary = _Summary("ros1", [], {})
    for window in range(3):
        rows = [_transform("odom", "base_link", SIM + (window * 4000 + i) * NS_PER_S // 50, 0.0) for i in range(4000)]
        stamps = np.array([r.stamp for r in rows], np.int64)
        builder = BatchBuilder()
        for r, record in zip(rows, stamps + WALL - SIM, strict=True):
            builder.add(r.frame_id, r.child_frame_id, r.stamp, r.translation, r.rotation, record_time=int(record))
        summary.add(RecordingContents([builder.take()], [], ("/tf",)))
    (edge,) = summary.edges()
    assert edge.arrivals == 12_000 > SAMPLES_PER_FRAME


def test_a_window_that_cannot_be_read_ends_the_replay_with_its_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A window that cannot be read after the first pass: the replay thread stops, and ``follow`` raises why."""
    bag = simulation(tmp_path / "sim.bag", BagFormat.ros1)
    streamed = stream_recording([bag], window_messages=300)

    def unreadable(*_: object) -> None:
        raise BagNotFoundError(str(bag))

    monkeypatch.setattr(streamed.reader, "read", unreadable)
    with pytest.raises(BagNotFoundError):
        follow(streamed.replay(rate=1e6), lambda _batch: None, lambda: None, period=0.01, duration=5)


def test_the_stream_reads_through_the_files_it_opened(tmp_path: Path) -> None:
    """The recording is opened once: a file removed after the first pass is still replayed whole
    (its reader holds it open), and closing the stream lets it go."""
    bag = simulation(tmp_path / "sim.bag", BagFormat.ros1)
    whole = len(read_contents([bag]).transforms)
    with stream_recording([bag], window_messages=300) as streamed:
        bag.unlink()
        assert len(streamed.windows) > 3
        assert sum(len(part) for part in streamed.parts()) == whole


def test_the_stream_closes_its_files_on_leaving_the_block_an_error_included(tmp_path: Path) -> None:
    """``with stream_recording(...) as streamed``: the files are let go on leaving the block, whether it
    ended or raised; a replay of a closed stream is told so."""
    bag = simulation(tmp_path / "sim.bag", BagFormat.ros1)
    with stream_recording([bag], window_messages=300) as streamed:
        assert streamed.reader.read(RecordWindow(0, 0)).files
    with pytest.raises(ValueError, match="not open"):
        next(streamed.parts())
    with pytest.raises(KeyError), stream_recording([bag], window_messages=300) as failed:
        raise KeyError("the caller's own error")
    with pytest.raises(ValueError, match="not open"):
        next(failed.parts())


def test_an_index_counting_too_many_messages_makes_at_most_max_windows() -> None:
    described = read_contents([SAMPLES / "robot.bag"], window=RecordWindow(0, 0)).files
    lying = [dataclasses.replace(f, message_count=2**62, end=2**63 - 1) for f in described]
    windows = _windows(lying, 4)
    assert len(windows) == MAX_WINDOWS
    firsts = [w.first for w in windows if w is not None]
    assert firsts == sorted(firsts) and all(w is not None and w.first <= w.last for w in windows)


@pytest.mark.parametrize(("paths", "chosen", "expected"), [
    ([SAMPLES / "robot.bag"], None, "ros1"),
    ([SAMPLES / "robot_mcap"], None, "ros2"),
    ([SAMPLES / "robot.bag"], "ros2", "ros2"),
])  # fmt: skip
def test_a_stream_answers_as_the_tf2_asked_for(paths: list[Path], chosen: Semantics | None, expected: str) -> None:
    with stream_recording(paths, semantics=chosen) as streamed:
        assert streamed.semantics == expected


@pytest.mark.parametrize("fmt", list(BagFormat))
def test_the_indexes_are_read_once_for_every_window(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: BagFormat
) -> None:
    """The first pass and the replay read many windows through one reader: each file's index (a ROS 1
    bag's, an MCAP summary) is read once, not once a window, and a .db3 is read through one sqlite
    connection (its topics, statistics and every window's rows)."""
    from tftools.sources.bag import mcap, ros1
    from tftools.sources.bag.rosbag2 import db3

    bag = simulation(tmp_path / "sim", fmt)
    counted: list[str] = []
    for module, name in ((ros1, "read_index"), (mcap, "summary_of"), (db3, "Database")):
        real = getattr(module, name)

        def count(*a: object, _real: Any = real, _name: str = name) -> Any:
            counted.append(_name)
            return _real(*a)

        monkeypatch.setattr(module, name, count)
    with stream_recording([bag], window_messages=300) as streamed:
        assert len(streamed.windows) > 3
        assert sum(len(part) for part in streamed.parts()) == len(read_recording([bag]).transforms)
    assert len(counted) == 2  # this stream's, then read_recording's


@pytest.mark.parametrize("native", [True, False], ids=["extension", "sqlite3"])
def test_a_db3_stream_is_replayed_from_another_thread_through_its_one_connection(
    monkeypatch: pytest.MonkeyPatch, native: bool
) -> None:
    """A replay reads its windows in a thread of its own, through the connection the first pass opened (one
    used by one thread at a time): every row comes back, through the extension or Python's sqlite3."""
    import threading

    from tftools.sources.bag.rosbag2 import database

    if not native:
        monkeypatch.setattr(database, "_Native", None)
    paths = [SAMPLES / "robot_db3"]
    read: list[RecordingContents] = []
    with stream_recording(paths, window_messages=300) as streamed:
        thread = threading.Thread(target=lambda: read.extend(streamed.reader.read(w) for w in streamed.windows))
        thread.start()
        thread.join()
    assert len(read) == len(streamed.windows) > 3 and all(not contents.problems for contents in read)
    assert sum(len(contents.transforms) for contents in read) == len(read_recording(paths).transforms)


@pytest.mark.parametrize("fmt", [BagFormat.ros1, BagFormat.rosbag2_sqlite3])
@pytest.mark.parametrize("simulated", [False, True], ids=["wall", "sim"])
def test_a_replay_plays_to_the_recordings_end_past_its_last_tf(tmp_path: Path, fmt: BagFormat, simulated: bool) -> None:
    """A real Neato's driver died 59.7 s into a 71.1 s recording while its wall follower went on sending
    /cmd_vel (corpus ``ros2-neato-real-wall-follower-stopped-2023-db3``): rosbag play plays on to 71.1 s, and so
    does the replay (``tfx monitor --play``), so that its last table shows the tf gone, not a healthy 6 Hz. In a
    simulation the end is /clock's at the recording's end."""
    base = SIM if simulated else WALL  # the stamps' clock

    def at(tenths: int, clock: int = base) -> int:
        return clock + tenths * NS_PER_S // 10

    tf = [TfMessage("/tf", at(i, WALL) + 1000, [_transform("odom", "base_link", at(i), i)]) for i in range(50)]
    other = [ClockMessage(at(i, WALL), at(i), topic="/clock" if simulated else "/cmd_vel_heard") for i in range(80)]
    bag = write_bag(tmp_path / "bag", tf, fmt, other)
    with stream_recording([bag]) as streamed:
        replay = streamed.replay()
        replay.attach(lambda batch: None)
        replay.advance_to(at(50))  # every tf played: not yet the end
        assert not replay.finished and replay.clock.now() == at(50)
        replay.advance_to(at(100))
        assert replay.finished and replay.end == at(79) and replay.clock.now() == at(79)
        assert streamed.replay(end=at(10)).end == at(10)  # an end asked for is kept


def _two_clocks(path: Path) -> Path:
    """A simulated robot (odom -> base) on a /clock ticking every 100 ms beside a device (imu -> sonar) stamped
    on the wall clock, recorded 0.4-0.6 ms after its stamps."""
    ms, wall, sim = 10**6, 1_700_000_000 * NS_PER_S, 1400 * NS_PER_S
    robot = [
        TfMessage(
            "/tf", wall + i * 34 * ms + ms, [Transform(stamp=sim + i * 34 * ms, frame_id="odom", child_frame_id="base")]
        )
        for i in range(290)
    ]
    device = []
    for i in range(95):
        stamp = wall + i * 100 * ms + 7 * ms
        sonar = Transform(stamp=stamp, frame_id="imu", child_frame_id="sonar")
        device.append(TfMessage("/tf", stamp + 400_000 + (i % 3) * 100_000, [sonar]))
    ticks = [ClockMessage(wall + i * 100 * ms, sim + i * 100 * ms) for i in range(100)]
    messages = sorted(robot + device, key=lambda m: m.record_time)
    return write_bag(path, messages, BagFormat.rosbag2_sqlite3, ticks)


def _delays(buffer: Buffer, timeline: Timeline, child: str) -> list[int]:
    hist = buffer.history(child)
    assert hist is not None
    delays: list[int] = timeline.delays(child, hist.stamps, hist.record_times, hist.flags).tolist()
    return delays


def test_a_replay_measures_a_devices_delays_on_its_record_times_as_a_whole_read_does(tmp_path: Path) -> None:
    """ros2_db3_ias0220_gazebo_diff_cont_2025's shape (``_two_clocks``). A replay plays every row on /clock, whose
    ticks cannot time the device; its delays are measured on the record times its first pass kept, as a whole
    read measures them: the same figures (they were unavailable in the replay). The robot's stay unavailable."""
    bag = _two_clocks(tmp_path / "two_clocks")
    whole = read_recording([bag])
    streamed = stream_recording([bag], window_messages=100)
    played = Buffer(cache_time=None)
    for part in streamed.parts():
        played.insert(part)
    assert streamed.timeline.record_clocked == whole.timeline.record_clocked == {"sonar"}
    expected = [400_000 + (i % 3) * 100_000 for i in range(95)]
    assert _delays(whole.buffer, whole.timeline, "sonar") == _delays(played, streamed.timeline, "sonar") == expected
    assert _delays(whole.buffer, whole.timeline, "base") == _delays(played, streamed.timeline, "base") == []


def test_a_replays_windows_are_let_go_once_both_halves_are_taken() -> None:
    """`monitor --play` of a 4 h recording peaked at 2.7x the memory of a 1.3 h one: ``itertools.tee``, which split
    each window into its transforms and its messages, let go of its items 57 at a time: a 1.3 h recording's 25
    windows were held whole, a 4 h one's 75 up to 57 at once. Taken in step, only the pair the generator yielded
    last is alive."""

    class Window:
        pass

    made: list[tuple[weakref.ref[Window], weakref.ref[Window]]] = []

    def windows() -> Iterator[tuple[Window, Window]]:
        for _ in range(200):
            parts, sent = Window(), Window()
            made.append((weakref.ref(parts), weakref.ref(sent)))
            yield parts, sent

    parts, messages = _halves(windows())
    alive = []
    for part in parts:
        message = next(messages)
        del part, message
        alive.append(sum(1 for a, b in made if a() is not None or b() is not None))
    assert len(made) == 200 and max(alive) == 1, alive
