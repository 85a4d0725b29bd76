"""Real recordings made by others (tests/corpus/manifest.json): what a correct ``tfx`` says of each.

Every expectation comes from the data: the manifest's verdicts were written by reading each
recording's stamps, record times, publishers and /clock (README.md says why), and the figures
checked here (gaps, rates, lookups) are computed from the recording by rosbags' reader, numpy
and the real tf2, never taken from tftools' own output.
"""

from __future__ import annotations

import dataclasses
import html
import itertools
import json
import math
import re
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

import tftools
from tests.cli.conftest import Result, Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus import data
from tests.corpus.fetch import Recording, shared_dir
from tests.corpus.recordings import ARCHIVES, BY_ID, RECORDINGS, WITH_TF, Corpus
from tests.oracle import ERROR_CLASSES, Row, Scenario, bag_rows, binding_time, cpp_insert, run_cpp_core, run_tf2
from tests.sources.test_stream import whole_parents
from tftools.analysis.expected import shape_of
from tftools.core.batch import concat_batches
from tftools.core.errors import TransformError
from tftools.core.time import NS_PER_S
from tftools.sources import read_recording
from tftools.sources.edge_clocks import EdgeClock
from tftools.sources.stream import SAMPLES_PER_FRAME, stream_recording
from tftools.sources.timeline import Playback

ROS1_WITH_TF = [r for r in WITH_TF if r.meta["format"] == "ros1"]
ROS2_WITH_TF = [r for r in WITH_TF if r.meta["format"] != "ros1"]
DAY_S = 86_400.0
RECORDING_SUFFIXES = (".bag", ".mcap", ".db3")
# tf2's binding rounds stamps through a double (~120 ns at epoch times): values it gives are compared to
# what 1 us of motion can change (as tests/sources/test_bags_vs_tf2.py does).
TF2_VALUE_TOLERANCE = 1e-5
# ROS 1's tf2 in C++ holds every stamp exactly, as tftools does: what may differ is the arithmetic's last bits.
CPP_TOLERANCE = 1e-12
CPP_CACHE_S = 1_000_000  # longer than any recording: tftools keeps a recording's every sample
# Our own composition of the same samples differs from tftools' only by float rounding: ROS 2's tf2 holds
# each rotation through tf2::Transform's matrix (Shepperd's branch), which over a chain of rotations
# recorded slightly off unit length (float32 sources) rounds by up to 2.5e-9 (the Husky's gripper chain);
# a wrong sample, interpolation or chain is off by far more.
COMPOSE_TOLERANCE = 1e-8


def _ids(recordings: list[Recording]) -> list[str]:
    return [r.id for r in recordings]


def _marks(test: str, recording: Recording) -> list[pytest.MarkDecorator]:
    """A strict expected failure where the entry's ``depends_on`` names ``test``: tfx today disagrees with
    what the recording's bytes prove (the reason says how, and what fixes it). It fails with the reason,
    and an unexpected pass fails too, so the line is removed with the fix; an entry is never weakened to
    match tfx's output."""
    why = recording.meta.get("depends_on", {}).get(test)
    return [pytest.mark.xfail(reason=f"tfx disagrees with the data: {why}", strict=True)] if why else []


def _cases(test: str, recordings: list[Recording]) -> list[pytest.param]:  # type: ignore[valid-type]  # its type, ParameterSet, is private
    """``recordings`` as parameters of ``test``, each marked where its entry says tfx disagrees."""
    return [pytest.param(r, id=r.id, marks=_marks(test, r)) for r in recordings]


def _run_json(tfx: Callable[..., Result], *args: str | Path) -> tuple[int, dict[str, Any]]:  # noqa: F811
    result = tfx(*args, "--format", "json")
    assert result.stdout.strip(), (
        f"tfx {' '.join(map(str, args))} printed nothing (exit {result.code}): {result.stderr}"
    )
    return result.code, json.loads(result.stdout)


def _edge_key(frames: list[str]) -> tuple[str, str]:
    return frames[0], frames[1]


def _kept(recording: Recording, samples: data.EdgeSamples) -> list[int]:
    """Which of an edge's samples tf2 stores: a moving edge's sample at a stamp already held is not
    stored again (ROS 1's tf2 ignores it, TF_REPEATED_DATA; ROS 2's takes an identical one again
    silently), and where the manifest says (``stored_samples``) a stream mixes unset stamps (0) with
    wall-clock ones, tf2's cache drops those as soon as the others come. A sample whose values are not finite
    (NaN, infinity) is refused (TF_NAN_INPUT), by both tf2s."""
    seen: set[tuple[float, ...]] = set()
    keep = []
    for i, stamp in enumerate(samples.stamps):
        if not all(math.isfinite(v) for v in samples.values[i]):
            continue
        key = (stamp,) if recording.meta["format"] == "ros1" else (stamp, *samples.values[i])
        if (key in seen and not samples.static) or (stamp == 0 and "stored_samples" in recording.meta):
            continue
        seen.add(key)
        keep.append(i)
    return keep


