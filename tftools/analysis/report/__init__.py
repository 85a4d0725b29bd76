"""``tfx report``'s room: ``report(recording, query)``, what the page shows of one recording (``recording``),
its query (``query``), and ``report_fleet``, each recording of a fleet read and reported (``fleet``)."""

from __future__ import annotations

from tftools.analysis.report.fleet import Unreadable, report_fleet
from tftools.analysis.report.query import ReportQuery
from tftools.analysis.report.recording import RecordingReport, recording_facts, report

__all__ = ["RecordingReport", "ReportQuery", "Unreadable", "recording_facts", "report", "report_fleet"]
