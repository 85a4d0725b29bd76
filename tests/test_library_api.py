"""The library is the product: each command's work is one public call, whose result, rendered, is what
``tfx COMMAND --format json`` prints (the command line only parses and renders); the README's examples run."""

from __future__ import annotations

import importlib
import io
import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

import tftools
from tests.live import conftest as live
from tftools.core import NS_PER_S, BatchBuilder
from tftools.sources import Recording
from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.header_store import HeaderListener, HeaderStore

# the live tests' real roscore
master, ros, ros1_available = live.master, live.ros, live.ros1_available
REPO = Path(__file__).resolve().parents[1]
SAMPLE = REPO / "sample_bags"
BAGS = [str(SAMPLE / "robot.bag"), str(SAMPLE / "robot_db3"), str(SAMPLE / "robot_mcap")]

#: Each command and the one call that does its work.
CALLS = {
    "frames": "frame_tree",
    "echo": "echo",
    "monitor": "monitor",
    "view-frames": "view_frames",
    "wtf": "check_fleet",
    "filter": "filter_messages",
    "report": "report_fleet",
    "diff": "diff_trees",
    "static": "copy_with_statics",
}


#: The commands that listen to a live system without bags, and the one call that does their work there.
#: (``tfx wtf``, ``tfx report`` and ``tfx filter`` make their one call on a recording captured live:
#: ``tftools.capture_live``; ``tfx echo`` streams.)
LIVE_CALLS = {"wtf": "check", "report": "report", "filter": "filter_messages", "echo": "echo_stream"}


def tfx(*arguments: str, cwd: Path = REPO) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "tftools", *arguments],
        cwd=cwd,
        capture_output=True,
        text=True,
        env={**os.environ, "COLUMNS": "200"},
    )


def tfx_json(*arguments: str) -> Any:
    done = tfx(*arguments)
    assert done.returncode in (0, 1), done.stderr
    return json.loads(done.stdout)


def rendered(write: Any, *values: Any) -> Any:
    out = io.StringIO()
    write(*values, out)
    return json.loads(out.getvalue())


@pytest.fixture(scope="module", params=BAGS, ids=lambda p: Path(p).name)
def bag(request: pytest.FixtureRequest) -> str:
    return str(request.param)


@pytest.fixture(scope="module")
def recording(bag: str) -> Recording:
    return tftools.read_recording([bag])


def _corpus(name: str) -> str:
    from tests.corpus.fetch import shared_dir

    path = shared_dir() / "corpus" / name
    if not path.exists():
        pytest.skip(f"{name} is not in {path.parent} ($TFTOOLS_SHARED_DIR/corpus)")
    return str(path)


def test_every_command_has_its_call_in_tftools() -> None:
    from tftools.cli.commands import SUBCOMMANDS

    assert set(CALLS) == set(SUBCOMMANDS)
    for call in [*CALLS.values(), *LIVE_CALLS.values()]:
        assert call in tftools.__all__ and callable(getattr(tftools, call))


@pytest.mark.parametrize("package", ["tftools.sinks", "tftools.render"])
def test_the_other_public_packages_list_their_calls(package: str) -> None:
    module = importlib.import_module(package)
    assert [name for name in module.__all__ if getattr(module, name, None) is None] == []
    assert set(module.__all__) <= set(dir(module))


def test_frames(bag: str, recording: Recording) -> None:
    from tftools.render import frames

    called = rendered(frames.write_json, tftools.frame_tree(recording))
    assert called == tfx_json("frames", "-b", bag, "-f", "json")
    assert len(called["frames"]) == 18


def test_echo(bag: str, recording: Recording) -> None:
    from tftools.render import echo

    query = tftools.EchoQuery(
        target="map", source="gripper", rate=2, start=tftools.Offset(1), end=tftools.Offset(-3, True)
    )
    series = tftools.echo(recording, query)
    out = io.StringIO()
    echo.write_json(series, out)
    printed = tfx("echo", "map", "gripper", "-b", bag, "-r", "2", "--start", "+1", "--end", "-3", "-f", "json")
    assert out.getvalue() == printed.stdout
    assert len(series) == 22 and series.valid.all()


