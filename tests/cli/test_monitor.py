"""``tfx monitor`` as a user runs it: sample bags' true rates, text and JSON, chains, errors, --play."""

from __future__ import annotations

import itertools
import json
import math
import re
from pathlib import Path

import pytest

from tests.analysis.monitor_scenes import FORMATS, scene, write_scene
from tests.bags import BagFormat, ClockMessage, TfMessage, detections_bag, device_beside_simulation_bag, write_bag
from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tftools.analysis.edges import TimeWindow
from tftools.analysis.monitor import monitor_buffer
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S, to_sec
from tftools.core.transform import Transform
from tftools.sources import read_recording

# The truth sample_bags/generate.py wrote (its docstring): child frame -> publishing rate.
ARM = [f"arm_link{i}" for i in range(1, 7)]
TRUE_RATES = {"odom": 10, "base_footprint": 50, "left_wheel": 30, "right_wheel": 30, **dict.fromkeys(ARM, 50)}
STATIC = {"base_link", "laser", "imu_link", "camera_link", "camera_optical_frame", "arm_base", "gripper"}
PUBLISHER_RATES = {"/amcl": 10, "/ekf_localization": 50, "/robot_state_publisher": 30, "/arm/robot_state_publisher": 50}

EDGE_KEYS = {"parent", "child", "authorities", "count", "rate_hz", "jitter_s", "gap_max_s", "gap_start", "silent_s",
             "gap_in_damage", "delay_mean_s", "delay_max_s", "delay_unmeasurable", "static", "sightings", "first_stamp",
             "last_stamp"}  # fmt: skip
SAMPLES = list(SAMPLE_BAGS)
MS_NS = 1_000_000


@pytest.mark.parametrize("fmt", SAMPLES)
def test_sample_bags_every_edge_at_its_true_rate(tfx: Tfx, fmt: str) -> None:
    result = tfx("monitor", "-b", SAMPLE_BAGS[fmt], "--format", "json")
    assert result.code == 0, result.stderr
    edges = {e["child"]: e for e in json.loads(result.stdout)["edges"]}
    assert set(edges) == set(TRUE_RATES) | STATIC
    for child, hz in TRUE_RATES.items():
        assert edges[child]["rate_hz"] == pytest.approx(hz, rel=0.02), child
        assert edges[child]["count"] == pytest.approx(15 * hz, abs=1)
        assert edges[child]["gap_max_s"] == pytest.approx(1 / hz, abs=0.001)  # no message lost: +-0.3 ms jitter
        assert 0.001 <= edges[child]["delay_mean_s"] <= edges[child]["delay_max_s"] <= 0.005  # recorded 1-5 ms late
    assert {c for c, e in edges.items() if e["static"]} == STATIC
    if fmt == "ros1":  # ROS1 bags name each publisher
        publishers = {a["authority"]: a for a in json.loads(result.stdout)["authorities"]}
        for name, hz in PUBLISHER_RATES.items():
            assert publishers[name]["rate_hz"] == pytest.approx(hz, rel=0.02), name


def test_json_schema_with_a_chain(tfx: Tfx) -> None:
    result = tfx("monitor", "map", "gripper", "-b", SAMPLE_BAGS["mcap"], "-f", "json")
    assert result.code == 0, result.stderr
    doc = json.loads(result.stdout)
    assert set(doc) == {
        "window",
        "edges",
        "authorities",
        "publishers_named",
        "publishers_listed",
        "chain",
        "delays_unavailable",
        "delays_other_clock",
    }
    assert doc["delays_unavailable"] is None  # delays are measured: the sample robot's tf is on its record clock
    assert doc["delays_other_clock"] is None  # and no frame is stamped on another clock
    for edge in doc["edges"]:
        assert set(edge) == EDGE_KEYS
        assert isinstance(edge["authorities"], list) and isinstance(edge["count"], int)
        if edge["static"]:  # NaN in Python, null in JSON; no rhythm: null, not 0.0 ("a rate of zero", "just arrived")
            assert edge["delay_mean_s"] is None and edge["delay_max_s"] is None
            assert [edge[k] for k in ("rate_hz", "jitter_s", "gap_max_s", "gap_start", "silent_s")] == [None] * 5
        else:
            assert all(isinstance(edge[k], float) for k in ("rate_hz", "jitter_s", "gap_max_s", "delay_mean_s"))
    for authority in doc["authorities"]:
        assert set(authority) == {
            "authority", "messages", "rate_hz", "delay_mean_s", "delay_max_s", "delay_unmeasurable", "delay_of",
            "no_delay_of", "delays_counted", "delays_beyond_edges", "edges"
        }  # fmt: skip
        assert authority["delay_unmeasurable"] is None  # one clock: every delay measured
    statics = [a for a in doc["authorities"] if all(child in STATIC for _, child in a["edges"])]
    assert statics and all(a["rate_hz"] is None for a in statics)  # "static" in the table, no rate of zero
    chain = doc["chain"]
    assert chain["frames"][0] == "gripper" and chain["frames"][-1] == "map" and len(chain["frames"]) == 12
    assert [e["child"] for e in chain["edges"]] == chain["frames"][:-1]
    # map -> odom at 10 Hz holds the chain back: its newest stamp is up to 0.1 s + 5 ms old.
    assert chain["limiting"] == ["map", "odom"]
    assert 0.05 <= chain["net_delay_mean_s"] <= 0.056 and 0.1 <= chain["net_delay_max_s"] <= 0.106
    # a chain's net delay is no edge's delay (each about 3 ms here): never under the edges' name
    assert "delay_mean_s" not in chain and all(e["delay_mean_s"] < 0.006 for e in chain["edges"] if not e["static"])
    assert "chain" not in json.loads(tfx("monitor", "-b", SAMPLE_BAGS["mcap"], "-f", "json").stdout)


