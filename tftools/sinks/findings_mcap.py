"""A recording's findings as an MCAP to open beside it in Foxglove, on the recording's own record times:
each finding a ``foxglove.Log`` when it first showed (topic ``/tfx/findings``), the ``/diagnostics`` a
watcher would have said once a second (diagnostic_msgs/DiagnosticArray, ros1msg), and the edges a finding
names as a ``foxglove.FrameTransforms`` at that time (``/tfx/finding_frames``). Foxglove's messages are
protobuf, with the schemas of ``foxglove-schemas-protobuf`` (pip install 'tftools[foxglove]')."""

from __future__ import annotations

import dataclasses
import io
import itertools
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from tftools.analysis.edges import TimeWindow, edge_stats
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.fleet import BagReport
from tftools.analysis.wtf.health import statuses
from tftools.core.errors import TfToolsError, TransformError
from tftools.render.files import write_atomically
from tftools.sinks.diagnostics import DIAGNOSTIC_ARRAY, TOPIC, encode_ros1
from tftools.sinks.errors import FindingsFileError
from tftools.sources.codecs.types import ros1_message_type

if TYPE_CHECKING:
    from tftools.analysis.wtf.query import CheckQuery
    from tftools.core.buffer import Buffer
    from tftools.core.transform import Transform
    from tftools.sources.recording import Recording

LOG_TOPIC = "/tfx/findings"
FRAMES_TOPIC = "/tfx/finding_frames"
#: The /diagnostics period over the recording (ns), as diagnostic_updater's default.
PERIOD = 1_000_000_000
#: The window each second's edge figures are taken over (ns), as ``tfx wtf --watch``'s default.
WINDOW = 10_000_000_000
#: The statuses of one recording, at most: a longer one (a day of it, or a record time decades from the rest's) has
#: them less often than once a ``PERIOD``.
MOST_STATUSES = 100_000


class FoxgloveSchemasMissingError(TfToolsError):
    def __init__(self) -> None:
        super().__init__("writing findings for Foxglove needs foxglove-schemas-protobuf")
        self.hint = "pip install 'tftools[foxglove]'"


def check_into_mcap(
    paths: Sequence[str | os.PathLike[str]], path: str | os.PathLike[str], query: CheckQuery, *, force: bool = False
) -> tuple[BagReport, int]:
    """``check`` of the recording ``paths`` (read as ``query.reading()`` says), its findings written to a new MCAP
    at ``path`` (``write_findings_mcap``; refused before any reading if it may not be written): the report and
    the messages written (none when the recording could not be read)."""
    from tftools.analysis.wtf.fleet import check, unreadable

    refuse_output(path, paths, force)
    _protobuf()
    try:
        recording = query.reading().read(paths)
    except TfToolsError as error:
        return unreadable(tuple(str(p) for p in paths), str(error), error.hint), 0
    report = check(recording, query)
    return report, write_findings_mcap(path, report, recording, force=force, ignore=query.ignore)


def refuse_output(path: str | os.PathLike[str], inputs: Sequence[str | os.PathLike[str]], force: bool) -> None:
    """A ``FindingsFileError`` if ``path`` is one of the ``inputs``, or exists (unless ``force``)."""
    target = Path(path)
    if any(_same_file(target, Path(p)) for p in inputs):
        raise FindingsFileError(str(target), "input")
    if target.is_dir():
        raise FindingsFileError(str(target), "folder")
    if target.exists() and not force:
        raise FindingsFileError(str(target), "exists")


def write_findings_mcap(
    path: str | os.PathLike[str],
    report: BagReport,
    recording: Recording,
    *,
    force: bool = False,
    ignore: Sequence[str] = (),
) -> int:
    """Write ``report``'s findings on ``recording`` (the one it checked) to a new MCAP at ``path`` (an existing
    file only with ``force``, never one of the recording's own files); the messages written."""
    target = Path(path)
    refuse_output(target, report.paths, force)
    proto = _protobuf()
    out = io.BytesIO()
    written = _write(out, report, recording, proto, ignore)
    write_atomically(target, out.getvalue())  # an existing file is replaced whole or not at all
    return written


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _protobuf() -> Any:
    try:
        from foxglove_schemas_protobuf import FrameTransforms_pb2, Log_pb2
    except ImportError:
        raise FoxgloveSchemasMissingError() from None
    return Log_pb2, FrameTransforms_pb2


