"""One number per figure in every command, on every corpus recording (issue 39): each edge's samples, rate,
largest gap, silence, delays and stamps as ``monitor`` gives them, against ``frames``, ``view-frames``' labels,
``report``'s captions and timelines, and the figures ``wtf``'s findings say of the same edge; the recording's span
in ``wtf``, ``view-frames`` and ``report``; and no figure that cannot be (negative, NaN, a rate above its samples
over its span). Slow: five commands on each recording."""

from __future__ import annotations

import html
import json
import math
import re
from pathlib import Path
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording
from tests.corpus.recordings import BY_ID, RECORDINGS, Corpus

#: ``duration``'s units (core/time.py), in seconds.
UNITS = {"s": 1.0, "min": 60.0, "h": 3600.0, "days": 86400.0}
DURATION = r"(-?[\d.]+) (s|min|h|days)\b"


def _shown(said: float, value: float | None, decimals: int) -> bool:
    """Whether ``said`` is ``value`` rounded to ``decimals`` (None is said as nothing)."""
    return value is not None and abs(said - value) <= 0.51 * 10**-decimals + 1e-9 * abs(value)


def _duration_shown(number: str, unit: str, seconds: float | None) -> bool:
    """Whether ``duration``'s words (a number and a unit) are ``seconds``."""
    decimals = 3 if unit == "s" and abs(float(number)) < 1 else 1
    return seconds is not None and _shown(float(number), seconds / UNITS[unit], decimals)


#: view-frames' label lines: the figure each says, and which word of the line it is.
LABELLED = {
    "Average rate: ": ("rate", 2),
    "Samples: ": ("count", 1),
    "Most recent transform: ": ("last", 3),
    "Oldest transform: ": ("first", 2),
    "Buffer length: ": ("span", 2),
    "Largest gap: ": ("gap", 2),
    "Silent for the last ": ("silent", 4),
}


def _view_frames_labels(dot: str) -> dict[str, dict[str, float]]:
    """Each edge's figures as view-frames' label says them, by "parent -> child"."""
    ident = r'("(?:[^"\\]|\\.)*"|[^\s"]+)'

    def name(token: str) -> str:
        return token[1:-1].replace('\\"', '"').replace("\\\\", "\\") if token.startswith('"') else token

    nodes = {
        name(m.group(1)): html.unescape(m.group(2))
        for m in re.finditer(r"^\t" + ident + r" \[label=<<B>(.*?)</B>", dot, re.M)
    }
    edges = {}
    for m in re.finditer(r"^\t" + ident + " -> " + ident + r" \[label=<(.*)> ", dot, re.M):
        parent, child = (nodes.get(name(t), name(t)) for t in (m.group(1), m.group(2)))
        figures: dict[str, float] = {}
        for item in (html.unescape(re.sub(r"<[^>]+>", "", x)) for x in m.group(3).split('<BR ALIGN="LEFT"/>')):
            for prefix, (key, at) in LABELLED.items():
                word = item.split()[at] if item.startswith(prefix) and len(item.split()) > at else ""
                if re.fullmatch(r"[\d.]+", word):  # not "- (1 sample)", nor "stamped on 2 clocks, no span"
                    figures[key] = float(word)
            if static := re.fullmatch(r"static(?: \((\d+) samples\))?", item):  # "static (104 samples)"
                figures.update(static=1.0, count=float(static.group(1) or 1))
        edges[f"{parent} -> {child}"] = figures
    return edges


def _report_captions(page: str) -> tuple[dict[str, dict[str, float]], list[Any]]:
    """Each moving edge's figures as report's timeline caption says them, and the page's timelines' data."""
    captions = {}
    pattern = (
        r'<div class="row edge" data-row="(\d+)"><div class="label"><b>(.*?) &#8594; (.*?)</b><small>(.*?)</small>'
    )
    for m in re.finditer(pattern, page):
        about = html.unescape(m.group(4))
        figures: dict[str, float] = {"row": int(m.group(1)), "undrawn": float("not drawn: " in about)}
        said = re.match(r"([\d.]+) Hz, (\d+) samples, largest gap ([\d.]+) s", about)
        if said:
            figures.update(rate=float(said.group(1)), count=int(said.group(2)), gap=float(said.group(3)))
        delay = re.search(r"delay ([-\d.]+) ms \(max ([-\d.]+)\)", about)
        if delay:
            figures.update(delay_mean=float(delay.group(1)) / 1000, delay_max=float(delay.group(2)) / 1000)
        captions[f"{html.unescape(m.group(2))} -> {html.unescape(m.group(3))}"] = figures
    data = re.search(r'<script type="application/json" class="report-data">(.*?)</script>', page, re.S)
    return captions, json.loads(data.group(1))["edges"] if data else []