def test_monitor(bag: str, recording: Recording) -> None:
    from tftools.render import monitor

    report = tftools.monitor(recording, tftools.MonitorQuery(target="map", source="gripper", start=tftools.Offset(2)))
    called = rendered(monitor.write_json, report)
    assert called == tfx_json("monitor", "map", "gripper", "-b", bag, "--start", "+2", "-f", "json")
    assert report.chain is not None and report.chain.frames[0] == "gripper"


def test_monitor_refuses_a_range_outside_the_recording(recording: Recording) -> None:
    from tftools.core.errors import TimeRangeError

    with pytest.raises(TimeRangeError, match="outside the recording") as raised:
        tftools.monitor(recording, tftools.MonitorQuery(start=tftools.Offset(100)))
    assert raised.value.span == (recording.timeline.tf_start, recording.timeline.tf_end)
    assert "its tf runs from" in tfx("monitor", "-b", BAGS[0], "--start", "+100").stderr


def test_view_frames(bag: str, recording: Recording) -> None:
    from tftools.render import recording_legend, to_digraph

    graph = tftools.view_frames(recording)
    dot = to_digraph(graph, recording_legend(recording), rankdir="LR", brief=True)
    printed = tfx("view-frames", "-b", bag, "-o", "-", "-f", "dot", "--rankdir", "LR", "--brief")
    assert printed.returncode == 0, printed.stderr
    assert dot.source == printed.stdout
    assert len(graph.nodes) == 18 and not graph.findings


def test_wtf(bag: str) -> None:
    from tftools.analysis.wtf import Thresholds
    from tftools.analysis.wtf.fleet import exit_code
    from tftools.render import wtf

    reports = list(tftools.check_fleet([[bag]]))
    out = io.StringIO()
    wtf.write_json(reports, out, False, Thresholds(), exit_code(reports))
    assert json.loads(out.getvalue()) == tfx_json("wtf", bag, "-f", "json")
    assert not reports[0].failed()


def test_wtf_of_a_fleet() -> None:
    from tftools.analysis.wtf import Thresholds
    from tftools.analysis.wtf.fleet import exit_code, in_order
    from tftools.render import wtf

    groups = [[BAGS[0]], [_corpus("ros1_tb3_waffle_static.bag")], [BAGS[2]]]
    reports = in_order(groups, list(tftools.check_fleet(groups, fleet=tftools.analysis.Fleet(jobs=2))))
    out = io.StringIO()
    wtf.write_json(reports, out, False, Thresholds(), exit_code(reports))
    said = tfx_json("wtf", *(g[0] for g in groups), "-f", "json")
    assert json.loads(out.getvalue()) == said
    assert [r["paths"] for r in said["bags"]] == groups
    assert [r.failed() for r in reports] == [False, True, False] and exit_code(reports) == 1


@pytest.mark.parametrize(
    ("name", "lost"),
    [
        ("ros1_tb3_waffle_static.bag", True),
        ("ros2_db3_tb3_gazebo_walker", True),  # /imu's 6 messages stamped before any tf (its entry in the manifest)
        ("ros2_db3_tb3_gazebo_walker2", False),
    ],
)
def test_filter(name: str, lost: bool) -> None:
    from tftools.render import filter as render

    bag = _corpus(name)
    report = tftools.filter_messages(tftools.read_recording([bag], headers=()), tftools.FilterQuery())
    done = tfx("filter", "-b", bag, "-f", "json")
    assert rendered(render.write_json, report) == json.loads(done.stdout)
    assert report.streams and report.lost is lost and done.returncode == int(lost)


def test_filter_with_a_target_a_timeout_and_a_queue() -> None:
    from tftools.render import filter as render

    bag = _corpus("ros2_db3_tb3_gazebo_walker")
    problems: list[str] = []
    query = tftools.FilterQuery(
        target="/odom", sensor_topics=("/scan", "/nothere"), cache_time=2 * tftools.NS_PER_S, wait=10**8, queue=3
    )
    recording = query.reading().read([bag])
    report = tftools.filter_messages(recording, query, on_problem=problems.append)
    done = tfx("filter", "/scan", "/nothere", "-b", bag, "--target", "/odom", "--cache", "2", "--wait", "0.1",
               "--queue", "3", "-f", "json")  # fmt: skip
    assert rendered(render.write_json, report) == json.loads(done.stdout)
    assert [s.topic for s in report.streams] == ["/scan"] and report.target == "odom"
    assert problems == ["/nothere: not in the recording"]
    assert f"tfx: warning: {problems[0]}" in done.stderr