def test_text_uses_tf_monitors_words(tfx: Tfx) -> None:
    result = tfx("monitor", "-b", SAMPLE_BAGS["db3"])
    assert result.code == 0, result.stderr
    out = result.stdout
    for words in ("RESULTS: for all Frames", "Frames:", "All Broadcasters:", "Average Delay", "Max Delay"):
        assert words in out
    for child in [*TRUE_RATES, *STATIC]:
        assert re.search(rf"\s{child}\s", out), child
    odom = next(line for line in out.splitlines() if re.match(r"\s*map\s+odom\s", line))
    assert re.search(r"\s150\s+10\.00\s", odom)  # samples and rate
    chained = tfx("monitor", "odom", "left_wheel", "-b", SAMPLE_BAGS["db3"]).stdout
    assert "RESULTS: for odom to left_wheel" in chained
    assert "Chain is: left_wheel -> base_link -> base_footprint -> odom" in chained
    assert re.search(r"Net delay\s+avg = 0\.0\d+: max = 0\.0\d+", chained)
    assert "Net delay: how far the chain's newest common stamp is behind ROS time" in " ".join(chained.split())
    assert "arm_link3" not in chained.split("All Broadcasters:")[0]  # only the chain's frames, as tf_monitor


@pytest.mark.parametrize("fmt", FORMATS)
def test_unseen_bags_text_and_json_agree_with_the_truth(tfx: Tfx, tmp_path: Path, fmt: BagFormat) -> None:
    truth = scene(seed=11)
    bag = write_scene(tmp_path, fmt, truth.messages)
    doc = json.loads(tfx("monitor", "-b", bag, "-f", "json").stdout)
    edges = {e["child"]: e for e in doc["edges"]}
    for child, t in truth.truth.items():
        assert edges[child]["count"] == len(t.stamps)
        assert edges[child]["delay_max_s"] == pytest.approx(max(t.delays) / NS_PER_S, abs=1e-9)
    text = tfx("monitor", "-b", bag).stdout
    camera = next(line for line in text.splitlines() if re.match(r"\s*base_link\s+camera\s", line))
    assert f"{edges['camera']['delay_mean_s']:.4f}" in camera and f"{edges['camera']['gap_max_s']:.4f}" in camera


def test_start_and_end_select_a_stretch(tfx: Tfx) -> None:
    whole = json.loads(tfx("monitor", "-b", SAMPLE_BAGS["mcap"], "-f", "json").stdout)
    part = json.loads(tfx("monitor", "-b", SAMPLE_BAGS["mcap"], "-f", "json", "--start", "+5", "--end", "+10").stdout)
    counts = {e["child"]: e["count"] for e in part["edges"]}
    assert counts["odom"] == pytest.approx(50, abs=1) and counts["base_footprint"] == pytest.approx(250, abs=1)
    assert part["window"]["end"] - part["window"]["start"] == pytest.approx(5.0)
    assert whole["window"] == {"start": None, "end": None}


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (("-b", "/nonexistent/robot.bag"), "robot.bag"),
        (("map", "base_lnk", "-b", SAMPLE_BAGS["mcap"]), "base_link"),  # the close match is offered
        (("map", "-b", SAMPLE_BAGS["mcap"]), "two frames"),
        (("-b", SAMPLE_BAGS["mcap"], "--play", "--rate", "0"), "--rate"),
        (("-b", SAMPLE_BAGS["mcap"], "--rate", "4"), "--rate is the replay speed of --play"),  # not ignored
        (("-b", SAMPLE_BAGS["mcap"], "--start", "+10", "--end", "+5"), "empty"),
        (("-b", SAMPLE_BAGS["mcap"], "--start", "+20", "--play"), "outside the recording"),
    ],
)
def test_unusable_input_is_one_line_and_exit_2(tfx: Tfx, args: tuple[str | Path, ...], says: str) -> None:
    result = tfx("monitor", *args)
    assert result.code == 2
    assert result.stderr.startswith("tfx: error:") and says in result.stderr
    assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1