def _stored(recording: Recording, contents: data.Contents) -> data.Contents:
    """The samples tf2 stores (``_kept``)."""
    edges = {}
    for edge, samples in contents.edges.items():
        keep = _kept(recording, samples)
        edges[edge] = data.EdgeSamples(
            samples.static,
            [samples.stamps[i] for i in keep],
            [samples.record_times[i] for i in keep],
            [samples.values[i] for i in keep],
            samples.publishers,
            [samples.on_tf[i] for i in keep],
        )
    return dataclasses.replace(contents, edges=edges)


def _delays(report: dict[str, Any]) -> Iterator[tuple[str, dict[str, Any], float]]:
    """Each delay ``monitor --format json`` gives (edges and publishers): its key, row and value."""
    for row in [*report["edges"], *report["authorities"]]:
        for key in ("delay_mean_s", "delay_max_s"):
            if row.get(key) is not None:
                yield key, row, row[key]


# --- the manifest tells the truth about the data -----------------------------------------------


def test_manifest_is_complete() -> None:
    assert len(RECORDINGS) == len({r.id for r in RECORDINGS})
    archive_ids = {a.id for a in ARCHIVES}
    for recording in RECORDINGS:
        if recording.shared is None:
            assert recording.archive in archive_ids, recording.id
        else:  # awaiting placement in shared/: it says where it came from, so it can be placed and checked
            upstream = recording.meta.get("upstream", {})
            for key in ("repo", "commit", "path", "licence"):
                assert upstream.get(key), (recording.id, "upstream", key)
            assert len(upstream["commit"]) == 40, recording.id
            assert recording.meta.get("size"), recording.id
        assert recording.members and all(len(h) == 64 for h in recording.members.values()), recording.id
        assert any(m == recording.open or m.startswith(recording.open + "/") for m in recording.members)
        for key in ("format", "source", "description", "duration_s", "frames", "has_clock", "expected"):
            assert key in recording.meta, (recording.id, key)


@pytest.mark.parametrize("recording", _cases("test_manifest_matches_the_data", RECORDINGS))
def test_manifest_matches_the_data(recording: Recording, corpus: Corpus) -> None:
    contents = data.read_contents(corpus(recording))
    meta = recording.meta
    assert len(contents.frames) == meta["frames"]
    assert bool(contents.clock) == meta["has_clock"]  # a /clock listed without a message is none recorded
    assert "/clock" in contents.topics or not meta["has_clock"]
    duration = (contents.last_record - contents.first_record) / NS_PER_S
    assert duration == pytest.approx(meta["duration_s"], abs=0.1)
    assert set(contents.dynamic) == {tuple(e) for e in meta["dynamic_edges"]}


# --- tfx wtf: no false alarm, the real problems ------------------------------------------------