def test_filter_finds_no_sensor_data_in_the_sample() -> None:
    from tftools.analysis import NoStampedDataError

    report = tftools.filter_messages(tftools.read_recording([BAGS[0]], headers=()), tftools.FilterQuery())
    assert not report.streams and report.unchecked is not None and report.unchecked.reasons == []
    assert set(report.unchecked.topics) == {"/tf", "/tf_static"} and not report.lost
    done = tfx("filter", "-b", BAGS[0])
    assert done.returncode == 0 and "No sensor data to check" in done.stdout
    with pytest.raises(NoStampedDataError, match="no topic with a Header to check: /scan: not in the recording"):
        query = tftools.FilterQuery(sensor_topics=("/scan",))
        tftools.filter_messages(tftools.read_recording([BAGS[0]], headers=("/scan",)), query)
    assert "frame 'odm' does not exist (frames: odom" in tfx("filter", "-b", BAGS[0], "--target", "odm").stderr


def test_report(bag: str, tmp_path: Path) -> None:
    from tftools.render.report import page, recording_section

    [(index, report)] = tftools.report_fleet([[bag]])
    assert isinstance(report, tftools.analysis.RecordingReport)
    written = tmp_path / "report.html"
    done = tfx("report", "-b", bag, "-o", str(written))
    assert done.returncode == 0, done.stderr
    assert page(f"tfx report: {report.name}", [recording_section(index, report)]) == written.read_text()


def test_diff() -> None:
    from tftools.render import diff

    found = tftools.diff_trees(BAGS[0], BAGS[2], tftools.DiffQuery(translation_mm=2))
    out = io.StringIO()
    diff.write_json(found.a, found.b, found.differences, found.tolerances, 0, out)
    assert json.loads(out.getvalue()) == tfx_json("diff", BAGS[0], BAGS[2], "--tolerance-mm", "2", "-f", "json")
    assert found.tolerances.translation_mm == 2 and found.differences == []


def test_diff_against_a_tree_file_finds_a_moved_laser(tmp_path: Path) -> None:
    from tftools.render import diff

    tree = tmp_path / "tree.yaml"
    tree.write_text(
        tfx("wtf", "--init", BAGS[0]).stdout.replace("translation: [0.22, 0.0, 0.18]", "translation: [0.25, 0.0, 0.18]")
    )
    found = tftools.diff_trees(str(tree), BAGS[1])
    out = io.StringIO()
    diff.write_json(found.a, found.b, found.differences, found.tolerances, 1, out)
    assert json.loads(out.getvalue()) == tfx_json("diff", str(tree), BAGS[1], "-f", "json")
    assert [d.change.value for d in found.differences] == ["moved"]


@pytest.mark.parametrize("bag", [BAGS[0], BAGS[1]], ids=["robot.bag", "robot_db3"])
def test_static(bag: str, tmp_path: Path) -> None:
    from tftools.render import frames
    from tftools.sinks import static_transform

    suffix = ".bag" if bag.endswith(".bag") else "_db3"
    called, printed = tmp_path / f"called{suffix}", tmp_path / f"printed{suffix}"
    lidar = static_transform([0.1, 0, 0.3, 90, 0, 0], "/base_link", "lidar", degrees=True)
    copy = tftools.copy_with_statics(bag, called, tftools.StaticQuery((lidar,)))
    assert copy.path == called and copy.transforms == (tftools.sinks.checked(lidar),)
    done = tfx(
        "static", "0.1", "0", "0.3", "90", "0", "0", "/base_link", "lidar", "--deg", "-b", bag, "-o", str(printed)
    )
    assert done.returncode == 0, done.stderr
    trees = [
        rendered(frames.write_json, tftools.frame_tree(tftools.read_recording([path]))) for path in (called, printed)
    ]
    assert trees[0] == trees[1]
    lidar_frame = next(f for f in trees[0]["frames"] if f["frame"] == "lidar")
    assert lidar_frame["parent"] == "base_link"


