"""Analyses over a buffer: echo series, frame summaries, monitor statistics, wtf checks, reports and fleets.

Three commands' calls share their room's name (``echo``, ``monitor``, ``report``): here those names are the rooms
(packages), so the calls are reached as ``tftools.echo`` / ``tftools.monitor`` / ``tftools.report``, or from the
room (``from tftools.analysis.echo import echo``), never as an attribute that would turn into the package once
it is imported.

The names load on first use (PEP 562): ``import tftools.analysis`` costs nothing until a name of it is
asked for, and each brings only its own modules."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy

if TYPE_CHECKING:
    from tftools.analysis.description import Robot, robot_of
    from tftools.analysis.diff import DiffQuery, TreeDiff, diff_trees
    from tftools.analysis.differences import Difference, compare
    from tftools.analysis.echo import EchoQuery, EchoSeries, echo_stream
    from tftools.analysis.expected import Tolerances, TreeShape, shape_of
    from tftools.analysis.filter import FilterQuery, filter_messages
    from tftools.analysis.filter.fates import FilterReport
    from tftools.analysis.findings import Finding, Severity
    from tftools.analysis.fleet import Fleet, Unfinished, UnfinishedCause, run_fleet
    from tftools.analysis.frames import FrameTree, frame_tree
    from tftools.analysis.graph import FrameGraph, frame_graph, view_frames
    from tftools.analysis.monitor import LiveMonitor, MonitorQuery, MonitorReport, monitor_stream
    from tftools.analysis.report import RecordingReport, ReportQuery, Unreadable, report_fleet
    from tftools.analysis.times import Offset, Stamp, TimeSpec, parse_time_spec
    from tftools.analysis.tree_file import read_tree, write_tree
    from tftools.analysis.wtf import CHECKS, Thresholds, findings_of
    from tftools.analysis.wtf.fleet import BagReport, check, check_fleet
    from tftools.analysis.wtf.loops import find_loops
    from tftools.analysis.wtf.query import CheckQuery
    from tftools.sources.errors import NoStampedDataError

__all__ = [
    "CHECKS",
    "BagReport",
    "CheckQuery",
    "DiffQuery",
    "Difference",
    "EchoQuery",
    "EchoSeries",
    "FilterQuery",
    "FilterReport",
    "Finding",
    "Fleet",
    "FrameGraph",
    "FrameTree",
    "LiveMonitor",
    "MonitorQuery",
    "MonitorReport",
    "NoStampedDataError",
    "Offset",
    "RecordingReport",
    "ReportQuery",
    "Robot",
    "Severity",
    "Stamp",
    "Thresholds",
    "TimeSpec",
    "Tolerances",
    "TreeDiff",
    "TreeShape",
    "Unfinished",
    "UnfinishedCause",
    "Unreadable",
    "check",
    "check_fleet",
    "compare",
    "diff_trees",
    "echo_stream",
    "filter_messages",
    "find_loops",
    "findings_of",
    "frame_graph",
    "frame_tree",
    "monitor_stream",
    "parse_time_spec",
    "read_tree",
    "report_fleet",
    "robot_of",
    "run_fleet",
    "shape_of",
    "view_frames",
    "write_tree",
]

#: Where each name is defined.
_HOME = {
    "BagReport": "tftools.analysis.wtf.fleet",
    "CHECKS": "tftools.analysis.wtf",
    "CheckQuery": "tftools.analysis.wtf.query",
    "DiffQuery": "tftools.analysis.diff",
    "Difference": "tftools.analysis.differences",
    "EchoQuery": "tftools.analysis.echo",
    "EchoSeries": "tftools.analysis.echo",
    "FilterQuery": "tftools.analysis.filter",
    "FilterReport": "tftools.analysis.filter.fates",
    "Finding": "tftools.analysis.findings",
    "Fleet": "tftools.analysis.fleet",
    "FrameGraph": "tftools.analysis.graph",
    "FrameTree": "tftools.analysis.frames",
    "LiveMonitor": "tftools.analysis.monitor",
    "MonitorQuery": "tftools.analysis.monitor",
    "MonitorReport": "tftools.analysis.monitor",
    "NoStampedDataError": "tftools.sources.errors",
    "Offset": "tftools.analysis.times",
    "RecordingReport": "tftools.analysis.report",
    "ReportQuery": "tftools.analysis.report",
    "Robot": "tftools.analysis.description",
    "Severity": "tftools.analysis.findings",
    "Stamp": "tftools.analysis.times",
    "Thresholds": "tftools.analysis.wtf",
    "TimeSpec": "tftools.analysis.times",
    "Tolerances": "tftools.analysis.expected",
    "TreeDiff": "tftools.analysis.diff",
    "TreeShape": "tftools.analysis.expected",
    "Unfinished": "tftools.analysis.fleet",
    "UnfinishedCause": "tftools.analysis.fleet",
    "Unreadable": "tftools.analysis.report",
    "check": "tftools.analysis.wtf.fleet",
    "check_fleet": "tftools.analysis.wtf.fleet",
    "compare": "tftools.analysis.differences",
    "diff_trees": "tftools.analysis.diff",
    "echo_stream": "tftools.analysis.echo",
    "filter_messages": "tftools.analysis.filter",
    "find_loops": "tftools.analysis.wtf.loops",
    "findings_of": "tftools.analysis.wtf",
    "frame_graph": "tftools.analysis.graph",
    "frame_tree": "tftools.analysis.frames",
    "monitor_stream": "tftools.analysis.monitor",
    "parse_time_spec": "tftools.analysis.times",
    "read_tree": "tftools.analysis.tree_file",
    "report_fleet": "tftools.analysis.report",
    "robot_of": "tftools.analysis.description",
    "run_fleet": "tftools.analysis.fleet",
    "shape_of": "tftools.analysis.expected",
    "view_frames": "tftools.analysis.graph",
    "write_tree": "tftools.analysis.tree_file",
}


__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