def _write(out: IO[bytes], report: BagReport, recording: Recording, proto: Any, ignore: Sequence[str]) -> int:
    from mcap.writer import Writer

    log_pb2, frames_pb2 = proto
    writer = Writer(out)
    writer.start(profile="", library="tfx")
    log_channel = writer.register_channel(LOG_TOPIC, "protobuf", _protobuf_schema(writer, log_pb2.Log))
    frames_channel = writer.register_channel(
        FRAMES_TOPIC, "protobuf", _protobuf_schema(writer, frames_pb2.FrameTransforms)
    )
    diagnostics = ros1_message_type(DIAGNOSTIC_ARRAY)
    schema = writer.register_schema(diagnostics.name, "ros1msg", diagnostics.definition.encode())
    diagnostics_channel = writer.register_channel(TOPIC, "ros1", schema)
    start, end = report.start, report.end
    written = 0
    messages: list[tuple[int, int, bytes]] = []
    for finding in report.findings:
        at = finding_time(finding, start, end)
        messages.append((at, log_channel, _log(log_pb2, finding, at, report.name).SerializeToString()))
        frames = _frame_transforms(frames_pb2, recording, finding, at)
        if frames is not None:
            messages.append((at, frames_channel, frames.SerializeToString()))
    for at, statuses_at in diagnostics_over(report, recording, ignore):
        messages.append((at, diagnostics_channel, encode_ros1(at, statuses_at)))
    messages.sort(key=lambda m: m[0])
    for sequence, (at, channel, data) in enumerate(messages):
        writer.add_message(channel, log_time=at, data=data, publish_time=at, sequence=sequence)
        written += 1
    writer.finish()
    return written


def finding_time(finding: Finding, start: int, end: int) -> int:
    """When ``finding`` first showed, on the recording's record times: its ``first_time`` where it falls in the
    recording's span (stamps on another clock, or none, are said at its start)."""
    return finding.first_time if start <= finding.first_time <= end else start


def active(finding: Finding, at: int, start: int, end: int) -> bool:
    """Whether a watcher would say ``finding`` at ``at``: what shows it (from when it first showed to when it
    last did; to the end where it has no span on the record times) falls in the ``WINDOW`` before ``at``."""
    first = finding_time(finding, start, end)
    last = finding.last_time if first <= finding.last_time <= end else end
    return first <= at and max(last, first) >= at - WINDOW


def diagnostics_over(
    report: BagReport, recording: Recording, ignore: Sequence[str] = ()
) -> Iterator[tuple[int, list[Any]]]:
    """The statuses once a ``PERIOD`` of the recording (``MOST_STATUSES`` at most): the findings that hold then, and
    each edge's figures over the ``WINDOW`` before."""
    start, end = report.start, report.end
    period = max(PERIOD, -(-(end - start) // max(MOST_STATUSES - 1, 1)))  # from its start to its end
    at = start
    while at <= end:
        held = dataclasses.replace(report, findings=[f for f in report.findings if active(f, at, start, end)])
        window = TimeWindow(max(start, at - WINDOW), at, by_record_time=True, timeline=recording.timeline)
        edges = edge_stats(recording.buffer, window)
        unavailable = recording.timeline.delays_unavailable
        yield at, statuses(held, edges, at, ignore=ignore, window=WINDOW, delays_unavailable=unavailable)
        at += period


def _log(log_pb2: Any, finding: Finding, at: int, recording: str) -> Any:
    level = {Severity.error: log_pb2.Log.ERROR, Severity.warning: log_pb2.Log.WARNING}.get(
        finding.severity, log_pb2.Log.INFO
    )
    message = f"not checked: {finding.message}" if finding.skipped else finding.message
    if finding.hint:
        message = f"{message}\nhint: {finding.hint}"
    log = log_pb2.Log(level=level, name=f"tfx wtf: {finding.code}", message=message, file=recording)
    log.timestamp.FromNanoseconds(at)
    return log


def _frame_transforms(frames_pb2: Any, recording: Recording, finding: Finding, at: int) -> Any:
    """The edges among the frames ``finding`` names, as the recording's tf had them at ``at`` (None: none)."""
    buffer = recording.buffer
    message = frames_pb2.FrameTransforms()
    for parent, child in itertools.pairwise(finding.frames):
        transform = _lookup(buffer, parent, child, finding.first_time)
        if transform is None:
            continue
        item = message.transforms.add(parent_frame_id=parent, child_frame_id=child)
        item.timestamp.FromNanoseconds(at)
        x, y, z = transform.translation
        qx, qy, qz, qw = transform.rotation
        item.translation.x, item.translation.y, item.translation.z = x, y, z
        item.rotation.x, item.rotation.y, item.rotation.z, item.rotation.w = qx, qy, qz, qw
    return message if len(message.transforms) else None


def _lookup(buffer: Buffer, parent: str, child: str, stamp: int) -> Transform | None:
    """``parent`` <- ``child`` when the finding showed (its stamp), else the latest; None if tf has no such edge."""
    for time in (stamp, 0):
        try:
            return buffer.lookup(parent, child, time)
        except (TransformError, ValueError):
            continue
    return None


def _protobuf_schema(writer: Any, message_class: Any) -> int:
    """An MCAP schema of ``message_class``: its full name and a FileDescriptorSet of its file and those it
    imports, as Foxglove reads protobuf schemas."""
    from google.protobuf import descriptor_pb2

    files = descriptor_pb2.FileDescriptorSet()
    seen: set[str] = set()
    pending = [message_class.DESCRIPTOR.file]
    while pending:
        file = pending.pop()
        if file.name in seen:
            continue
        seen.add(file.name)
        file.CopyToProto(files.file.add())
        pending.extend(file.dependencies)
    return int(writer.register_schema(message_class.DESCRIPTOR.full_name, "protobuf", files.SerializeToString()))
