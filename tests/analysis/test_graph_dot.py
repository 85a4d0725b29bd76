"""The frame graph's dot source, read back through Graphviz: nodes, edges, labels, styles and colours."""

from __future__ import annotations

import itertools
import json
import os
import shutil
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import graphviz
import pytest

from tests.analysis.test_graph import END, START, healthy, publish, publish_static
from tests.cli.conftest import SAMPLE_BAGS
from tftools.analysis.edges import edge_stats
from tftools.analysis.findings import Severity
from tftools.analysis.graph import frame_graph
from tftools.analysis.wtf import Scene
from tftools.core.buffer import Buffer
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S, SimClock
from tftools.core.transform import Transform
from tftools.render.graph import COLOURS, INK, SIGNATURE, STATIC_INK, recording_legend, to_digraph
from tftools.sources import Recording, read_recording


@pytest.fixture(scope="module", autouse=True)
def dot_available() -> None:
    if shutil.which("dot") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("CI must have Graphviz's dot (apt-get install graphviz)")
        pytest.skip("Graphviz's dot is not installed")


@dataclass
class Parsed:
    graph: dict[str, Any]
    nodes: dict[str, dict[str, Any]]
    edges: dict[tuple[str, str], dict[str, Any]]


def dot_source(
    source: Buffer | Recording, *, legend: Sequence[str] = (), rankdir: str = "TB", brief: bool = False
) -> str:
    """What view-frames draws of ``source``, tfx wtf's findings in colour; the legend a recording's own."""
    if isinstance(source, Recording):
        legend = legend or recording_legend(source)
    return str(to_digraph(frame_graph(Scene(source)), legend, rankdir=rankdir, brief=brief).source)


def parse(source: str) -> Parsed:
    """The graph as Graphviz itself understands the source (attributes with their defaults applied)."""
    data = json.loads(graphviz.Source(source).pipe(format="json0"))
    objects = data["objects"]
    by_id = {o["_gvid"]: o for o in objects}
    nodes = {o["name"]: o for o in objects if "nodes" not in o}
    edges = {(by_id[e["tail"]]["name"], by_id[e["head"]]["name"]): e for e in data.get("edges", [])}
    return Parsed(data, nodes, edges)


def drawn_edges(parsed: Parsed) -> dict[tuple[str, str], dict[str, Any]]:
    return {key: e for key, e in parsed.edges.items() if e.get("style") != "invis"}


def test_every_frame_and_edge_with_view_frames_labels() -> None:
    buffer = healthy()
    parsed = parse(dot_source(buffer))
    assert set(buffer.frames) <= set(parsed.nodes)
    edges = drawn_edges(parsed)
    stats = edge_stats(buffer)
    assert set(edges) == {s.key for s in stats}
    for s in stats:
        label = edges[s.key]["label"]
        assert s.authorities[0] in label
        if s.static:
            assert "static" in label and "Average rate" not in label
            continue
        for line in (
            f"Broadcaster: {s.authorities[0]}",
            f"Average rate: {s.rate_hz:.2f} Hz",
            f"Samples: {s.count}",
            f"Most recent transform: {s.last_stamp / NS_PER_S:.3f} ({(END - s.last_stamp) / NS_PER_S:.3f} s old)",
            f"Oldest transform: {s.first_stamp / NS_PER_S:.3f}",
            f"Buffer length: {(s.last_stamp - s.first_stamp) / NS_PER_S:.3f} s",
            f"Largest gap: {seconds(s.longest_interval):.3f} s",
        ):
            assert line in label


def test_static_edges_are_dashed_and_blue_and_dynamic_ones_solid() -> None:
    edges = drawn_edges(parse(dot_source(healthy())))
    for key, edge in edges.items():
        static = key[0] == "base_link"
        assert edge["style"] == ("dashed" if static else "solid"), key
        assert edge["color"] == (STATIC_INK if static else INK), key


