"""One reproducer per way ``tfx filter`` once differed from the real ``tf2_ros::MessageFilter`` (issue 29):
each scene is a case of the designed bag (tests/oracle/msgfilter/make_designed_bag.py), whose answers the
real filter gives in tests/oracle/test_msgfilter.py; here the rule alone, without ROS."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.analysis.filter.fates import NEVER, Fate, Fates, message_fates, pushed_out, smallest_queue
from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.render.filter import as_dict, renderable
from tftools.sources.contents import StampedMessages

T0 = 1_700_000_000 * NS_PER_S
MS = 1_000_000
SECONDS = 30


def _t(parent: str, child: str, stamp: int, x: float = 0.1) -> Transform:
    return Transform.from_rpy((x, 0.0, 0.0), (0.0, 0.0, 0.0), stamp, parent, child)


def _grid(hz: int, start_s: float = 0.0, end_s: float = SECONDS) -> list[int]:
    count = round((end_s - start_s) * hz)
    return [T0 + round(start_s * NS_PER_S) + i * NS_PER_S // hz for i in range(count)]


def _moving(
    parent: str, child: str, hz: int, late: int, start_s: float = 0.0, end_s: float = SECONDS
) -> list[TfMessage]:
    return [
        TfMessage("/tf", s + late, [_t(parent, child, s, (s - T0) / NS_PER_S)], "/node")
        for s in _grid(hz, start_s, end_s)
    ]


def _static(parent: str, child: str, record: int = T0) -> TfMessage:
    return TfMessage("/tf_static", record, [_t(parent, child, T0)], "/static")


def _buffer(*parts: list[TfMessage] | TfMessage) -> Buffer:
    messages = [m for p in parts for m in (p if isinstance(p, list) else [p])]
    return recording(sorted(messages, key=lambda m: m.record_time)).buffer


def _stream(rows: Sequence[tuple[int, str, int]], topic: str = "/sensor") -> StampedMessages:
    """(arrival, frame_id, stamp) rows, in arrival order."""
    rows = sorted(rows, key=lambda r: r[0])
    frames = sorted({f for _, f, _ in rows})
    return StampedMessages(
        topic,
        "sensor_msgs/msg/LaserScan",
        np.array([r[0] for r in rows], np.int64),
        np.array([r[2] for r in rows], np.int64),
        np.array([frames.index(f) for _, f, _ in rows], np.int32),
        frames,
    )


def _base() -> list[TfMessage]:
    """odom -> base_link at 50 Hz for 30 s, recorded 30 ms after its stamps; base_link -> laser static."""
    return [*_moving("odom", "base_link", 50, 30 * MS), _static("base_link", "laser")]


def _fates(buffer: Buffer, stream: StampedMessages, cache_s: float = 10.0) -> Fates:
    return message_fates(buffer, stream, "odom", round(cache_s * NS_PER_S))


def test_a_message_older_than_the_cache_when_it_arrives_is_dropped_at_once() -> None:
    """Fault A: clouds stamped 12 s before they arrive (the designed bag's /cloud_old and /cloud_old_early)."""
    arrivals = [T0 + 300 * MS + i * NS_PER_S // 2 for i in range(56)]
    stream = _stream([(a, "laser", a - 12 * NS_PER_S) for a in arrivals])
    buffer = _buffer(_base())
    fates = _fates(buffer, stream)
    assert (fates.fate == Fate.TOO_OLD_ON_ARRIVAL).all()  # tf2: stamp + 10 s is before the latest common time
    np.testing.assert_array_equal(fates.left, stream.record_time)  # dropped inside add(): never queued
    report = filter_streams(buffer, [stream], FilterQuery(target="odom")).streams[0]
    assert (report.never, report.reasons, report.undecided) == (56, {"too_old_on_arrival": 56}, {})
    assert report.cache_needed == 15 * NS_PER_S  # 12 s behind: a 15 s cache keeps those stamped after tf began
    assert report.before_tf == 24  # stamped before T0 (tf's start): the real filter drops them with any cache


def test_no_cache_is_suggested_for_messages_stamped_before_their_chains_tf_began() -> None:
    """Issue 39: clouds stamped 12 s behind from the recording's first second are all stamped before tf began:
    'cache 15 s' was suggested, and the real MessageFilter with a 15 s cache drops every one (tf2 never held
    tf that old: 'earlier than all the data in the transform cache'). No cache keeps them: say what does."""
    arrivals = [T0 + 300 * MS + i * NS_PER_S // 2 for i in range(20)]
    stream = _stream([(a, "laser", a - 12 * NS_PER_S) for a in arrivals])
    buffer = _buffer(_base())
    fates = message_fates(buffer, stream, "odom", 15 * NS_PER_S)
    assert fates.early().all() and not (fates.fate == Fate.LATER).any()  # a 15 s cache passes none of them
    whole = filter_streams(buffer, [stream], FilterQuery(target="odom"))
    assert (whole.streams[0].cache_needed, whole.streams[0].before_tf) == (None, 20)
    assert "20 stamped before tf began: no cache keeps them" in " ".join(_text(whole).split())


def test_messages_stamped_before_the_first_tf_anyone_sent_are_said_to_predate_tf() -> None:
    """The walker's (ros2_db3_tb3_roomba_walker_tarunreddyy_2023) 6 IMU messages stamped 0.173-0.198 s, recorded
    before the simulation's first tf (0.202 s) arrived, 1.65 s after the recorder's first message (/tf_static):
    the recorder was listening and no tf existed yet, so 'record tf from before the sensor' asked for what never
    was. They are lost, as the advice says: 'undecided: before recorded tf' beside it said a listener started
    earlier might have had their tf. Messages recorded after tf began keep it."""
    early = [(T0 - 20 * MS + i * 5 * MS, "laser", T0 - 50 * MS + i * 5 * MS) for i in range(6)]  # before tf
    later = [(T0 + 300 * MS + i * 20 * MS, "laser", T0 + 270 * MS + i * 20 * MS) for i in range(20)]
    buffer = _buffer(_base(), _static("base_link", "imu", T0 - NS_PER_S))  # the recorder heard /tf_static 1 s before
    report = filter_streams(buffer, [_stream(early + later)], FilterQuery(target="odom"))
    (stream,) = report.streams
    assert (stream.before_tf, stream.before_any_tf) == (6, True), stream
    assert (stream.never, stream.reasons, stream.undecided) == (6, {"before_any_tf": 6}, {}), stream
    assert stream.wait_needed is not None  # the timeout of the other 20, which a wait decides
    text = " ".join(_text(report).split())
    assert "6 stamped before the first tf anyone published: the sensor started before tf" in text, text
    assert "6 never: before any tf 6" in text and "before recorded tf" not in text, text
    assert "record tf from before the sensor" not in text, text


def test_messages_before_an_edge_that_came_late_while_tf_was_recorded_are_told_its_publisher_started_late() -> None:
    """A CompRobo Neato in Gazebo (titut/ros_behaviors_fsm person_following, a scout's, 2026-12-02): the wheels and
    /stable_scan from the first moment, odom -> base_footprint's first transform 0.99 s later; 5 scans stamped
    before it were told 'record tf from before the sensor', which was recorded. They stay undecided (its first
    transforms may have gone unheard), with what was observed: that edge's first transform came after them, while
    other tf was recorded already."""
    scans = [(T0 + 2 * MS + i * 100 * MS, "laser", T0 + i * 100 * MS) for i in range(30)]
    odom = _moving("odom", "base_link", 10, 1 * MS, start_s=1.0)
    buffer = _buffer(odom, _static("base_link", "laser", T0 - 5 * MS), _moving("base_link", "wheel", 10, 1 * MS))
    report = filter_streams(buffer, [_stream(scans)], FilterQuery(target="odom"))
    (stream,) = report.streams
    assert stream.before_tf == 10 and stream.undecided == {"before_recorded_tf": 10}, stream
    assert stream.began_late == ("odom", "base_link", 999 * MS), stream.began_late
    text = " ".join(_text(report).split())
    assert "odom -> base_link's first transform arrived 0.999 s after the first of them, while other tf" in text
    assert "record tf from before the sensor" not in text, text
    assert as_dict(report)["topics"][0]["began_late"] == {"parent": "odom", "child": "base_link", "after_s": 0.999}
    alone = _buffer(odom, _static("base_link", "laser", T0 + 500 * MS))  # no tf heard before the scans: unknown
    unheard = filter_streams(alone, [_stream(scans)], FilterQuery(target="odom"))
    assert unheard.streams[0].began_late is None
    assert "record tf from before the sensor" in " ".join(_text(unheard).split())


def test_messages_before_tf_that_came_right_after_the_recording_began_stay_undecided() -> None:
    """The same messages where the recorder's first message is theirs and tf arrives 50 ms later, within the
    silence a 50 Hz stream may keep and still be publishing: a listener started earlier might have had tf that
    old, so the recording cannot tell (undecided, 'record tf from before the sensor')."""
    early = [(T0 - 20 * MS + i * 5 * MS, "laser", T0 - 50 * MS + i * 5 * MS) for i in range(6)]
    report = filter_streams(_buffer(_base()), [_stream(early)], FilterQuery(target="odom"))
    (stream,) = report.streams
    assert (stream.never, stream.undecided, stream.before_any_tf) == (0, {"before_recorded_tf": 6}, False), stream
    assert "6 stamped before tf began: no cache keeps them; record tf from before the sensor" in " ".join(
        _text(report).split()
    )


def test_the_waiters_of_a_tf_publisher_that_died_never_pass() -> None:
    """Fault B: odom -> base_dead stops 10 s into a 30 s recording (/scan_dead); a scan waiting for it is
    lost. Only an edge still publishing at the end leaves its last waiters undecided."""
    tf = [*_base(), *_moving("odom", "base_dead", 20, 5 * MS, end_s=10.0), _static("base_dead", "laser_dead")]
    stamps = _grid(20)
    scans = [(s + 45 * MS, "laser", s + 40 * MS) for s in stamps]  # the last stamped after base_link's last
    stream = _stream([(s + 10 * MS, "laser_dead", s) for s in stamps] + scans)
    fates = _fates(_buffer(tf), stream)
    dead = stream.frame == stream.frame_ids.index("laser_dead")
    after = dead & (stream.stamp >= T0 + 10 * NS_PER_S)
    assert (fates.fate[after] == Fate.NEEDS_NEWER_TF).all() and after.sum() == 400
    assert (fates.left[after] == NEVER).all()  # waiting for good, a slot of the queue each
    assert (fates.fate[dead & ~after] == Fate.ON_ARRIVAL).all()
    laser = np.flatnonzero(stream.frame == stream.frame_ids.index("laser"))  # base_link publishes to the end:
    assert fates.fate[laser[-1]] == Fate.AFTER_RECORDED_TF  # the last scan's tf would have come after it
    assert (fates.fate[laser[:-1]] == Fate.LATER).all()
    report = filter_streams(_buffer(tf), [stream], FilterQuery(target="odom")).streams[0]
    assert report.reasons == {"needs_newer_tf": 400} and report.undecided == {"after_recorded_tf": 1}


def test_a_reparented_frame_is_walked_through_its_parent_at_the_stamp() -> None:
    """Fault C: tool under base_link (30 ms late) until 15 s, then under odom (/tool_points): clouds of the
    first half wait for base_link, those of the second do not."""
    tf = [*_base(), *_moving("base_link", "tool", 20, 5 * MS, end_s=15.0), *_moving("odom", "tool", 20, 5 * MS, 15.0)]
    stream = _stream([(s + 10 * MS, "tool", s) for s in _grid(20)])
    fates = _fates(_buffer(tf), stream)
    first = stream.stamp < T0 + 15 * NS_PER_S
    assert (fates.fate[first] == Fate.LATER).all()
    waits = fates.ready[first] - stream.record_time[first]  # for base_link's next stamp, 30 ms late
    assert set(waits.tolist()) == {20 * MS, 30 * MS}
    assert {fates.edge[int(i)] for i in np.flatnonzero(first)} == {("odom", "base_link")}
    assert (fates.fate[~first][:-1] == Fate.ON_ARRIVAL).all()


def test_the_suggested_queue_counts_the_messages_that_never_pass() -> None:
    """Fault D: /scan_multi, 100 Hz alternating 'laser' (waiting ~30 ms for its tf) and 'laser_rear' (a frame
    no transform names, waiting for good): the real filter with the suggested queue keeps every laser scan;
    one slot less loses some."""
    rows = [(s + 5 * MS, "laser" if i % 2 == 0 else "laser_rear", s + 4 * MS) for i, s in enumerate(_grid(100))]
    stream = _stream(rows)
    buffer = _buffer(_base())
    fates = _fates(buffer, stream)
    later = fates.fate == Fate.LATER
    rear = stream.frame == stream.frame_ids.index("laser_rear")
    assert later.sum() == 1499 and (fates.fate[rear] == Fate.UNKNOWN_FRAME).all()
    queue = filter_streams(buffer, [stream], FilterQuery(target="odom")).streams[0].queue_needed
    assert not (pushed_out(fates, stream, queue) & later).any()
    assert (pushed_out(fates, stream, queue - 1) & later).any()
    assert queue > 3  # what only the passing messages held at once would suggest
    report = filter_streams(buffer, [stream], FilterQuery(target="odom", queue=queue)).streams[0]
    assert report.dropped_by_queue == report.never  # only the unknown frame's


def test_a_stamp_0_message_never_waits() -> None:
    """Fault F: stamp 0 asks for the latest common time; it passes at arrival only where that time is
    inside every edge's cache, and is dropped at arrival or as soon as its frame is known otherwise
    (/scan_zero, /scan_zero_late)."""
    arm = [*_moving("base_link", "arm", 20, 5 * MS, end_s=5.0), _static("arm", "hand")]  # arm stops at 5 s
    late_static = _static("base_link", "laser_ls", T0 + 8 * NS_PER_S)
    tf = [*_base(), *arm, late_static]
    arrivals = [T0 + 110 * MS + i * NS_PER_S // 5 for i in range(145)]
    stream = _stream(
        [(a, "laser", 0) for a in arrivals]
        + [(a + MS, "hand", 0) for a in arrivals]
        + [(a + 2 * MS, "laser_ls", 0) for a in arrivals]
    )
    fates = _fates(_buffer(tf), stream)

    def of(frame: str) -> np.ndarray:
        return np.flatnonzero(stream.frame == stream.frame_ids.index(frame))

    assert (fates.fate[of("laser")] == Fate.ON_ARRIVAL).all()
    hand = fates.fate[of("hand")]  # the latest common time is arm's last stamp: base_link's cache drops it
    hand_at = stream.record_time[of("hand")]  # 10 s after arm stopped
    assert (hand[hand_at < T0 + 15 * NS_PER_S] == Fate.ON_ARRIVAL).all()
    assert (hand[hand_at > T0 + 15 * NS_PER_S + 100 * MS] == Fate.TOO_OLD_ON_ARRIVAL).all()
    late = of("laser_ls")  # unknown until 8 s: waits, then dropped by the transform that makes it known
    before = stream.record_time[late] < T0 + 8 * NS_PER_S
    assert (fates.fate[late[before]] == Fate.OLDER_THAN_CACHE).all()
    assert (fates.left[late[before]] == T0 + 8 * NS_PER_S).all()
    assert (fates.fate[late[~before]] == Fate.ON_ARRIVAL).all()


def test_the_counts_add_up() -> None:
    """Issue 30: 'before recorded tf' was listed under 'why never' while 'never' was 0. Messages stamped
    before the recording's tf began (/scan_early) are undecided, apart from those lost."""
    tf = [*_base(), *_moving("odom", "early_base", 20, 30 * MS), _static("early_base", "early_laser")]
    early = [(T0 + i * MS, "early_laser", T0 - 200 * MS) for i in (1, 2, 3)]
    typo = [(s + 5 * MS, "lazer", s) for s in _grid(10)]
    stream = _stream(early + typo)
    buffer = _buffer(tf)
    fates = _fates(buffer, stream)
    assert (fates.fate[:3] == Fate.BEFORE_RECORDED_TF).all()
    np.testing.assert_array_equal(fates.left[:3], T0 + 9_850 * MS + 30 * MS)  # when 9.85 s arrived: 9.8 + 10 s
    report = filter_streams(buffer, [stream], FilterQuery(target="odom")).streams[0]
    assert report.never == sum(report.reasons.values()) == 300
    assert report.undecided == {"before_recorded_tf": 3}
    assert report.on_arrival + report.later + report.never + sum(report.undecided.values()) == report.messages
    text = _text(filter_streams(buffer, [stream], FilterQuery(target="odom")))
    assert "unknown frame 300" in text and "before recorded tf 3" in text


def _text(report: object) -> str:
    from rich.console import Console

    console = Console(width=250, record=True)
    console.print(renderable(report))  # type: ignore[arg-type]  # a FilterReport, passed as object
    return console.export_text()


def test_the_suggested_queue_is_the_smallest_that_keeps_every_passing_message() -> None:
    """Against the filter's own queue replayed message by message (``pushed_out``), on random streams of
    messages that pass at once, after a wait, never (waiting for good), or are dropped after a wait."""
    rng = np.random.default_rng(29)
    for _ in range(300):
        n = int(rng.integers(1, 40))
        arrived = np.sort(rng.integers(0, 50, n)).astype(np.int64)  # ties included
        fate = rng.choice([Fate.ON_ARRIVAL, Fate.LATER, Fate.UNKNOWN_FRAME, Fate.OLDER_THAN_CACHE], n).astype(np.int8)
        wait = rng.integers(1, 30, n)
        left = np.where(fate == Fate.UNKNOWN_FRAME, NEVER, np.where(fate == Fate.ON_ARRIVAL, arrived, arrived + wait))
        ready = np.where(fate == Fate.LATER, left, NEVER).astype(np.int64)
        fates = Fates(fate, ready, [None] * n, np.zeros(n, np.int64), left.astype(np.int64))
        stream = StampedMessages("/t", "t", arrived, arrived, np.zeros(n, np.int32), ["f"])
        later = fate == Fate.LATER
        keeps = [q for q in range(1, n + 2) if not (pushed_out(fates, stream, q) & later).any()]
        assert smallest_queue(fates, stream) == (keeps[0] if later.any() else 0)


def test_a_topic_recorded_without_a_message_is_not_said_to_lack_a_frame_id() -> None:
    """ros2_db3_jetacker_real_stamps_back recorded /imu/data_raw and /imu/mag with 0 messages; filter said
    they had 'a header but no frame_id': nothing was read to say so. One with messages without a frame_id is."""
    buffer = _buffer(_moving("odom", "base_link", 20, MS))
    unframed = _stream([(T0 + NS_PER_S, "", T0 + NS_PER_S)], "/unframed")
    report = filter_streams(buffer, [_stream([], "/imu/mag"), unframed], FilterQuery(target="odom"))
    assert report.skipped == ["/unframed"] and not report.streams


def test_a_wait_for_a_slow_edge_is_said_as_its_next_sample_not_as_lateness() -> None:
    """Issue 39 (ros2_db3_neato_real_person_marker_2025): markers waited ~0.18 s for odom -> base_footprint at
    5.5 Hz, said as '0.001 s behind'. The edge is on time; the wait is its step to the next sample: say both."""
    edge = [TfMessage("/tf", s + MS, [_t("odom", "base_link", s)], "/odom") for s in _grid(5)]
    stamps = _grid(5)[:-1]  # 1 ms after each tf's stamp, arriving 1 ms after that tf
    stream = _stream([(s + 2 * MS, "base_link", s + MS) for s in stamps])
    report = filter_streams(_buffer(edge), [stream], FilterQuery(target="odom")).streams[0]
    assert report.later == len(stamps) and report.wait["p50"] == 199 * MS  # to the next sample's arrival
    assert (report.late_by, report.late_after, report.late_rate_hz) == (MS, 199 * MS, 5.0)
    text = " ".join(_text(filter_streams(_buffer(edge), [stream], FilterQuery(target="odom"))).split())
    assert "its newest stamp 0.001 s behind the message's on arrival, its next sample stamped 0.199 s after" in text
    assert "at 5.0 Hz" in text
    from tftools.analysis.wtf import Scene, findings_of

    (wait,) = [f for f in findings_of(Scene(recording(edge), streams=[stream])) if f.code == "sensor_wait"]
    assert "for odom -> base_link: its newest stamp 0.001 s behind" in wait.message  # wtf says the same
    assert "its next sample stamped 0.199 s after it at 5.0 Hz" in wait.message


def test_a_lag_under_a_millisecond_is_said_so_never_0_000_s() -> None:
    """A real car's markers (ros1_car_path_follower.bag, /car_marker) are stamped a few microseconds after the
    newest tf: said as 'its newest stamp 0.000 s behind'. Under a millisecond is said so; the step stays."""
    edge = [TfMessage("/tf", s + MS, [_t("odom", "base_link", s)], "/odom") for s in _grid(20)]
    stamps = _grid(20)[:-1]
    stream = _stream([(s + 2 * MS, "base_link", s + 20_000) for s in stamps])  # 20 µs after each tf's stamp
    report = filter_streams(_buffer(edge), [stream], FilterQuery(target="odom"))
    assert report.streams[0].late_by == 20_000
    text = " ".join(_text(report).split())
    assert "its newest stamp under 1 ms behind the message's on arrival, its next sample stamped 0.050 s" in text
    assert "0.000 s" not in text


def test_a_wait_for_an_edge_not_yet_sent_is_said_so_never_as_a_lag_from_stamp_0() -> None:
    """A real KTH robot (ros2_db3_kth_robp_scan_statics_2024): the recorder found the laser's
    static_transform_publisher 2.3 s after it began, so 17 scans waited for base_link -> laser's first
    transform; filter said 'its newest stamp 1710875440.851 s behind the message's' (a stamp of 0 taken for
    the newest) and 'its next sample stamped with the message's stamp'. Nothing had arrived to be behind."""
    scans = [(s + 2 * MS, "laser", s) for s in _grid(10, 0.0, 5.0)]
    late = _static("base_link", "laser", record=T0 + 2 * NS_PER_S + 500 * MS)  # stamped T0, recorded at +2.5 s
    report = filter_streams(_buffer(late), [_stream(scans)], FilterQuery(target="base_link")).streams[0]
    assert report.later == 25 and report.never == 0 and report.late_edge == ("base_link", "laser")
    assert (report.late_unheld, report.late_by, report.late_after) == (25, 0.0, 0.0)
    text = " ".join(_text(filter_streams(_buffer(late), [_stream(scans)], FilterQuery(target="base_link"))).split())
    assert "base_link -> laser (25 arrived before its first transform and waited for it)" in text
    assert "behind" not in text and "next sample" not in text


def test_waits_before_and_after_an_edge_first_arrived_are_said_apart() -> None:
    """Messages that waited for a moving edge's first transform, and later ones that waited for its next
    sample: the lag and step are the later ones' (the first ones had nothing to lag behind)."""
    started = T0 + 1_500 * MS  # its first samples (stamped from +1.0 s) recorded together at +1.5 s
    edge = [TfMessage("/tf", max(s + MS, started), [_t("odom", "base_link", s)], "/odom") for s in _grid(5, 1.0)]
    stream = _stream([(s + 2 * MS, "base_link", s + MS) for s in _grid(5, 1.0)[:-1]])
    report = filter_streams(_buffer(edge), [stream], FilterQuery(target="odom")).streams[0]
    assert report.late_unheld == 3 and report.later == len(stream)  # stamped +1.0, +1.2, +1.4: before +1.5
    assert (report.late_by, report.late_after) == (MS, 199 * MS)  # the waits for its next sample only
    text = " ".join(_text(filter_streams(_buffer(edge), [stream], FilterQuery(target="odom"))).split())
    assert "3 arrived before its first transform and waited for it; then its newest stamp 0.001 s behind" in text


def test_the_longest_wait_is_said_with_its_edge_where_most_waited_for_another() -> None:
    """The TurtleBot 4 simulator (ros2_db3_turtlebot4_gz_wheels_two_publishers_2025): 131 scans waited a few ms for
    odom -> base_link, the first 7 up to 0.543 s for the lidar's static, sent 0.68 s in. filter said only 'waited for
    odom -> base_link ...' beside 'wait 0.543 s': the timeout it advised is the static's, so say whose it is."""
    scans = [(s + 2 * MS, "laser", s) for s in _grid(10, 0.0, 5.0)]  # 2 ms after odometry's sample at its stamp
    late = _static("base_link", "laser", record=T0 + 650 * MS)  # the laser's mount, recorded at +0.65 s
    report = filter_streams(_buffer(_base()[:-1], late), [_stream(scans)], FilterQuery(target="odom"))
    (scan,) = report.streams
    assert scan.late_edge == ("odom", "base_link") and scan.longest_edge == ("base_link", "laser")
    assert (scan.longest_waited, scan.longest_unheld) == (7, 7) and scan.wait["max"] == 650 * MS - 2 * MS
    text = " ".join(_text(report).split())
    assert "; the longest for base_link -> laser: 7 arrived before its first transform and waited for it;" in text
    lone = filter_streams(_buffer(_base()), [_stream(scans)], FilterQuery(target="odom"))
    assert lone.streams[0].longest_edge is None and "the longest" not in " ".join(_text(lone).split())