def test_play_ends_on_the_numbers_of_its_last_window(tfx: Tfx) -> None:
    result = tfx("monitor", "map", "base_footprint", "-b", SAMPLE_BAGS["mcap"], "--play", "--rate", "500",
                 "--window", "4", "-f", "json")  # fmt: skip
    assert result.code == 0, result.stderr
    last = json.loads(result.stdout.splitlines()[-1])
    recording = read_recording([SAMPLE_BAGS["mcap"]])
    end = recording.end
    last_four = TimeWindow(end - 4 * NS_PER_S, end, by_record_time=True)
    expected = monitor_buffer(recording.buffer, "map", "base_footprint", last_four)
    assert last["window"] == {"start": to_sec(end - 4 * NS_PER_S), "end": to_sec(end)}
    for theirs, ours in zip(last["edges"], expected.edges, strict=True):
        assert (theirs["child"], theirs["count"]) == (ours.child, ours.count)
        assert theirs["rate_hz"] == (None if ours.static else pytest.approx(ours.rate_hz, rel=1e-12))
    assert expected.chain is not None
    assert last["chain"]["net_delay_mean_s"] == pytest.approx(seconds(expected.chain.delay_mean), rel=1e-12)


@pytest.mark.parametrize("rate", ["50", "500"])
def test_play_refreshes_once_a_second_of_the_recording_whatever_the_rate(tfx: Tfx, rate: str) -> None:
    """As its --help says since polish14 made a replay tick on its own clock: --rate 2 refreshes every 0.5 s of
    wall time (ros2_db3_tb3_real_lap_2025), so the 15 s sample bag gets a table at each of its 14 whole seconds
    that the replay reaches as they come, at any rate (on the wall clock, 50x would give it none before the
    end), and one as it ends where the replay got past the last one's time first (follow's summary). A replay
    faster than its tables (500x: 30 ms of wall time) no longer repeats the window it reached for each second
    it ran past (issue 39: 831 of 1361 tables of that lap at --rate 40): each table is a new window, the last
    the recording's end; how fast the replay ran decides how many."""
    result = tfx("monitor", "-b", SAMPLE_BAGS["mcap"], "--play", "--rate", rate, "-f", "json")
    assert result.code == 0, result.stderr
    recording = read_recording([SAMPLE_BAGS["mcap"]])
    seconds_of_it = (recording.end - recording.start) // NS_PER_S
    ends = [json.loads(line)["window"]["end"] for line in result.stdout.splitlines()]
    assert seconds_of_it == 14 and 1 <= len(ends) <= seconds_of_it + 1
    assert all(later > earlier for earlier, later in itertools.pairwise(ends)), ends
    assert ends[-1] == pytest.approx(to_sec(recording.end), abs=1e-6)


def test_play_text_shows_the_live_header_and_table(tfx: Tfx) -> None:
    result = tfx("monitor", "-b", SAMPLE_BAGS["mcap"], "--play", "--rate", "500")
    assert result.code == 0, result.stderr
    assert re.search(r"time 1700000014\.999 \(\+15\.0 s\), last 10 s, rate 500x", result.stdout)
    assert "RESULTS: for all Frames" in result.stdout and "All Broadcasters:" in result.stdout


def test_echo_play_prints_the_latest_transform_in_bag_time(tfx: Tfx) -> None:
    # One second of bag at real speed, two lines a second: the one test here that takes wall time.
    result = tfx("echo", "map", "base_footprint", "-b", SAMPLE_BAGS["mcap"], "--play", "--start", "-1", "--rate", "4",
                 "-f", "json")  # fmt: skip
    assert result.code == 0, result.stderr
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    stamps = [line["stamp_ns"] for line in lines]
    assert len(lines) >= 3 and stamps == sorted(stamps)
    end = read_recording([SAMPLE_BAGS["mcap"]]).end
    assert end - NS_PER_S - 100_000_000 <= stamps[0] and end - 100_000_000 <= stamps[-1] <= end
    # tf_echo looks up the latest transform, and says the time it asked at: the replay's clock then
    # (JSON's seconds keep ~0.2 us at epoch times)
    times = [round(line["time"] * NS_PER_S) for line in lines]
    assert times == sorted(times) and end - NS_PER_S - 1000 <= times[0] and times[-1] <= end + 1000
    assert all(stamp <= time + 1000 for stamp, time in zip(stamps, times, strict=True))


def test_static_chain_text_says_it_never_goes_stale(tfx: Tfx, tmp_path: Path) -> None:
    bag = write_scene(tmp_path, BagFormat.rosbag2_mcap, scene().messages)
    out = tfx("monitor", "base_link", "laser", "-b", bag).stdout
    assert "Net delay     avg = -: max = -" in out and "never stale" in out