def test_static_repair_is_the_same_call(tmp_path: Path) -> None:
    from tftools.sinks import static_transform

    called, printed = tmp_path / "called.bag", tmp_path / "printed.bag"
    copy = tftools.copy_with_statics(BAGS[0], called, tftools.StaticQuery(repair=True))
    done = tfx("static", "--repair", "-b", BAGS[0], "-o", str(printed))
    assert done.returncode == 0, done.stderr
    assert copy.path == called and called.read_bytes() == printed.read_bytes()
    statics = tftools.read_recording([BAGS[0]]).transforms
    assert len(copy.transforms) == len({int(c) for c in statics.child[statics.static]}) > 0
    with pytest.raises(ValueError, match="takes none"):
        tftools.StaticQuery((static_transform([0, 0, 0, 0, 0, 0], "a", "b"),), repair=True)


def test_static_refuses_a_frame_the_bag_has(tmp_path: Path) -> None:
    from tftools.sinks import static_transform

    laser = static_transform([0, 0, 0, 0, 0, 0, 1], "base_link", "laser")
    with pytest.raises(tftools.core.InvalidTransformError, match="already has laser") as present:
        tftools.copy_with_statics(BAGS[0], tmp_path / "copy.bag", tftools.StaticQuery((laser,)))
    assert present.value.child == "laser" and present.value.recording == BAGS[0]
    assert "tfx" not in present.value.hint and "-b" not in present.value.hint
    assert not (tmp_path / "copy.bag").exists()


def _readme_api() -> Iterator[str]:
    text = (REPO / "README.md").read_text()
    section = text.split("\n## Python API\n", 1)[1].split("\n## ", 1)[0]
    yield section.split("```python\n", 1)[1].split("```", 1)[0]


@pytest.mark.parametrize("code", list(_readme_api()))
def test_the_readmes_api_examples_run(code: str, capsys: pytest.CaptureFixture[str], monkeypatch: Any) -> None:
    monkeypatch.chdir(REPO)
    exec(compile(code, "README.md", "exec"), {})
    assert capsys.readouterr().out.split() == ["18", "28", "17", "False", "0", "0"]


class _Robot(LiveSource):
    """A live system without a network, on the wall clock: once started, a second of odom -> base_link
    at 20 Hz (x = 0 .. 19) and a static base_link -> laser; and, to a header listener, five scans in laser
    and one in a misspelt frame."""

    format = "test-live"

    def __init__(self, transforms: bool = True) -> None:
        super().__init__(None, False, None)
        self.transforms = transforms

    def start(self, on_batch: OnBatch) -> None:
        if not self.transforms:
            return
        builder, now = BatchBuilder(), self.clock.now()
        for i in range(20):
            stamp = now - (19 - i) * NS_PER_S // 20
            builder.add("odom", "base_link", stamp, (i, 0, 0), (0, 0, 0, 1), record_time=now, authority="/odometry")
        builder.add(
            "base_link", "laser", now, (0.2, 0, 0.1), (0, 0, 0, 1), static=True, record_time=now, authority="/s"
        )
        self.message_count += 21
        self._pass_on(on_batch, builder.take())

    def describe(self) -> str:
        return "a test robot"

    def close(self) -> None:
        self._closed.set()

    def header_listener(self, store: HeaderStore) -> HeaderListener:
        return _Scans(store)


