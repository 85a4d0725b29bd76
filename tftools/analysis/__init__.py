"""Analyses over a buffer: echo series, frame summaries, monitor statistics, wtf checks, reports and fleets.

``tfx report``'s one call is ``tftools.analysis.report.report`` (``tftools.report``): here ``report`` names its
room, the package.

The names load on first use (PEP 562): ``import tftools.analysis`` costs nothing until a name of it is
asked for, and each brings only its own modules."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy

if TYPE_CHECKING:
    from tftools.analysis.description import Robot, robot_of
    from tftools.analysis.diff import Difference, compare
    from tftools.analysis.echo import EchoSeries, echo, echo_latest, echo_played, echo_recording, echo_times
    from tftools.analysis.expected import Tolerances, TreeShape, shape_of
    from tftools.analysis.filter import FilterReport, filter_heard, filter_recording, filter_report
    from tftools.analysis.findings import Finding, Severity
    from tftools.analysis.fleet import Fleet, Unfinished, run_fleet
    from tftools.analysis.frames import FrameTree, frame_tree
    from tftools.analysis.graph import FrameGraph, frame_graph
    from tftools.analysis.live import echo_live, filter_live
    from tftools.analysis.loops import find_loops
    from tftools.analysis.monitor import LiveMonitor, MonitorReport, monitor, monitor_recording, watch_feed
    from tftools.analysis.report import RecordingReport, ReportQuery, Unreadable, report_fleet
    from tftools.analysis.times import parse_time, time_range
    from tftools.analysis.tree_diff import TreeDiff, diff_trees
    from tftools.analysis.tree_file import read_tree, write_tree
    from tftools.analysis.wtf import CHECKS, Thresholds, findings_of
    from tftools.analysis.wtf.fleet import BagReport, check, check_fleet
    from tftools.analysis.wtf.query import CheckQuery
    from tftools.sources.errors import NoStampedDataError

__all__ = [
    "CHECKS",
    "BagReport",
    "CheckQuery",
    "Difference",
    "EchoSeries",
    "FilterReport",
    "Finding",
    "Fleet",
    "FrameGraph",
    "FrameTree",
    "LiveMonitor",
    "MonitorReport",
    "NoStampedDataError",
    "RecordingReport",
    "ReportQuery",
    "Robot",
    "Severity",
    "Thresholds",
    "Tolerances",
    "TreeDiff",
    "TreeShape",
    "Unfinished",
    "Unreadable",
    "check",
    "check_fleet",
    "compare",
    "diff_trees",
    "echo",
    "echo_latest",
    "echo_live",
    "echo_played",
    "echo_recording",
    "echo_times",
    "filter_heard",
    "filter_live",
    "filter_recording",
    "filter_report",
    "find_loops",
    "findings_of",
    "frame_graph",
    "frame_tree",
    "monitor",
    "monitor_recording",
    "parse_time",
    "read_tree",
    "report_fleet",
    "robot_of",
    "run_fleet",
    "shape_of",
    "time_range",
    "watch_feed",
    "write_tree",
]

#: Where each name is defined.
_HOME = {
    "BagReport": "tftools.analysis.wtf.fleet",
    "CHECKS": "tftools.analysis.wtf",
    "CheckQuery": "tftools.analysis.wtf.query",
    "Difference": "tftools.analysis.diff",
    "EchoSeries": "tftools.analysis.echo",
    "FilterReport": "tftools.analysis.filter",
    "Finding": "tftools.analysis.findings",
    "Fleet": "tftools.analysis.fleet",
    "FrameGraph": "tftools.analysis.graph",
    "FrameTree": "tftools.analysis.frames",
    "LiveMonitor": "tftools.analysis.monitor",
    "MonitorReport": "tftools.analysis.monitor",
    "NoStampedDataError": "tftools.sources.errors",
    "RecordingReport": "tftools.analysis.report",
    "ReportQuery": "tftools.analysis.report",
    "Robot": "tftools.analysis.description",
    "Severity": "tftools.analysis.findings",
    "Thresholds": "tftools.analysis.wtf",
    "Tolerances": "tftools.analysis.expected",
    "TreeDiff": "tftools.analysis.tree_diff",
    "TreeShape": "tftools.analysis.expected",
    "Unfinished": "tftools.analysis.fleet",
    "Unreadable": "tftools.analysis.report",
    "check": "tftools.analysis.wtf.fleet",
    "check_fleet": "tftools.analysis.wtf.fleet",
    "compare": "tftools.analysis.diff",
    "diff_trees": "tftools.analysis.tree_diff",
    "echo": "tftools.analysis.echo",
    "echo_latest": "tftools.analysis.echo",
    "echo_live": "tftools.analysis.live",
    "echo_played": "tftools.analysis.echo",
    "echo_recording": "tftools.analysis.echo",
    "echo_times": "tftools.analysis.echo",
    "filter_heard": "tftools.analysis.filter",
    "filter_live": "tftools.analysis.live",
    "filter_recording": "tftools.analysis.filter",
    "filter_report": "tftools.analysis.filter",
    "find_loops": "tftools.analysis.loops",
    "findings_of": "tftools.analysis.wtf",
    "frame_graph": "tftools.analysis.graph",
    "frame_tree": "tftools.analysis.frames",
    "monitor": "tftools.analysis.monitor",
    "monitor_recording": "tftools.analysis.monitor",
    "parse_time": "tftools.analysis.times",
    "read_tree": "tftools.analysis.tree_file",
    "report_fleet": "tftools.analysis.report",
    "robot_of": "tftools.analysis.description",
    "run_fleet": "tftools.analysis.fleet",
    "shape_of": "tftools.analysis.expected",
    "time_range": "tftools.analysis.times",
    "watch_feed": "tftools.analysis.monitor",
    "write_tree": "tftools.analysis.tree_file",
}


__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