def test_a_table_too_long_to_lay_out_is_written_as_lines(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    """Past MAX_LAID_OUT_ROWS rows (rich lays a table out at 0.3 ms a row) the tables go out as lines,
    unmeasured: every name whole, every figure the JSON's."""
    import json

    from tftools.render import fitted

    monkeypatch.setattr(fitted, "MAX_LAID_OUT_ROWS", 2)
    text = tfx("monitor", "-b", SAMPLE_BAGS["ros1"])
    figures = json.loads(tfx("monitor", "-b", SAMPLE_BAGS["ros1"], "-f", "json").stdout)
    assert text.code == 0, text.stderr
    rows = {
        tuple(line.split(" by ")[0].split()[-3::2]): line.split() for line in text.stdout.splitlines() if " -> " in line
    }
    for edge in figures["edges"]:
        row = rows[(edge["parent"], edge["child"])]
        assert row[0] == str(edge["count"])
        assert row[1] == ("static" if edge["static"] else f"{edge['rate_hz']:.2f}")
    assert "Frames:" in text.stdout and "All Broadcasters:" in text.stdout


def _gazebo_under_sim_time(path: Path) -> Path:
    """A ``rosbag record`` under use_sim_time of a simulator on a 10 ms /clock (the shape of
    ``ros1_gazebo_kobuki_repeated_stamps.bag``, the real recording where ``--play`` counted 160 of /gazebo's
    199 messages and the whole read 166): record times are /clock's, every fifth odom message repeats the
    last stamp with other values (tf2's ``TF_REPEATED_DATA``), a state publisher's wheel is sent on every
    fourth tick, its latched static recorded a tick before the first /clock."""
    tick, start = 10 * MS_NS, 220 * MS_NS
    messages = [TfMessage("/tf_static", start - tick, [Transform((0, 0, 0.1), (0, 0, 0, 1), 0, "base_footprint",
                                                                  "base_link")], "/rsp")]  # fmt: skip
    stamp = start
    for k in range(100):
        now = start + k * tick
        stamp = stamp if k % 5 == 4 else now  # the simulation did not step: the last stamp again
        odom = Transform((0.001 * k, 0, 0), (0, 0, 0, 1), stamp, "odom", "base_footprint")
        messages.append(TfMessage("/tf", now, [odom], "/gazebo"))
        if k % 4 == 0:
            wheel = Transform((0, 0.1, 0), (0, 0, math.sin(k / 40), math.cos(k / 40)), now, "base_link", "wheel")
            messages.append(TfMessage("/tf", now, [wheel], "/rsp"))
    clock = [ClockMessage(start + k * tick, start + k * tick) for k in range(100)]
    return write_bag(path / "sim.bag", messages, BagFormat.ros1, clock)


def test_a_publishers_messages_are_those_it_sent_in_the_whole_read_and_the_replay(tfx: Tfx, tmp_path: Path) -> None:
    bag = _gazebo_under_sim_time(tmp_path)
    whole = tfx("monitor", "-b", bag, "-f", "json")
    played = tfx("monitor", "-b", bag, "--play", "--rate", "500", "-f", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    for report in (json.loads(whole.stdout), json.loads(played.stdout.splitlines()[-1])):
        publishers = {a["authority"]: a for a in report["authorities"]}
        # 100 messages on /tf, 20 of them refused as repeated stamps, on 10 ms record times: all counted
        assert publishers["/gazebo"]["messages"] == 100
        assert publishers["/gazebo"]["rate_hz"] == pytest.approx(100.0, rel=1e-9)
        # 25 on /tf and the latched /tf_static message (played at the first /clock, with a /tf one)
        assert publishers["/rsp"]["messages"] == 26
        edges = {e["child"]: e for e in report["edges"]}
        assert edges["base_footprint"]["count"] == 80  # the samples tf2 stored


def _webots_resends(path: Path, fmt: BagFormat) -> Path:
    """A ROS 2 recording shaped as ``ros2_db3_webots_epuck`` (where ``--play`` showed 4 of 8 /tf_static messages
    and 780 of 1,028 /tf ones): its /tf_static messages recorded before the first /clock (a broadcaster's
    message of two transforms, then 2 and 3 re-sends of single ones, identical values), and a controller whose
    /tf messages come two at a time on a 20 ms record clock (the simulation did not step: the last odometry
    again, identical, with a wheel's message at that time too)."""
    tick, start = 20 * MS_NS, 3 * NS_PER_S
    laser = Transform((0.1, 0, 0.2), (0, 0, 0, 1), 0, "base_link", "laser")
    footprint = Transform((0, 0, -0.02), (0, 0, 0, 1), 0, "base_link", "base_footprint")
    messages = [TfMessage("/tf_static", start - 5 * MS_NS, [laser, footprint])]
    messages += [TfMessage("/tf_static", start - 4 * MS_NS, [laser]) for _ in range(2)]
    messages += [TfMessage("/tf_static", start - 3 * MS_NS, [footprint]) for _ in range(3)]
    for k in range(50):
        now = start + k * tick
        odom = Transform((0.001 * k, 0, 0), (0, 0, 0, 1), now, "odom", "base_link")
        wheel = Transform((0, 0.1, 0), (0, 0, math.sin(k / 20), math.cos(k / 20)), now, "base_link", "wheel")
        messages += [TfMessage("/tf", now, [odom]), TfMessage("/tf", now, [odom]), TfMessage("/tf", now, [wheel])]
    clock = [ClockMessage(start + k * tick, start + k * tick) for k in range(50)]
    return write_bag(path / "webots", messages, fmt, clock)


@pytest.mark.parametrize("fmt", [BagFormat.rosbag2_sqlite3, BagFormat.rosbag2_mcap])
def test_every_message_sent_is_counted_however_many_share_a_record_time(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat
) -> None:
    bag = _webots_resends(tmp_path, fmt)
    whole = tfx("monitor", "-b", bag, "-f", "json")
    played = tfx("monitor", "-b", bag, "--play", "--rate", "500", "-f", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    for report in (json.loads(whole.stdout), json.loads(played.stdout.splitlines()[-1])):
        publishers = {a["authority"]: a for a in report["authorities"]}
        assert publishers["/tf_static"]["messages"] == 6  # all before the first /clock, played at one time
        assert publishers["/tf"]["messages"] == 150  # three a tick, two of them identical
        assert publishers["/tf"]["rate_hz"] == pytest.approx(149 / 0.98, rel=1e-9)
        edges = {e["child"]: e for e in report["edges"]}
        assert edges["base_link"]["count"] == 50  # the samples tf2 stored: one a stamp


def _clock_heard_late(path: Path, fmt: BagFormat) -> Path:
    """A ROS 2 recording shaped as ``ros2_db3_tb3_webots_sim_clock_2025`` (where ``--play``'s first tables said
    /tf at 143, 98 and 82 msgs/s for 50, and ``+4.1 s`` for ``--start +5``): odometry at 50 Hz stamped on
    simulated time from 90 s, received 30 ms after them on the wall clock, the recorder hearing /clock (100 Hz, in
    step with the stamps) only 1.92 s after the first /tf: 96 messages whose ROS time at arrival is unknown."""
    tick, wall, sim, late = 20 * MS_NS, 1_700_000_000 * NS_PER_S, 90 * NS_PER_S, 96
    odometry = [Transform((0.01 * k, 0, 0), (0, 0, 0, 1), sim + k * tick, "odom", "base_link") for k in range(250)]
    messages = [TfMessage("/tf", wall + k * tick + 30 * MS_NS, [odom]) for k, odom in enumerate(odometry)]
    clock = [ClockMessage(wall + k * tick // 2, sim + k * tick // 2) for k in range(2 * late, 500)]
    return write_bag(path / "late_clock", messages, fmt, clock)


@pytest.mark.parametrize("fmt", [BagFormat.rosbag2_sqlite3, BagFormat.rosbag2_mcap])
def test_messages_before_the_first_clock_are_timed_in_the_replay_as_in_the_whole_read(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat
) -> None:
    """Played at /clock's first value, the 96 messages recorded before it were 147 messages in 1 s of the
    replay; as in the whole read, their ROS time at arrival is unknown: not a rate, not a delay."""
    bag = _clock_heard_late(tmp_path, fmt)
    played = tfx("monitor", "-b", bag, "--play", "--rate", "500", "--end", "+2.92", "-f", "json")
    whole = tfx("monitor", "-b", bag, "--end", "+2.92", "-f", "json")
    assert played.code == 0 and whole.code == 0, played.stderr + whole.stderr
    for report in (json.loads(played.stdout.splitlines()[-1]), json.loads(whole.stdout)):
        assert report["window"]["end"] == pytest.approx(92.92)
        (tf,) = (a for a in report["authorities"] if a["authority"] == "/tf")
        assert tf["messages"] == 145  # 96 before /clock, 49 arrived on it by 92.92 s (30 ms after their stamps)
        assert tf["rate_hz"] == pytest.approx(50.0, rel=0.02)
        assert tf["delay_max_s"] == pytest.approx(0.03, abs=0.011)  # the 51 timed: not 1.92 s, /clock came late


def test_play_counts_its_header_seconds_from_the_first_stamp_as_start_does(tfx: Tfx, tmp_path: Path) -> None:
    """``+S`` is after the first tf stamp, in ``--start`` and in the replay's header alike (it counted from the
    first arrival on /clock, 1.92 s later: ``--start +1`` began a table headed ``+0.1 s``)."""
    bag = _clock_heard_late(tmp_path, BagFormat.rosbag2_mcap)
    played = tfx("monitor", "-b", bag, "--play", "--rate", "500", "--start", "+3", "--end", "+4")
    assert played.code == 0, played.stderr
    headers = re.findall(r"^time ([\d.]+) \(\+([\d.]+) s\)", played.stdout, re.MULTILINE)
    assert headers and headers[-1] == ("94.000", "4.0"), played.stdout
    assert all(float(since) == pytest.approx(float(time) - 90, abs=0.06) for time, since in headers), headers


@pytest.mark.parametrize("fmt", [BagFormat.ros1, BagFormat.rosbag2_sqlite3])
def test_a_statics_only_recording_says_its_recorded_span_and_the_statics_stamps(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat
) -> None:
    """The real kth_robp_scan_statics_2024: /tf_static stamped over 0.449 s, 37 s before a 54 s recording began;
    the header said "0.449 s" as if it were the recording's."""
    start = 1_700_000_000 * NS_PER_S
    laser = Transform((0.2, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0), start, "base_link", "laser")
    camera = Transform((0.1, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0), start + 500 * MS_NS, "base_link", "camera")
    recorded = start + 30 * NS_PER_S
    messages = [
        TfMessage("/tf_static", recorded, [laser, camera], "/rsp"),
        TfMessage("/tf_static", recorded + 10 * NS_PER_S, [laser, camera], "/rsp"),  # latched again, 10 s on
    ]
    bag = write_bag(tmp_path / ("statics.bag" if fmt is BagFormat.ros1 else "statics"), messages, fmt)
    header = tfx("monitor", "-b", bag).stdout.splitlines()[0]
    assert header == (
        f"{bag}: recorded 10.000 s from 1700000030.000 to 1700000040.000; static transforms only, stamped "
        "0.500 s from 1700000000.000 to 1700000000.500, the latest 29.5 s before recording began"
    )
    window = tfx("monitor", "-b", bag, "--start", "1700000000", "--end", "1700000000.5").stdout.splitlines()[0]
    assert window == f"{bag}: 0.500 s from 1700000000.000 to 1700000000.500"  # a window asked for: as asked


def test_a_frame_tf2_made_static_but_sent_on_tf_is_not_a_statics_only_recording(tfx: Tfx, tmp_path: Path) -> None:
    """The real neato_urdf_beside_driver_2018 (ROS 1): base_link latched on /tf_static first, then 413 times on /tf
    by the driver; tf2 keeps base_link static, and the header said "static transforms only" of 2177 /tf messages."""
    start = 1_700_000_000 * NS_PER_S
    mount = Transform((0.0, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0), start, "base_footprint", "base_link")
    messages = [TfMessage("/tf_static", start, [mount], "/rsp")]
    for k in range(1, 11):
        odom = Transform((0.1 * k, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), start + k * 100 * MS_NS, "odom", "base_link")
        messages.append(TfMessage("/tf", start + k * 100 * MS_NS, [odom], "/driver"))
    bag = write_bag(tmp_path / "mixed.bag", messages, BagFormat.ros1)
    header = tfx("monitor", "-b", bag).stdout.splitlines()[0]
    assert header == f"{bag}: tf stamped over 0.900 s from 1700000000.100 to 1700000001.000"  # the stamps' span


def _late_odometry(tmp_path: Path) -> Path:
    """odom -> base_link at 10 Hz from 1700000000.0 over 0.9 s, each arriving 50 ms after its stamp."""
    start = 1_700_000_000 * NS_PER_S
    messages = []
    for k in range(10):
        odom = Transform((0.1 * k, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), start + k * 100 * MS_NS, "odom", "base_link")
        messages.append(TfMessage("/tf", start + k * 100 * MS_NS + 50 * MS_NS, [odom], "/driver"))
    return write_bag(tmp_path / "late.bag", messages, BagFormat.ros1)


def test_a_chain_asked_without_a_window_says_the_stamps_span_as_all_frames_do(tfx: Tfx, tmp_path: Path) -> None:
    """The real create3 (ros2_db3_create3_real_two_urdfs): `monitor odom base_link` said "50.902 s from
    1663967370.849 to 1663967421.751", its first stamp to the recording's last record time (the chain's delays are
    counted to the recording's clock), beside "tf stamped over 50.850 s" for all frames. One span for both; a
    window asked for is still said as asked."""
    bag = _late_odometry(tmp_path)
    whole = tfx("monitor", "-b", bag).stdout.splitlines()[0]
    chain = tfx("monitor", "odom", "base_link", "-b", bag).stdout.splitlines()[0]
    assert whole == chain == f"{bag}: tf stamped over 0.900 s from 1700000000.000 to 1700000000.900"
    window = tfx("monitor", "odom", "base_link", "-b", bag, "--end", "1700000000.5").stdout.splitlines()[0]
    assert window == f"{bag}: 0.500 s from 1700000000.000 to 1700000000.500"


def test_a_chain_asked_without_a_window_has_none_in_json(tfx: Tfx, tmp_path: Path) -> None:
    """`monitor A B --format json` gave "window": {"start": null, "end": <the record end>} where no window was asked
    (its chain's delays are counted to then): null/null, as without a chain and as the text's header says; a window
    asked for is still given as asked."""
    bag = _late_odometry(tmp_path)
    chain = json.loads(tfx("monitor", "odom", "base_link", "-b", bag, "--format", "json").stdout)
    assert chain["window"] == {"start": None, "end": None}
    assert chain["chain"]["net_delay_mean_s"] is not None  # still counted to the recording's clock
    asked = tfx("monitor", "odom", "base_link", "-b", bag, "--end", "1700000000.5", "--format", "json").stdout
    assert json.loads(asked)["window"]["end"] == pytest.approx(1_700_000_000.5)


def test_an_edge_sent_once_has_no_rate_jitter_or_gap(tfx: Tfx, tmp_path: Path) -> None:
    """A marker detected once (DIGIT_works' camera -> marker_367): '-' for its rate, jitter and largest gap, which one
    sample does not have, not 0.00 and 0.0000; the marker seen 50 times keeps its figures."""
    result = tfx("monitor", "-b", detections_bag(tmp_path / "detections.bag"))
    assert result.code == 0, result.stderr
    once = next(line for line in result.stdout.splitlines() if "marker_367" in line).split()
    assert once[once.index("/aruco") + 1 :][:4] == ["1", "-", "-", "-"]
    many = next(line for line in result.stdout.splitlines() if "marker_0" in line).split()
    assert many[many.index("/aruco") + 1 :][:2] == ["50", "25.00"]


def test_an_edge_sent_once_has_null_rate_jitter_and_gap_in_json(tfx: Tfx, tmp_path: Path) -> None:
    """The JSON of the same: null where the table shows '-' (a 0 reads as a rate measured), figures for the marker
    seen 50 times."""
    result = tfx("monitor", "-b", detections_bag(tmp_path / "detections.bag"), "--format", "json")
    assert result.code == 0, result.stderr
    edges = {e["child"]: e for e in json.loads(result.stdout)["edges"]}
    once = edges["marker_367"]
    assert (once["rate_hz"], once["jitter_s"], once["gap_max_s"], once["gap_start"]) == (None, None, None, None)
    assert edges["marker_0"]["rate_hz"] == pytest.approx(25.0) and edges["marker_0"]["jitter_s"] is not None


def test_a_marker_seen_in_bursts_shows_its_rate_within_them_in_text_and_json(tfx: Tfx, tmp_path: Path) -> None:
    """A marker seen 10 times 40 ms apart, then lost 0.6 s, 10 times (DIGIT_works' marker_222, seen 58% of the
    time): the table's rate is over the whole window; a line and the JSON say the rate within its bursts and
    the share of the time it was seen, as wtf's rate finding does (``figures.sightings``)."""
    stamps = [1_000_000_000 + (b * 1000 + i * 40) * MS_NS for b in range(10) for i in range(10)]
    seen = [Transform((1.0, 0, 0), (0, 0, 0, 1.0), s, "camera", "marker_5") for s in stamps]
    bag = write_bag(tmp_path / "bursts.bag", [TfMessage("/tf", t.stamp + MS_NS, [t], "/aruco") for t in seen])
    text = tfx("monitor", "-b", bag).stdout
    said = (
        "camera -> marker_5: a detection, seen in 10 bursts, at 25.0 Hz within them, 38% of the time from its first "
        "sighting to its last"
    )
    assert said + " (unseen for up to 0.640 s)" in " ".join(text.split()), text
    (edge,) = json.loads(tfx("monitor", "-b", bag, "--format", "json").stdout)["edges"]
    assert edge["sightings"]["bursts"] == 10 and edge["sightings"]["rate_hz"] == pytest.approx(25.0)
    assert edge["sightings"]["seen_share"] == pytest.approx(3.6 / 9.36)


def test_a_publishers_delay_over_some_of_its_edges_says_which(tfx: Tfx, tmp_path: Path) -> None:
    """One /tf of a robot simulated from 100 s (no /clock) beside a device on the wall clock (the IAS0220
    course's Gazebo robot beside its IMU): the /tf row's delay is the device's alone, and says so, in text and
    JSON; the simulated edge's is not measurable."""
    bag = device_beside_simulation_bag(tmp_path / "two_clocks")
    text = " ".join(tfx("monitor", "-b", bag).stdout.split())
    assert "/tf: delay of range alone; not measurable for base_link" in text, text
    (tf,) = [a for a in json.loads(tfx("monitor", "-b", bag, "--format", "json").stdout)["authorities"]
             if a["authority"] == "/tf"]  # fmt: skip
    assert (tf["delay_of"], tf["no_delay_of"]) == (["range"], ["base_link"])
    assert tf["delay_mean_s"] == pytest.approx(0.003)


def test_an_edge_ros1s_tf2_holds_static_has_no_delay_whole_or_replayed(tfx: Tfx, tmp_path: Path) -> None:
    """A ROS 1 bag shaped as the Neato beside its driver: a URDF's base_link -> laser latched on /tf_static, then the
    laser sent every 50 ms on /tf too, each 20 ms after its stamp. ROS 1's tf2 holds laser static for every time
    (each /tf sample replaces its value): view-frames and report show a static edge without delay; monitor's JSON
    gave it 0.020 s. The edge has no delay now, whole and replayed; the publisher's is still tf_monitor's, how late
    its messages came over the link."""
    wall = 1_700_000_000 * NS_PER_S
    laser = Transform((0.1, 0, 0.2), (0, 0, 0, 1), wall - 3600 * NS_PER_S, "base_link", "laser")
    messages = [TfMessage("/tf_static", wall, [laser], "/robot_state_publisher")]
    stamps = [wall + k * 50 * MS_NS for k in range(1, 41)]
    on_tf = [Transform((0.1, 0, 0.2), (0, 0, 0, 1), stamp, "base_link", "laser") for stamp in stamps]
    messages += [TfMessage("/tf", t.stamp + 20 * MS_NS, [t], "/laser_to_base") for t in on_tf]
    bag = write_bag(tmp_path / "laser", messages, BagFormat.ros1)
    whole = tfx("monitor", "-b", bag, "-f", "json")
    played = tfx("monitor", "-b", bag, "--play", "--rate", "500", "--window", "100", "-f", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    for report in (json.loads(whole.stdout), json.loads(played.stdout.splitlines()[-1])):
        (edge,) = report["edges"]
        assert edge["static"] and edge["count"] == 41, edge
        assert (edge["delay_mean_s"], edge["delay_max_s"]) == (None, None), edge
        publishers = {a["authority"]: a for a in report["authorities"]}
        assert publishers["/laser_to_base"]["delay_mean_s"] == pytest.approx(0.020, abs=1e-6)


@pytest.mark.parametrize("sample", SAMPLES)
def test_a_recording_that_names_no_publisher_shows_its_topics_as_topics(tfx: Tfx, sample: str) -> None:
    """A ROS 2 bag names no publisher: monitor's "Node" column held /tf and /tf_static, which a ROS 2 user read as
    node names (monitor42's note, on the Webots e-puck). The columns say topic there, with a line saying why, and
    the JSON's ``publishers_named`` says which; a ROS 1 bag's nodes stay nodes. Live and replayed alike."""
    named = sample == "ros1"
    doc = json.loads(tfx("monitor", "-b", SAMPLE_BAGS[sample], "-f", "json").stdout)
    assert doc["publishers_named"] is named
    assert ({a["authority"] for a in doc["authorities"]} == {"/tf", "/tf_static"}) is not named
    text = tfx("monitor", "-b", SAMPLE_BAGS[sample]).stdout
    assert ("Topic" in text and "names no publisher" in text) is not named, text
    assert ("Node" in text and "names no publisher" not in text) is named, text
    played = tfx("monitor", "-b", SAMPLE_BAGS[sample], "--play", "--rate", "500", "-f", "json").stdout
    assert json.loads(played.splitlines()[-1])["publishers_named"] is named


@pytest.mark.parametrize("sample", ["db3", "mcap"])
def test_what_a_ros2_bag_lists_of_its_publishers_is_said_under_its_topics(tfx: Tfx, sample: str) -> None:
    """Where a ROS 2 bag names no publisher, monitor said so and stopped, though its metadata.yaml counts each
    topic's publishers (one offered QoS profile each): it says that count under the topics, and in the JSON. The
    sample's writer kept one profile for /tf_static and none for /tf: a topic listed with none is left out (its
    messages are there), not said to have no publisher."""
    doc = json.loads(tfx("monitor", "-b", SAMPLE_BAGS[sample], "-f", "json").stdout)
    assert doc["publishers_listed"] == {"/tf_static": {"publishers": 1, "in": "metadata.yaml"}}
    text = " ".join(tfx("monitor", "-b", SAMPLE_BAGS[sample]).stdout.split())
    assert "; metadata.yaml lists 1 publisher of /tf_static" in text and "of /tf " not in text, text
    played = tfx("monitor", "-b", SAMPLE_BAGS[sample], "--play", "--rate", "500", "-f", "json").stdout
    assert json.loads(played.splitlines()[-1])["publishers_listed"] == doc["publishers_listed"]
    assert json.loads(tfx("monitor", "-b", SAMPLE_BAGS["ros1"], "-f", "json").stdout)["publishers_listed"] == {}