def test_the_root_stands_out_and_the_legend_says_when_and_that_all_is_well() -> None:
    parsed = parse(dot_source(healthy(), legend=["Recorded at time: 12.5", "Bag: x.bag"]))
    assert "root" in parsed.nodes["map"]["label"]
    assert float(parsed.nodes["map"]["penwidth"]) > float(parsed.nodes["odom"]["penwidth"])
    legend = parsed.nodes["legend"]["label"]
    assert "Recorded at time: 12.5" in legend and "Bag: x.bag" in legend
    assert "5 frames, 4 transforms (2 static), 1 tree" in legend
    assert "No problems found" in legend
    assert ("legend", "map") in parsed.edges  # the legend sits above the root, as in view_frames
    assert dot_source(healthy()).startswith(f"// {SIGNATURE}")


def test_problems_are_coloured_where_they_are_and_listed_in_the_legend() -> None:
    buffer = healthy()
    publish_static(buffer, "world", "rig")  # a second tree
    publish(buffer, "base_link", "wheel", end_s=3)  # stale
    publish(buffer, "base_link", "arm", hz=50, skip=(3.0, 6.0))  # a gap: warning
    buffer.set_transform(Transform((float("nan"), 0, 0), (0, 0, 0, 1), START, "base_link", "tool"), "/t")
    parsed = parse(dot_source(buffer))
    edges = drawn_edges(parsed)
    red, orange = COLOURS[Severity.error], COLOURS[Severity.warning]
    assert edges[("base_link", "wheel")]["color"] == red and "stale" in edges[("base_link", "wheel")]["label"]
    assert edges[("base_link", "arm")]["color"] == orange and "rate" in edges[("base_link", "arm")]["label"]
    assert edges[("base_link", "tool")]["style"] == "dotted" and edges[("base_link", "tool")]["color"] == red
    assert "rejected: 1 x TF_NAN_INPUT" in edges[("base_link", "tool")]["label"]
    for root in ("map", "world"):
        assert parsed.nodes[root]["color"] == red and "disconnected" in parsed.nodes[root]["label"]
    for healthy_edge in (("map", "odom"), ("odom", "base_link"), ("base_link", "laser")):
        assert edges[healthy_edge]["color"] in (INK, STATIC_INK)
    assert parsed.nodes["odom"]["color"] == INK
    legend = parsed.nodes["legend"]["label"]
    assert "3 errors, 1 warning" in legend
    assert "base_link -&gt; wheel by /node stopped at" in legend  # HTML-escaped in the source
    assert "every sample rejected" in parsed.nodes["legend_key"]["label"]


def test_brief_labels_and_rank_direction() -> None:
    parsed = parse(dot_source(healthy(), rankdir="LR", brief=True))
    assert parsed.graph["rankdir"] == "LR"
    label = drawn_edges(parsed)[("odom", "base_link")]["label"]
    assert "/node" in label and "50.0 Hz" in label
    assert "Most recent transform" not in label and "Samples" not in label


def test_awkward_frame_names_survive() -> None:
    buffer = Buffer(None, SimClock(END))
    names = ['a "quoted" frame', "x<y>&z", "back\\slash", "ünïcode"]
    publish(buffer, "root", names[0])
    for parent, child in itertools.pairwise(names):
        publish(buffer, parent, child)
    parsed = parse(dot_source(buffer))
    assert set(names) <= set(parsed.nodes)
    assert {(p, c) for p, c in itertools.pairwise(names)} <= set(parsed.edges)


def test_no_data_says_so() -> None:
    assert "No tf data received" in parse(dot_source(Buffer(None))).nodes


def test_a_recording_gives_its_span_and_files_to_the_legend() -> None:
    recording = read_recording([SAMPLE_BAGS["mcap"]])
    legend = parse(dot_source(recording)).nodes["legend"]["label"]
    start, end, span = (t / NS_PER_S for t in (recording.start, recording.end, recording.end - recording.start))
    assert f"Recorded at time: {start:.3f} to {end:.3f} ({span:.3f} s)" in legend
    assert "Bag: robot_mcap" in legend and "18 frames, 17 transforms (7 static), 1 tree" in legend