class _Scans:
    def __init__(self, store: HeaderStore) -> None:
        self.store = store

    def start(self) -> None:  # the topics the store wants, as a live system's listener subscribes them
        now = self.store.clock.now()
        scans = [("/scan", now - NS_PER_S // 2 + i * NS_PER_S // 10, "laser") for i in range(5)]
        for topic, stamp, frame in [*scans, ("/scan_misspelt", now - NS_PER_S // 2, "lasr")]:
            if self.store.wants(topic):
                self.store.heard(topic, "sensor_msgs/msg/LaserScan", (stamp, frame))

    def close(self) -> None:
        pass


class _NoSensors(_Robot):
    """The robot's tf, and no topic with a header heard."""

    def header_listener(self, store: HeaderStore) -> HeaderListener:
        return _Silent()


class _Silent:
    def start(self) -> None:
        pass

    def close(self) -> None:
        pass


def test_filter_of_a_robot_heard_without_sensor_data_says_to_name_a_topic_or_listen_longer() -> None:
    """Live as on a recording of tf alone (left40): no sensor data to check is a report that says so, not an
    error; what to do is a live system's (name a topic, listen longer), not a recording's (record it)."""
    from tftools.render.filter import unchecked_in_words
    from tftools.sources.live.sensor_headers import capture_live

    query = tftools.FilterQuery()
    report = tftools.filter_messages(capture_live(_NoSensors(), 0.1, query.reading().headers), query)
    assert not report.streams and report.unchecked is not None and report.unchecked.live and not report.lost
    said = unchecked_in_words(report.unchecked)
    assert said.startswith("No sensor data to check: ") and "listen longer (--duration)" in said, said
    assert "record" not in said


def test_check_of_a_fake_robot_heard_live() -> None:
    from tftools import capture_live

    query = tftools.CheckQuery(sensor_topics=("/scan", "/nobody"))
    heard = capture_live(_Robot(), 0.1, query.sensor_topics, require_tf=False)
    checked = tftools.check(heard, query)
    assert checked.paths == ("a test robot",) and checked.transforms == 21 and checked.frames == 3
    assert checked.sensor_topics == ("/scan",) and checked.sensor_target == "odom"
    problems = heard.stamped.problems
    assert problems == ["/nobody: no message heard (is it published?)"]
    unheard = tftools.check(capture_live(_Robot(transforms=False), 0.1, require_tf=False))
    assert unheard.failed() and [f.code for f in unheard.findings] == ["no_tf"]


def test_report_of_a_fake_robot_heard_live() -> None:
    from tftools import capture_live
    from tftools.sources.live.errors import NoTransformsHeardError

    query = tftools.ReportQuery(sensor_topics=("/scan",))
    report = tftools.report(capture_live(_Robot(), 0.1, query.sensor_topics), query)
    assert report.name == "a test robot" and {n.name for n in report.graph.nodes} == {"odom", "base_link", "laser"}
    with pytest.raises(NoTransformsHeardError, match=r"no transforms on /tf, /tf_static from a test robot in 0\.1 s"):
        capture_live(_Robot(transforms=False), 0.1)


def test_filter_of_a_fake_robot_heard_loses_the_misspelt_frame() -> None:
    from tftools.analysis import NoStampedDataError
    from tftools.sources.live.sensor_headers import capture_live

    query = tftools.FilterQuery(target="/odom")
    report = tftools.filter_messages(capture_live(_Robot(), 0.1, query.reading().headers), query)
    streams = {s.topic: s for s in report.streams}
    assert report.target == "odom" and set(streams) == {"/scan", "/scan_misspelt"}
    assert streams["/scan"].messages == 5 and streams["/scan"].never == 0
    assert streams["/scan_misspelt"].reasons == {"unknown_frame": 1} and report.lost
    with pytest.raises(NoStampedDataError, match="/nobody: no message heard") as unheard:
        query = tftools.FilterQuery(sensor_topics=("/nobody",))
        tftools.filter_messages(capture_live(_Robot(), 0.1, query.reading().headers), query)
    assert unheard.value.problems == ["/nobody: no message heard (is it published?)"]  # said once, as heard
    assert unheard.value.hint.endswith("or none to check every such topic")  # not 'e.g. /scan': what was named


def test_echo_stream_of_a_fake_robot() -> None:
    from tftools.analysis import EchoSeries
    from tftools.core import Buffer

    shown: list[EchoSeries] = []

    def show(series: EchoSeries, buffer: Buffer) -> None:
        assert sorted(buffer.frames) == ["base_link", "laser", "odom"]
        shown.append(series)

    tftools.echo_stream(_Robot(), tftools.EchoQuery(target="/odom", source="laser", rate=100), show, count=3, wait=10)
    assert len(shown) == 3 and all(s.valid.all() for s in shown)
    assert shown[-1].translations[0].tolist() == pytest.approx([19.2, 0, 0.1])


def test_wait_for_transform_reminds_then_gives_up() -> None:
    from tftools.core import Buffer
    from tftools.sources.live.capture import Waiting, wait_for_transform
    from tftools.sources.live.errors import TransformNotHeardError

    buffer, reminded = Buffer(), list[Waiting]()

    def remind(waiting: Waiting) -> None:  # the transform arrives after the first reminder
        reminded.append(waiting)
        builder = BatchBuilder()
        builder.add("odom", "base_link", 1, (1, 0, 0), (0, 0, 0, 1), static=True)
        buffer.insert(builder.take())

    wait_for_transform(buffer, "odom", "base_link", on_reminder=remind, remind_every=0.01)
    assert len(reminded) == 1 and reminded[0].frames == [] and "does not exist" in reminded[0].reason
    with pytest.raises(TransformNotHeardError, match="no transform odom <- laser after") as raised:
        wait_for_transform(buffer, "odom", "laser", timeout=0)
    assert raised.value.target == "odom" and '"laser" passed to lookupTransform' in raised.value.reason


@pytest.fixture
def roscore(monkeypatch: pytest.MonkeyPatch, ros: live.Ros) -> live.Ros:
    """The live tests' real roscore (tests/live), the environment pointing at it, and tf and scans on it."""
    from tests.live.conftest import STATIC_PUBLISHER, wait_until

    monkeypatch.setenv("ROS_MASTER_URI", ros.master.uri)
    monkeypatch.setenv("ROS_HOSTNAME", "127.0.0.1")
    monkeypatch.delenv("ROS_IP", raising=False)
    ros.spawn(STATIC_PUBLISHER, "0.2", "0", "0.1", "0", "0", "0", "base_link", "laser")
    ros.node("dynamic", "/odometry", "odom", "base_link", "0", "20")
    ros.node("scan", "/laser_driver", "/scan", "laser", "10")
    wait_until(lambda: all(ros.master.publishers(t) for t in ("/tf", "/tf_static", "/scan")), 20, "the publishers")
    return ros


@pytest.mark.live
def test_the_live_calls_on_a_real_roscore(roscore: live.Ros) -> None:
    from tftools import capture_live
    from tftools.analysis import EchoSeries
    from tftools.render import filter as render
    from tftools.sources.live import open_live

    checked = tftools.check(capture_live(open_live("ros1"), 2, ["/scan"]), tftools.CheckQuery(sensor_topics=("/scan",)))
    said = json.loads(roscore.run_tfx("wtf", "--ros1", "-d", "2", "--sensor", "/scan", "-f", "json").stdout)["bags"][0]
    assert checked.paths == tuple(said["paths"]) and checked.frames == said["frames"] == 3
    assert checked.sensor_topics == ("/scan",) and not checked.failed()

    from tftools.sources.live.sensor_headers import capture_live

    query = tftools.FilterQuery(target="odom", sensor_topics=("/scan",))
    fates = tftools.filter_messages(capture_live(open_live("ros1"), 2, query.reading().headers), query)
    printed = json.loads(
        roscore.run_tfx("filter", "/scan", "--ros1", "-d", "2", "--target", "odom", "-f", "json").stdout
    )
    assert rendered(render.write_json, fates)["target"] == printed["target"] == "odom"
    [scan] = fates.streams
    assert scan.topic == "/scan" and scan.messages >= 10 and scan.never == 0

    page = tftools.report(capture_live(open_live("ros1"), 1))
    assert page.name == checked.paths[0] and {n.name for n in page.graph.nodes} == {"odom", "base_link", "laser"}

    shown: list[EchoSeries] = []
    asked = tftools.EchoQuery(target="odom", source="laser", rate=20)
    tftools.echo_stream(open_live("ros1"), asked, lambda series, _: shown.append(series), count=3, wait=20)
    assert len(shown) == 3 and all(s.valid.all() for s in shown)
    assert shown[-1].translations[0][2] == pytest.approx(0.1)  # the laser 10 cm above the base, turned about z