@pytest.mark.parametrize("recording", _cases("test_wtf_verdict", RECORDINGS))
def test_wtf_verdict(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The errors and warnings the entry lists, and no other (but codes the bytes leave ``uncertain``);
    the codes it says must be ``reported`` (any severity, notes too), none it rules out (``absent``)."""
    expected = recording.meta["expected"]
    uncertain = set(expected.get("uncertain", []))
    code, report = _run_json(tfx, "wtf", corpus(recording))
    (bag,) = report["bags"]
    findings = bag["findings"]
    said = {f["code"] for f in findings}
    problems = []
    for severity, listed in (("error", expected["errors"]), ("warning", expected["warnings"])):
        shown = {f["code"] for f in findings if f["severity"] == severity} - uncertain
        if shown != set(listed) - uncertain:
            problems.append(f"{severity}s: tfx {sorted(shown)}, the data {sorted(set(listed) - uncertain)}")
    if missing := set(expected.get("reported", [])) - said:
        problems.append(f"not reported at all: {sorted(missing)}")
    if ruled_out := set(expected.get("absent", [])) & said:
        problems.append(f"reported, though the data rules them out: {sorted(ruled_out)}")
    if "rate" not in uncertain:
        warned = {_edge_key(f["frames"]) for f in findings if f["severity"] == "warning" and f["code"] == "rate"}
        edges = {tuple(e) for e in expected["warned_edges"]}
        if warned != edges:
            problems.append(f"rate warnings on {sorted(warned)}, the data {sorted(edges)}")
    if code != expected["wtf_exit"]:
        problems.append(f"exit {code}, the data {expected['wtf_exit']}")
    described = "\n".join(f"  {f['severity']} {f['code']}: {f['message']}" for f in findings)
    assert not problems, (
        f"tfx wtf on {recording.id}: {'; '.join(problems)}\nwhy (the entry): {recording.meta.get('why', '')}\n"
        f"tfx said:\n{described}"
    )


def test_every_placed_recording_is_judged_by_one_entry() -> None:
    """Each recording in the shared corpus folder is reached by exactly one entry (its ``archive`` or a
    registry entry's ``shared_copy``). One placed without an entry breaks nothing: it is reported here
    (skipped, with the names) until its entry is written from its data."""
    folder = shared_dir() / "corpus"
    if not folder.is_dir():
        pytest.skip(f"no shared corpus folder at {folder} ($TFTOOLS_SHARED_DIR/corpus)")
    reached = Counter(
        place
        for r in RECORDINGS
        for place in (r.shared, (r.meta.get("shared_copy") or {}).get("open"))
        if place is not None
    )
    assert not [p for p, n in reached.items() if n > 1], f"reached by more than one entry: {reached}"
    placed = {f"corpus/{p.name}" for p in folder.iterdir() if p.is_dir() or p.suffix in RECORDING_SUFFIXES}
    if unlisted := sorted(placed - set(reached)):
        pytest.skip(f"placed in {folder} without a manifest entry, so not judged yet: {', '.join(unlisted)}")


@pytest.mark.parametrize("recording", _cases("test_wtf_figures_are_plausible", WITH_TF))
def test_wtf_figures_are_plausible(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """No finding speaks of a delay, age or offset of more than a day in a recording that is fine."""
    _, report = _run_json(tfx, "wtf", corpus(recording))
    for finding in report["bags"][0]["findings"]:
        if finding["severity"] in ("note", "info"):  # a note may give an offset as observed (a replay's)
            continue
        figures = [float(x) for x in re.findall(r"(\d+(?:\.\d+)?(?:e[+-]?\d+)?) s\b", finding["message"])]
        durations = [x for x in figures if x < 1e8]  # absolute times (epoch or sim) are not durations
        assert all(x < DAY_S for x in durations), finding["message"]


@pytest.mark.parametrize("recording", _cases("test_wtf_times_are_counted_from_the_recording", WITH_TF))
def test_wtf_times_are_counted_from_the_recording(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Each moment a finding names, "(+S s)" into the tf data, lies within the recording, not decades away."""
    _, report = _run_json(tfx, "wtf", corpus(recording))
    for finding in report["bags"][0]["findings"]:
        offsets = [abs(float(x)) for x in re.findall(r"\(([+-]\d+(?:\.\d+)?) s\)", finding["message"])]
        assert all(x <= recording.meta["duration_s"] + DAY_S for x in offsets), finding["message"]


# --- tfx monitor: rates, gaps and delays as the data has them ----------------------------------


@pytest.mark.parametrize("recording", _cases("test_monitor_figures_match_the_data", WITH_TF))
def test_monitor_figures_match_the_data(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    path = corpus(recording)
    contents = _stored(recording, data.read_contents(path))
    code, report = _run_json(tfx, "monitor", "-b", path)
    assert code == 0
    edges = {(e["parent"], e["child"]): e for e in report["edges"]}
    assert set(edges) == set(contents.edges)
    for edge, samples in contents.dynamic.items():
        shown = edges[edge]
        assert shown["count"] == len(samples.stamps), edge
        if len(samples.stamps) == 1:  # no rate, no gap: null, not a 0 that reads as measured
            assert (shown["rate_hz"], shown["jitter_s"], shown["gap_max_s"]) == (None, None, None), edge
            continue
        assert shown["rate_hz"] == pytest.approx(data.stamp_rate(samples), rel=0.05), edge
        assert shown["gap_max_s"] == pytest.approx(data.largest_stamp_gap(samples), abs=1e-3), edge
    for key, row, value in _delays(report):
        assert abs(value) < DAY_S, f"{key} of {row} is not a delay: say it is unavailable"


@pytest.mark.parametrize("recording", _cases("test_monitor_counts_each_publishers_messages", ROS1_WITH_TF))
@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_monitor_counts_each_publishers_messages(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    play: bool,
) -> None:
    """A ROS 1 bag names each message's publisher: ``monitor``'s messages of one that sent only on /tf are
    its /tf messages that held a transform, refused ones (a stamp sent again, TF_REPEATED_DATA) too, read whole or
    replayed (ros1_gazebo_kobuki_repeated_stamps.bag: 166 and 160 of /gazebo's 199)."""
    path = corpus(recording)
    contents = data.read_contents(path)
    only_tf = {p: n for (topic, p), n in contents.messages.items() if topic == "/tf"}
    only_tf = {p: n for p, n in only_tf.items() if not contents.messages.get(("/tf_static", p))}
    window = ["--play", "--rate", "1000", "--window", str(int(recording.meta["duration_s"]) + 10)] if play else []
    result = tfx("monitor", "-b", path, *window, "--format", "json")
    assert result.code == 0, result.stderr
    report = json.loads(result.stdout.splitlines()[-1] if play else result.stdout)
    shown = {a["authority"]: a["messages"] for a in report["authorities"]}
    # A node that sent only empty messages (a real PR2's /dynamic_tf_publisher, 13 of them) sent no transform:
    # tf_monitor lists no such authority, nor does monitor
    assert {p: shown.get(p, 0) for p in only_tf} == only_tf


@pytest.mark.parametrize("recording", _cases("test_monitor_counts_tf_static_messages", ROS2_WITH_TF))
def test_monitor_counts_tf_static_messages(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A ROS 2 recording names no publisher: ``monitor``'s publishers are its tf topics; /tf_static's messages
    are every one that held a transform, whatever tf2 then kept (ros2_db3_jetacker_slam_toolbox_static_map: its
    second /tf_static message, a map -> odom ROS 2's tf2 replaced by /tf's, was not counted: 1 of 2)."""
    _assert_tf_static_messages(recording, corpus, tfx, play=False)


@pytest.mark.parametrize("recording", _cases("test_monitor_counts_tf_static_messages_replayed", ROS2_WITH_TF))
def test_monitor_counts_tf_static_messages_replayed(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """As ``test_monitor_counts_tf_static_messages``, with ``--play`` (the JetAcker's static map -> odom, played
    before the replay clock's 0, was taken for a message of unknown time: 0 of 2)."""
    _assert_tf_static_messages(recording, corpus, tfx, play=True)


def _assert_tf_static_messages(recording: Recording, corpus: Corpus, tfx: Callable[..., Result], play: bool) -> None:  # noqa: F811
    path = corpus(recording)
    contents = data.read_contents(path)
    sent = {topic.lstrip("/"): n for (topic, _), n in contents.messages.items() if n and "static" in topic}
    result = _monitored(recording, path, tfx, play)
    if result is None:
        return
    report = json.loads(result.stdout.splitlines()[-1] if play else result.stdout)
    shown = {a["authority"].lstrip("/"): a["messages"] for a in report["authorities"] if "static" in a["authority"]}
    assert shown == sent


@pytest.mark.parametrize("recording", _cases("test_monitor_counts_every_message_sent", WITH_TF))
@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_monitor_counts_every_message_sent(recording: Recording, corpus: Corpus, tfx: Tfx, play: bool) -> None:  # noqa: F811
    """Each publisher's messages (a ROS 2 recording's: each tf topic's) are every message that held a transform,
    on every topic, however many share a record time, read whole or replayed (evo-nav2-turtlebot-mcap: 5,406
    of 5,422 /tf messages, two logged at one time counted once; ros2-webots-epuck --play: 780 of 1,028)."""
    path = corpus(recording)
    sent: dict[str, int] = {}
    for (_, publisher), n in data.read_contents(path).messages.items():
        if n:
            sent[publisher.lstrip("/")] = sent.get(publisher.lstrip("/"), 0) + n
    result = _monitored(recording, path, tfx, play)
    if result is None:
        return
    report = json.loads(result.stdout.splitlines()[-1] if play else result.stdout)
    assert {a["authority"].lstrip("/"): a["messages"] for a in report["authorities"]} == sent


def _monitored(recording: Recording, path: Path, tfx: Callable[..., Result], play: bool) -> Result | None:  # noqa: F811
    """``tfx monitor --format json`` read whole or replayed fast; None where the entry says the recording cannot
    be replayed (``"replayable": false``: record times that are no clock), which --play then says in one line."""
    window = ["--play", "--rate", "1000", "--window", str(int(recording.meta["duration_s"]) + 10)] if play else []
    result = tfx("monitor", "-b", path, *window, "--format", "json")
    if play and recording.meta["expected"].get("replayable", True) is False:
        assert result.code == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
        return None
    assert result.code == 0, result.stderr
    return result


@pytest.mark.parametrize("recording", _cases("test_monitor_delays_are_never_negative", WITH_TF))
def test_monitor_delays_are_never_negative(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """A transform arrives after its stamp: a delay below 0 is a clock read wrong (say how coarse it is),
    but where the data puts stamps ahead of their arrival (``stamps_ahead_s``: a publisher's clock ahead of
    the recorder's, tf1's static_transform_publisher post-dating by its period), no further than that."""
    _, report = _run_json(tfx, "monitor", "-b", corpus(recording))
    ahead = recording.meta.get("stamps_ahead_s", 0.0)
    for key, row, value in _delays(report):
        assert value >= -ahead, f"{key} of {row} is negative (the data puts stamps at most {ahead} s ahead)"


@pytest.mark.parametrize("recording", _cases("test_wtf_span_is_the_recordings", RECORDINGS))
def test_wtf_span_is_the_recordings(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The record span is the recording's, never counted from 1970 (a time left 0 is unset)."""
    _, report = _run_json(tfx, "wtf", corpus(recording))
    (bag,) = report["bags"]
    assert bag["end"] - bag["start"] == pytest.approx(recording.meta["duration_s"], abs=0.1), bag


@pytest.mark.parametrize("recording", _cases("test_gap_is_the_same_in_wtf_and_monitor", WITH_TF))
def test_gap_is_the_same_in_wtf_and_monitor(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    path = corpus(recording)
    _, monitor = _run_json(tfx, "monitor", "-b", path)
    _, wtf = _run_json(tfx, "wtf", path)
    gaps = {(e["parent"], e["child"]): e["gap_max_s"] for e in monitor["edges"]}
    for finding in wtf["bags"][0]["findings"]:
        if finding["code"] != "rate" or "longest" not in finding["message"]:
            continue
        shown = re.search(r"longest for (\d+(?:\.\d+)?) s", finding["message"])
        assert shown, finding["message"]
        edge = _edge_key(finding["frames"])
        assert float(shown.group(1)) == pytest.approx(gaps[edge], abs=0.05), (finding["message"], gaps[edge])


def _report_page(tfx: Callable[..., Result], path: Path, out: Path) -> tuple[dict[str, Any], dict[str, str]]:  # noqa: F811
    """``tfx report``'s page for ``path``: its data (the timelines) and each edge's line of figures, by name."""
    result = tfx("report", "-b", path, "-o", out)
    assert result.code in (0, 1), result.stderr
    page = out.read_text()
    found = re.search(r'<script type="application/json" class="report-data">(.*?)</script>', page, re.S)
    assert found, "the page holds no data"
    rows = re.findall(r'<div class="label"><b>(.*?) &#8594; (.*?)</b><small>(.*?)</small>', page)
    about = {f"{html.unescape(a)} -> {html.unescape(b)}": html.unescape(line) for a, b, line in rows}
    assert len(about) == len(json.loads(found.group(1))["edges"]), "an edge of the data has no line of figures"
    return json.loads(found.group(1)), about


@pytest.mark.parametrize("recording", _cases("test_figures_agree_across_commands", WITH_TF))
def test_figures_agree_across_commands(recording: Recording, corpus: Corpus, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """An edge's rate, longest interval, pauses and delay, as ``monitor``, ``frames``, ``wtf`` and ``report``
    show them, are one figure each (``core.figures``): only their rounding differs."""
    path = corpus(recording)
    _, monitor = _run_json(tfx, "monitor", "-b", path)
    _, frames = _run_json(tfx, "frames", "-b", path)
    _, wtf = _run_json(tfx, "wtf", path)
    data, about = _report_page(tfx, path, tmp_path / "report.html")
    edges = {(e["parent"], e["child"]): e for e in monitor["edges"]}
    one_parent = {f["frame"]: f for f in frames["frames"] if len(f["parents"]) == 1}
    timelines = {e["name"]: e for e in data["edges"]}
    checked = 0
    for (parent, child), e in edges.items():
        name = f"{parent} -> {child}"
        if e["static"]:  # no rate, jitter, gap or silence: null, not 0.0 ("a rate of zero", "just arrived")
            assert [e[k] for k in ("rate_hz", "jitter_s", "gap_max_s", "gap_start", "silent_s")] == [None] * 5, name
            if child in one_parent and one_parent[child]["static"]:
                assert one_parent[child]["rate_hz"] is None, name
        if e["static"] or name not in timelines:
            continue
        if child in one_parent:
            assert one_parent[child]["rate_hz"] == e["rate_hz"], name
        line, timeline = about[name], timelines[name]
        if e["count"] == 1:
            assert e["rate_hz"] is None and line.startswith("1 sample: no rate, no gap"), line
        else:
            assert f"{e['rate_hz']:.1f} Hz, {e['count']} samples, largest gap {e['gap_max_s']:.3f} s" in line, line
        drawn = 0 if "not drawn: " in line else e["count"]  # on a clock no time of the axis places, said so
        assert sum(timeline["samples"]) == drawn, name
        delays = [(d, n) for d, n in zip(timeline["delayMean"], timeline["samples"], strict=True) if d is not None]
        if e["delay_mean_s"] is None:
            assert not delays, name  # no delay in one command is no delay in the others, nor its reason
            reason = f"delay {e['delay_unmeasurable']}" if e["delay_unmeasurable"] else None
            assert (reason in line) if reason else "delay" not in line, (line, reason)
        else:
            assert f"delay {e['delay_mean_s'] * 1000:.1f} ms (max {e['delay_max_s'] * 1000:.1f})" in line, line
            if sum(n for _, n in delays) == e["count"]:  # every sample has a delay: the bins' mean is the mean
                mean_ms = sum(d * n for d, n in delays) / e["count"]
                assert mean_ms == pytest.approx(e["delay_mean_s"] * 1000, rel=1e-3), name
        if timeline["gaps"] and "placed at arrival" not in line:  # the longest pause shaded: the longest interval
            start, end = max(timeline["gaps"], key=lambda g: g[1] - g[0])
            assert end - start == pytest.approx(e["gap_max_s"], abs=2e-6), name
        checked += 1
    assert checked == len(timelines), "an edge of the page is not one of monitor's"
    for finding in wtf["bags"][0]["findings"]:  # wtf's pauses: the longest is monitor's longest interval
        said = re.search(  # a detection's said as unseen (``detections``): its pauses among its times unseen
            r"(?:silent|unseen) (?:\d+ times, )?(\d+|once) (?:times? |of them )?.*the longest for (\d+(?:\.\d+)?) s "
            r"from (\d+(?:\.\d+)?)",
            finding["message"],
        )
        if finding["code"] == "rate" and said:
            e = edges[_edge_key(finding["frames"])]
            assert float(said.group(2)) == pytest.approx(e["gap_max_s"], abs=0.05), finding["message"]
            assert float(said.group(3)) == pytest.approx(e["gap_start"], abs=1e-3), finding["message"]
            name = f"{finding['frames'][0]} -> {finding['frames'][1]}"
            shaded = timelines[name]["gaps"]
            pauses = 0 if "not drawn: " in about[name] else 1 if said.group(1) == "once" else int(said.group(1))
            assert len(shaded) == pauses, finding["message"]


# --- tfx view-frames ---------------------------------------------------------------------------


@pytest.mark.parametrize("recording", _cases("test_view_frames", RECORDINGS))
def test_view_frames(recording: Recording, corpus: Corpus, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    out = tmp_path / "frames.svg"
    result = tfx("view-frames", "-b", corpus(recording), "-o", out)
    assert result.code == recording.meta["expected"]["view_frames_exit"], result.stdout + result.stderr
    if result.code == 2:
        assert "no transforms" in result.stderr and len(result.stderr.strip().splitlines()) == 1
        return
    svg = html.unescape(out.read_text())  # graphviz writes "-" as "&#45;"
    for frame in data.read_contents(corpus(recording)).frames:
        assert f">{frame}<" in svg, frame
    ages = [float(x) for x in re.findall(r"(\d+(?:\.\d+)?(?:e[+-]?\d+)?) s old", svg)]
    assert all(age < DAY_S for age in ages), f"ages of more than a day drawn: {sorted(ages)[-3:]}"
    assert not re.search(r"-\d[\d.]* s old", svg), "a negative age drawn"
    moving = data.read_contents(corpus(recording)).dynamic  # ages and stamps ahead are drawn on moving edges
    if "stamps_ahead_s" in recording.meta and moving:  # a clock ahead of the recorder's: said so, within the figure
        ahead = [float(x) for x in re.findall(r"stamped (\d+\.\d+) s ahead of ", svg)]
        assert ahead and max(ahead) <= recording.meta["stamps_ahead_s"], svg


# --- tfx echo --at +1 --------------------------------------------------------------------------

ECHO_CASES = [
    pytest.param(r, pair, id=f"{r.id}-{pair[0]}-{pair[1]}", marks=_marks("test_echo_one_second_in", r))
    for r in WITH_TF
    for pair in r.meta["expected"]["echo"]
]


@pytest.mark.parametrize(("recording", "pair"), ECHO_CASES)
def test_echo_one_second_in(recording: Recording, pair: list[str], corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """``--at +1`` is a second into the tf data of the frames asked about, on their own time base (a tree
    may hold two clocks), whose first second every one of these covers."""
    path = corpus(recording)
    target, source = pair
    result = tfx("echo", target, source, "-b", path, "--at", "+1", "--format", "json")
    assert result.code == 0, result.stdout + result.stderr
    shown = json.loads(result.stdout)
    contents = _stored(recording, data.read_contents(path))
    chain = {*data.chain_edges(contents, target), *data.chain_edges(contents, source)}
    moving = [min(contents.edges[e].stamps) for e in chain if e in contents.dynamic]
    # a chain all in static caches (ROS 1's tf2 keeps a frame first sent on /tf_static static): its /tf samples;
    # statics only (a real KTH robot's sensor mounts): they hold at every time, +1 counts from their stamps
    sent = [
        t for e in chain for t, on_tf in zip(contents.edges[e].stamps, contents.edges[e].on_tf, strict=True) if on_tf
    ]
    start = min(moving) if moving else min(sent) if sent else min(min(contents.edges[e].stamps) for e in chain)
    assert start <= shown["stamp_ns"] <= start + int(1.5 * NS_PER_S), (shown["stamp_ns"], start)
    translation, rotation = _reference(recording, contents, path, target, source, shown["stamp_ns"])
    np.testing.assert_allclose(shown["translation"], translation, atol=TF2_VALUE_TOLERANCE)
    np.testing.assert_allclose(_same_sign(shown["rotation"], rotation), rotation, atol=TF2_VALUE_TOLERANCE)


def _same_sign(q: Sequence[float], like: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    q_arr = np.asarray(q, np.float64)
    return -q_arr if float(np.dot(q_arr, like)) < 0 else q_arr


def _reference(
    recording: Recording, contents: data.Contents, path: Path, target: str, source: str, time: int
) -> tuple[np.ndarray, np.ndarray]:
    """The real tf2's answer (ROS1), else our own composition of the samples (ROS2)."""
    if recording.meta["format"] != "ros1":
        return data.lookup(contents, target, source, time)
    sec, nsec = divmod(binding_time(time), NS_PER_S)
    (result,) = run_tf2([Scenario(bag=str(path), queries=[["lookup", target, source, sec, nsec]])])
    (answer,) = result["answers"]
    assert answer["ok"], answer
    return np.asarray(answer["t"]), np.asarray(answer["q"])


# --- lookups: the real tf2 (ROS1), ROS 2's semantics (ROS2) ------------------------------------


def _cpp_tolerance(contents: data.Contents) -> float:
    """How far tftools' arithmetic may stray from C++ tf2's: a few of the last bits of the largest coordinate
    composed (its order of operations differs: a car's UTM positions, 5.8e6 m, cancel to 4.36 m 2e-9 apart)."""
    largest = max((abs(v) for s in contents.edges.values() for row in s.values for v in row[:3]), default=0.0)
    return max(CPP_TOLERANCE, 1e-15 * largest)


def _tf2_queries(contents: data.Contents, pairs: list[list[str]]) -> list[Row]:
    """Lookups at 150 times over the tf data (the moving edges', else the statics' stamps) and a second
    either side (a quarter of the data's span, if shorter: most inside it), and the latest (time 0). Where
    those stamps span longer than the recording lasted (two clocks: a replay a week behind live nodes), over
    the stamps of the edges between the frames asked about, on their own clock."""
    samples = list(contents.dynamic.values() or contents.edges.values())
    first = min(min(s.stamps) for s in samples)
    last = max(max(s.stamps) for s in samples)
    if last - first > contents.last_record - contents.first_record + NS_PER_S:
        chains = {e for a, b in pairs for e in set(data.chain_edges(contents, a)) ^ set(data.chain_edges(contents, b))}
        samples = [contents.dynamic[e] for e in chains if e in contents.dynamic] or samples
        first, last = min(min(s.stamps) for s in samples), max(max(s.stamps) for s in samples)
    margin = min(NS_PER_S, (last - first) // 4) if last > first else NS_PER_S
    rng = np.random.default_rng(21)
    # A ROS time is never below 0 (rospy refuses one): a recording starting under a second into simulated
    # time is asked from 1 ns on (0 is "the latest").
    asked = np.maximum(rng.integers(first - margin, last + margin, 150), 1)
    times = np.concatenate([asked, [first, last, 0]])
    return [["lookup", a, b, *divmod(int(t), NS_PER_S)] for a, b in pairs for t in times]


@pytest.mark.parametrize("recording", _cases("test_ros1_lookups_match_tf2", ROS1_WITH_TF))
@pytest.mark.usefixtures("tf2_available", "tf2_cpp")
def test_ros1_lookups_match_tf2(recording: Recording, corpus: Corpus) -> None:
    """Lookups over the recording, answered as ROS 1's tf2 in C++ answers them (a roscpp node: Debian's
    libtf2 fed the transforms rosbag reads, every stamp and query time to the nanosecond): the same
    stamps, values and error texts. tf2_py would round each time through a double, which moves an answer
    where an edge turns fast: ~0.1 us on the okoslam bag's odom -> base_link, whose two publishers'
    samples a few ms apart differ by ~1 rad, moved a rotation by 1.6e-5."""
    path = corpus(recording)
    contents = data.read_contents(path)
    queries = _tf2_queries(contents, recording.meta["expected"]["lookups"])
    times = [sec * NS_PER_S + nsec for *_, sec, nsec in queries]
    lines = [cpp_insert(row) for row in bag_rows(str(path))]
    lines += [f"lookup {target} {source} {time}" for (_, target, source, *_), time in zip(queries, times, strict=True)]
    answers = [line for line in run_cpp_core(lines, cache_time_s=CPP_CACHE_S)[0] if line not in ("0", "1")]
    buffer = tftools.read_recording([path]).buffer
    tolerance = _cpp_tolerance(contents)
    answered = failed = 0
    for (_, target, source, *_), time, theirs in zip(queries, times, answers, strict=True):
        kind, *words = theirs.split(" ", 2)
        try:
            ours = buffer.lookup(target, source, time)
        except TransformError as error:
            assert kind == "E", f"{target} -> {source} at {time}: we failed ({error}), tf2 answered"
            assert [type(error).__name__, str(error)] == [ERROR_CLASSES[words[0]], words[1]]
            failed += 1
            continue
        assert kind == "T", f"{target} -> {source} at {time}: tf2 failed ({theirs}), we answered"
        stamp, *values = theirs.split()[1:]
        assert ours.stamp == int(stamp), (target, source, time)
        expected = [float.fromhex(v) for v in values]
        np.testing.assert_allclose([*ours.translation, *ours.rotation], expected, rtol=CPP_TOLERANCE, atol=tolerance)
        answered += 1
    assert answered > len(queries) // 2, (answered, failed)
    assert failed > 0 or not contents.dynamic, "no lookup outside the moving data was asked"


@pytest.mark.parametrize("recording", _cases("test_ros2_lookups_match_composed_samples", ROS2_WITH_TF))
def test_ros2_lookups_match_composed_samples(recording: Recording, corpus: Corpus) -> None:
    path = corpus(recording)
    contents = _stored(recording, data.read_contents(path))
    buffer = tftools.read_recording([path]).buffer
    checked = needed = 0
    for target, source in recording.meta["expected"]["lookups"]:
        times = data.covered_sample_times(contents, target, source, limit=200)
        midpoints = [(a + b) // 2 for a, b in itertools.pairwise(times)]
        for time in [*times, *midpoints]:
            translation, rotation = data.lookup(contents, target, source, time)
            ours = buffer.lookup(target, source, time)
            assert ours.stamp == time
            np.testing.assert_allclose(ours.translation, translation, atol=COMPOSE_TOLERANCE)
            np.testing.assert_allclose(_same_sign(ours.rotation, rotation), rotation, atol=COMPOSE_TOLERANCE)
            checked += 1
    assert checked >= needed, (checked, needed)


@pytest.mark.parametrize("recording", _cases("test_a_streamed_replay_is_the_whole_ones", WITH_TF))
def test_a_streamed_replay_is_the_whole_ones(recording: Recording, corpus: Corpus) -> None:
    """``--play`` streams: read in windows of a few hundred messages, a real recording replays the rows
    a whole read replays, on the same clock, with the same frames and timeline."""
    path = corpus(recording)
    streamed = stream_recording([path], window_messages=200)
    rows = concat_batches(list(streamed.parts()))
    whole = read_recording([path])
    transforms = whole.transforms
    assert rows.record_time.tolist() == Playback(whole.timeline).moved(transforms.record_time).tolist()
    assert rows.stamp.tolist() == transforms.stamp.tolist()
    assert [rows.frame_names[i] for i in rows.child] == [transforms.frame_names[i] for i in transforms.child]
    np.testing.assert_array_equal(rows.translation, transforms.translation)
    played = whole.timeline.played()
    assert (streamed.timeline.reference, streamed.timeline.tf_start, streamed.timeline.tf_end) == (
        played.reference,
        played.tf_start,
        played.tf_end,
    )
    pairs = zip(
        sorted(streamed.timeline.edges, key=lambda e: e.child), sorted(played.edges, key=lambda e: e.child), strict=True
    )
    for kept, every in pairs:
        _same_edge_clock(kept, every)
    assert sorted(streamed.frames) == sorted(whole.buffer.frames)
    assert streamed.parents == whole_parents(whole.buffer)  # static where tf2 keeps it static, across windows


MS = 1_000_000


def _same_edge_clock(kept: EdgeClock, every: EdgeClock) -> None:
    """A streamed frame's clock is the whole read's; its medians (and 95th percentiles) are taken from evenly
    spaced arrivals where there were more than ``SAMPLES_PER_FRAME`` (a 22-minute real recording's odometry):
    there they agree to 1% of the frame's span (stamps) and 10 ms (offsets), far below the 10 s that tell clocks
    apart; the rest is exact."""
    assert (kept.child, kept.arrivals, kept.first_stamp, kept.last_stamp, kept.last_record) == (
        every.child,
        every.arrivals,
        every.first_stamp,
        every.last_stamp,
        every.last_record,
    )
    if every.arrivals <= SAMPLES_PER_FRAME:
        assert kept == every
        return
    span, offset = (every.last_stamp - every.first_stamp) / 100, 10 * MS
    for name, near in [
        ("median_stamp", span),
        ("median_record", span),
        ("offset_record", offset),
        ("reach_record", offset),
    ]:
        assert abs(getattr(kept, name) - getattr(every, name)) <= near, (name, kept, every)
    assert (kept.offset_clock is None) == (every.offset_clock is None)
    if kept.offset_clock is not None and every.offset_clock is not None:
        assert (
            abs(kept.offset_clock - every.offset_clock) <= offset
            and abs(kept.reach_clock - every.reach_clock) <= offset
        )


# --- two GrandTour calibrations read together, and compared ------------------------------------

CALIBRATIONS = ("grandtour-calibration-2024-bag", "grandtour-calibration-2025-bag")


def _calibrations(corpus: Corpus) -> tuple[Path, Path]:
    first, second = (corpus(BY_ID[i]) for i in CALIBRATIONS)
    return first, second


def test_two_calibrations_latched_together_are_one_static_conflict(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Two robot descriptions on /tf_static at once (-b both): one finding naming both publishers, the
    edges they disagree on and how far, not one dynamic_on_static error per edge. Expected from the data:
    the edges both send, with different values (the second bag names no publisher: its topic stands in)."""
    first, second = _calibrations(corpus)
    a, b = data.read_contents(first).edges, data.read_contents(second).edges
    differ = {e for e in a.keys() & b.keys() if a[e].values[-1] != b[e].values[-1]}
    metres = max(float(np.linalg.norm(np.subtract(a[e].values[-1][:3], b[e].values[-1][:3]))) for e in differ)
    _, report = _run_json(tfx, "wtf", "-b", first, "-b", second)
    findings = report["bags"][0]["findings"]
    (conflict,) = [f for f in findings if f["code"] == "static_conflict"]
    assert not [f for f in findings if f["code"] == "dynamic_on_static"], findings
    assert conflict["count"] == len(differ) == 16
    assert set(conflict["frames"]) == {frame for e in differ for frame in e}
    assert conflict["message"].startswith(
        f"/robot_state_publisher and a publisher on /tf_static (unnamed) send different values for {len(differ)} "
    )
    assert f"{metres * 1000:.1f} mm" in conflict["message"]
    assert f"they agree on {len(a.keys() & b.keys()) - len(differ)} others" in conflict["message"]


def test_diff_of_two_calibrations_counts_no_publisher_change_for_an_unnamed_one(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The 2025 bag names no publisher (no callerids): the topic standing in for it is not a publisher change. Each
    frame in one bag only is lost, added (or beneath one lost or added, said with it: zed2i_base_link's six) or one
    side of a rename (zed_base_link is zed2i_base, 0.4 mm away)."""
    first, second = _calibrations(corpus)
    result = tfx("diff", first, second, "--format", "json")
    found = json.loads(result.stdout)["differences"]
    changes = [d["change"] for d in found]
    assert result.code == 1 and "publishers" not in changes
    a, b = data.read_contents(first), data.read_contents(second)
    renamed = changes.count("renamed")

    def absent(change: str) -> int:  # each frame lost or added, and those beneath it said with it
        return sum(1 + len(d["said_with"]) for d in found if d["change"] == change)

    assert absent("lost") + renamed == len(a.frames - b.frames)
    assert absent("added") + renamed == len(b.frames - a.frames)


@pytest.mark.parametrize("recording", _cases("test_an_edges_publishers_are_those_its_bytes_name", ROS1_WITH_TF))
def test_an_edges_publishers_are_those_its_bytes_name(recording: Recording, corpus: Corpus) -> None:
    """What ``tfx diff`` and ``wtf --init`` say of each edge's publishers: the callerids of the connections that
    sent that parent -> child, read by another reader (ros1-neato-urdf-beside-driver-2018-bag: odom -> base_link
    was said to be /robot_state_publisher's too, which sent base_footprint -> base_link only)."""
    path = corpus(recording)
    contents = data.read_contents(path)
    shape = shape_of(read_recording([path]))
    named = [f for f in shape.frames.values() if f.parent is not None and f.publishers is not None]
    for frame in named:
        assert set(frame.publishers or ()) == contents.edges[(frame.parent or "", frame.frame)].publishers, frame.frame