def _frames_edges(frames: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """``tfx frames``' JSON by "parent -> child": a frame's row, or each parent's edge of a frame that had several."""
    found = {}
    for frame in frames["frames"]:
        if frame["parent"]:
            found[f"{frame['parent']} -> {frame['frame']}"] = frame
        for edge in frame.get("edges") or []:
            found[f"{edge['parent']} -> {frame['frame']}"] = {"clocks": frame["clocks"], **edge}
    return found


def _impossible(name: str, row: dict[str, Any], clocks: int) -> list[str]:
    """The figures of ``monitor``'s row that cannot be: negative or not finite, a rate above (samples - 1) over
    the stamps' span on one clock, a gap longer than that span."""
    wrong = [
        f"{name} {key} = {row[key]}"
        for key in ("rate_hz", "jitter_s", "gap_max_s", "silent_s", "count", "delay_mean_s", "delay_max_s")
        if row.get(key) is not None and (not math.isfinite(row[key]) or (row[key] < 0 and "delay" not in key))
    ]
    count, first, last = row["count"], row["first_stamp"], row["last_stamp"]
    if clocks == 1 and row.get("rate_hz") and count > 1 and last > first:
        if row["rate_hz"] > (count - 1) / (last - first) * 1.0001:
            wrong.append(f"{name} rate {row['rate_hz']} over {count} samples in {last - first} s")
        if (row.get("gap_max_s") or 0) > last - first + 1e-6:
            wrong.append(f"{name} gap {row['gap_max_s']} longer than its span {last - first}")
    return wrong


def _findings_against(bag: dict[str, Any], edges: dict[str, dict[str, Any]]) -> list[str]:
    """The figures ``wtf``'s findings say of an edge that ``monitor`` shows too, where they differ."""
    wrong = []
    for finding in bag["findings"]:
        frames, message, code = finding["frames"], finding["message"], finding["code"]
        row = edges.get(f"{frames[0]} -> {frames[1]}") if len(frames) >= 2 else None
        if row is None:
            continue
        said: list[tuple[str, str, str, float | None]] = []  # what, number, unit, monitor's
        if code == "stale" and " stopped at " in message and "re-sent" not in message:
            m = re.search(DURATION + " before the recording ends", message)
            said += [("silence", m.group(1), m.group(2), row["silent_s"])] if m else []
        if code == "rate" and "went silent" in message:
            m = re.search("the longest for " + DURATION, message)
            said += [("longest gap", m.group(1), m.group(2), row["gap_max_s"])] if m else []
        if code == "delay":
            m = re.search("at most " + DURATION, message)
            said += [("largest delay", m.group(1), m.group(2), row["delay_max_s"])] if m else []
        if code == "static_on_dynamic":
            m = re.search(
                r"([\d.]+) times a second \((?:(\d+) stamps in )?[\d,]+ transforms? over " + DURATION, message
            )
            if m and not _shown(float(m.group(1)), row["rate_hz"], 1):
                wrong.append(f"{code}: {m.group(1)} times a second, monitor {row['rate_hz']}")
            said += [("span", m.group(3), m.group(4), row["last_stamp"] - row["first_stamp"])] if m else []
        if code == "sensor_wait":
            m = re.search(r"\(([\d.]+) Hz over all its clocks", message) or re.search(r" at ([\d.]+) Hz", message)
            if m and not _shown(float(m.group(1)), row["rate_hz"], 1):
                wrong.append(f"{code}: {m.group(1)} Hz, monitor {row['rate_hz']}: {message}")
        wrong += [
            f"{code}: {what} {number} {unit}, monitor {value}: {message}"
            for what, number, unit, value in said
            if not _duration_shown(number, unit, value)
        ]
    return wrong


#: The figures view-frames' labels and report's captions say of a moving edge, to how many decimals.
IN_LABEL = {"count": 0, "rate": 2, "gap": 3, "silent": 3, "first": 3, "last": 3, "span": 3}
IN_CAPTION = {"count": 0, "rate": 1, "gap": 3, "delay_mean": 4, "delay_max": 4}


def _differ(
    name: str,
    where: str,
    said: dict[str, float],
    figures: dict[str, Any],
    decimals: dict[str, int],
    required: set[str] | frozenset[str] = frozenset(),
) -> list[str]:
    """The ``figures`` (monitor's) that ``where`` says otherwise than rounded to its ``decimals``, or leaves out
    though ``required`` and monitor has them."""
    return [
        f"{name} {key}: monitor {figures[key]}, {where} {said.get(key)}"
        for key, places in decimals.items()
        if (
            not _shown(said[key], figures[key], places) if key in said else key in required and figures[key] is not None
        )
    ]


#: A time as report gives it, with its UTC date where it counts from the epoch.
WHEN = r"([\d.]+)(?: \([^)]*\))?"


def _recorded_span(bag: dict[str, Any], dot: str, facts: str) -> list[str]:
    """Where view-frames' legend and report's facts give another span than wtf: its record span (``start`` to
    ``end``), or where the record times are no clock, tf's stamps' (``stamped``), said to be theirs as wtf says it."""
    if bag["stamped"] is None:
        first, last = bag["start"], bag["end"]
        said = {
            "view-frames": re.search(r"Recorded at time: ([\d.]+) to ([\d.]+) \(([\d.]+) s\)", dot),
            "report": re.search(rf"Recorded\|+{WHEN} to {WHEN} \(([\d.]+) s", facts),
        }
        groups = (1, 2, 3)
    else:
        first, last = bag["stamped"]["start"], bag["stamped"]["end"]
        over = rf"tf stamped over ([\d.]+) s from {WHEN} to {WHEN} \(the record times are no clock\)"
        said = {"view-frames": re.search(over, dot), "report": re.search(rf"Recorded\|+{over}", facts)}
        groups = (2, 3, 1)
    figures = dict(zip(groups, (first, last, last - first), strict=True))
    return [
        f"recorded span: wtf {first} to {last}, {where} {m and m.group(0)}"
        for where, m in said.items()
        if m is None or not all(_shown(float(m.group(i)), v, 3) for i, v in figures.items())
    ]


def _compare(tfx: Tfx, path: Path, out: Path) -> list[str]:  # noqa: F811
    """Every figure that differs between the commands on the recording at ``path``."""
    watched = tfx("monitor", "-b", path, "-f", "json")
    if watched.code == 2 and "tfx: error: " in watched.stderr:
        return []  # no transforms, or a recording tfx cannot open: one line says so (tests/corpus/test_corpus.py)
    monitor = json.loads(watched.stdout)
    frames = _frames_edges(json.loads(tfx("frames", "-b", path, "-f", "json").stdout))
    (bag,) = json.loads(tfx("wtf", "-b", path, "--format", "json").stdout)["bags"]
    tfx("view-frames", "-b", path, "-o", out / "tree.gv", "--format", "dot")
    labels = _view_frames_labels((out / "tree.gv").read_text())
    tfx("report", "-b", path, "-o", out / "page.html")
    page = (out / "page.html").read_text()
    captions, timelines = _report_captions(page)
    wrong = []
    wrong += _recorded_span(bag, (out / "tree.gv").read_text(), html.unescape(re.sub(r"<[^>]+>", "|", page)))
    edges = {f"{row['parent']} -> {row['child']}": row for row in monitor["edges"]}
    for name, row in edges.items():
        frame = frames.get(name)
        if frame is None:
            wrong.append(f"{name}: not in frames")
            continue
        wrong += _impossible(name, row, frame.get("clocks", 1))
        wrong += [
            f"{name} {key}: monitor {row[key]}, frames {frame[key]}"
            for key in ("count", "rate_hz", "first_stamp", "last_stamp")
            if row[key] != frame[key]
        ]
        figures = {
            "count": row["count"],
            "rate": row["rate_hz"],
            "gap": row["gap_max_s"],
            "silent": row["silent_s"],
            "first": row["first_stamp"],
            "last": row["last_stamp"],
            "span": row["last_stamp"] - row["first_stamp"],
            "delay_mean": row["delay_mean_s"],
            "delay_max": row["delay_max_s"],
        }
        label = labels.get(name)
        if label is None:
            wrong.append(f"{name}: not in view-frames")
        elif row["static"] != bool(label.get("static")):
            wrong.append(f"{name}: static {row['static']} in monitor, {bool(label.get('static'))} in view-frames")
        elif not row["static"]:
            # each figure monitor has is on the label, but a span on two clocks ("stamped on 2 clocks, no span")
            wrong += _differ(name, "view-frames", label, figures, IN_LABEL, required=set(IN_LABEL) - {"span"})
        else:
            # static to tf2, some sent on /tf too (ROS 1's tf2 holds a frame first on /tf_static static for every
            # time: the agv's lasers): its samples, and no delay, as view-frames and report show none
            wrong += _differ(name, "view-frames", label, figures, {"count": 0}, required={"count"})
            wrong += [
                f"{name} {key}: monitor {row[key]}, static" for key in ("delay_mean_s", "delay_max_s") if row[key]
            ]
        caption = captions.get(name)
        if row["static"] and caption is not None:
            wrong.append(f"{name}: static in monitor, a timeline in report")
        if row["static"] or caption is None:
            wrong += [] if row["static"] or not captions else [f"{name}: no timeline in report"]
            continue
        wrong += _differ(name, "report", caption, figures, IN_CAPTION)
        binned = sum(n or 0 for n in timelines[int(caption["row"])]["samples"])
        drawn = 0 if caption["undrawn"] else row["count"]  # on a clock no time of the axis places: said, not drawn
        wrong += [] if binned == drawn else [f"{name}: {row['count']} samples, report's timeline {binned}"]
    return wrong + _findings_against(bag, edges)


@pytest.mark.slow
@pytest.mark.parametrize("recording", RECORDINGS, ids=lambda r: r.id)
def test_every_command_shows_one_number_per_figure(
    recording: Recording,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """On every corpus recording: a figure of an edge is one number in monitor, frames, view-frames, report and
    wtf (to each one's display rounding), and none is impossible. A difference is a defect (two computations of
    one figure) or two quantities under one name: either is fixed, never allowed here."""
    assert _compare(tfx, corpus(recording), tmp_path) == []


SAMPLES = Path(__file__).resolve().parents[2] / "sample_bags"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
def test_the_sample_bags_show_one_number_per_figure(name: str, tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    """The same on the three recordings the README's examples use."""
    assert _compare(tfx, SAMPLES / name, tmp_path) == []


#: A real Neato over wifi: its driver stamps its three edges alike, and they stop together 5 times.
CHECKPOINT = "ros2-neato-real-wifi-stalls-odom-jumps-wheels-alone-2023-db3"


def test_edges_silent_from_one_stamp_are_said_to_stop_at_the_same_instant(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """'each time within 0.000 s of each other' read as a figure rounded away; the stamps say the same instant."""
    (bag,) = json.loads(tfx("wtf", "-b", corpus(BY_ID[CHECKPOINT]), "--format", "json").stdout)["bags"]
    (stall,) = [f for f in bag["findings"] if f["code"] == "stall"]
    assert "all 3 moving edges went silent at once 5 times (each time at the same instant)" in stall["message"]
    assert "0.000 s" not in stall["message"], stall["message"]


#: A real TurtleBot 2: odom -> base_footprint at 19.6 Hz, each sample arriving within 0.5 ms of its stamp.
TURTLEBOT2 = "ros1-turtlebot2-real-cut-no-statics-2019-bag"


def test_a_chains_net_delay_is_not_called_its_edges_delay(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """monitor odom base_footprint: a chain of one edge gave "delay_mean_s" 0.028 for the chain and 0.0004 for its
    one edge in the same JSON. Two figures: how far the newest stamp is behind (half a period and more), and how
    late each sample arrived; the chain's is now named net_delay, and the text says what it is."""
    path = corpus(BY_ID[TURTLEBOT2])
    chain = json.loads(tfx("monitor", "odom", "base_footprint", "-b", path, "-f", "json").stdout)["chain"]
    (edge,) = chain["edges"]
    assert chain["net_delay_mean_s"] == pytest.approx(0.0282, abs=1e-4) and "delay_mean_s" not in chain, chain
    assert edge["delay_mean_s"] == pytest.approx(0.0004, abs=1e-4), edge
    text = " ".join(tfx("monitor", "odom", "base_footprint", "-b", path).stdout.split())
    assert "Net delay avg = 0.0282: max = 0.0605" in text and "not only how late each sample arrived" in text


def test_frames_yaml_rate_is_tf2s_and_its_help_says_so(tfx: Tfx) -> None:  # noqa: F811
    """tf2's allFramesAsYAML counts samples over their span (750 over 14.98 s: 50.066), every other figure of tfx
    intervals (749: 50.00 Hz). The YAML is tf2's byte for byte, so its "rate" stays; the help says which it is."""
    path = SAMPLES / "robot.bag"
    said = tfx("frames", "-b", path, "--format", "yaml").stdout
    assert "base_footprint: \n  parent: 'odom'\n  broadcaster: '/ekf_localization'\n  rate: 50.066\n" in said
    frames = json.loads(tfx("frames", "-b", path, "-f", "json").stdout)["frames"]
    (row,) = [f for f in frames if f["frame"] == "base_footprint"]
    assert row["count"] == 750 and row["rate_hz"] == pytest.approx(49.9996, abs=1e-4), row
    assert "whose rate is tf2's: samples over the span" in " ".join(tfx("frames", "--help").stdout.split())
