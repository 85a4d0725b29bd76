"""tftools: diagnose ROS tf trees on bag files and live systems, with tf2's exact semantics.

The names below load on first use (PEP 562), so that ``import tftools`` and ``tfx --version`` cost
no numpy, and a command imports only what it uses. ``__version__`` is pyproject.toml's (the one place
it is written), as the build wrote it into the installed package; read on first use too."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from tftools import lazy

if TYPE_CHECKING:
    from tftools.analysis import (
        CheckQuery,
        DiffQuery,
        FilterQuery,
        MonitorQuery,
        Offset,
        ReportQuery,
        Stamp,
        check,
        check_fleet,
        diff_trees,
        filter_messages,
        frame_tree,
        report_fleet,
        view_frames,
    )
    from tftools.analysis.echo import EchoQuery, echo, echo_stream
    from tftools.analysis.monitor import monitor, monitor_stream
    from tftools.analysis.report import report
    from tftools.core import (
        DEFAULT_CACHE_TIME,
        LATEST,
        NS_PER_S,
        SEMANTICS,
        BatchBuilder,
        Buffer,
        ConnectivityError,
        EdgeHistory,
        ExtrapolationError,
        InvalidArgumentError,
        LookupBatch,
        Rejection,
        RejectionCode,
        Semantics,
        SimClock,
        TfToolsError,
        Transform,
        TransformBatch,
        TransformError,
        UnknownFrameError,
        WallClock,
        format_sec,
        from_sec,
        to_sec,
    )
    from tftools.sinks import StaticQuery, copy_with_statics, publish_static
    from tftools.sources import Recording, read_recording, stream_recording
    from tftools.sources.live.sensor_headers import capture_live

__version__: str  # set on first use, by __getattr__

__all__ = [
    "DEFAULT_CACHE_TIME", "LATEST", "NS_PER_S", "SEMANTICS", "BatchBuilder", "Buffer", "CheckQuery",
    "ConnectivityError", "DiffQuery", "EchoQuery", "EdgeHistory", "ExtrapolationError", "FilterQuery",
    "InvalidArgumentError", "LookupBatch", "MonitorQuery", "Offset", "Recording", "Rejection", "RejectionCode",
    "ReportQuery", "Semantics", "SimClock", "Stamp", "StaticQuery", "TfToolsError", "Transform", "TransformBatch",
    "TransformError", "UnknownFrameError", "WallClock", "capture_live", "check", "check_fleet", "copy_with_statics",
    "diff_trees", "echo", "echo_stream", "filter_messages", "format_sec", "frame_tree", "from_sec", "monitor",
    "monitor_stream", "publish_static", "read_recording", "report", "report_fleet", "stream_recording", "to_sec",
    "view_frames",
]  # fmt: skip

#: The package each name comes from, when not ``tftools.core``: reading (sources), each command's call
#: (analysis; sinks for ``tfx static``).
_PACKAGE = {
    **dict.fromkeys(["Recording", "read_recording", "stream_recording"], "tftools.sources"),
    **dict.fromkeys(
        [
            "CheckQuery",
            "DiffQuery",
            "FilterQuery",
            "MonitorQuery",
            "Offset",
            "ReportQuery",
            "Stamp",
            "check",
            "check_fleet",
            "diff_trees",
            "filter_messages",
            "frame_tree",
            "report_fleet",
            "view_frames",
        ],
        "tftools.analysis",
    ),
    # named as their rooms are: from the room itself, which ``tftools.analysis``'s attribute becomes once imported
    **dict.fromkeys(["EchoQuery", "echo", "echo_stream"], "tftools.analysis.echo"),
    **dict.fromkeys(["monitor", "monitor_stream"], "tftools.analysis.monitor"),
    **dict.fromkeys(["StaticQuery", "copy_with_statics", "publish_static"], "tftools.sinks"),
    "report": "tftools.analysis.report",  # the function: in tftools.analysis, ``report`` is its package
    "capture_live": "tftools.sources.live.sensor_headers",
}


def version() -> str:
    """The version pyproject.toml gives, as installed (in tftools._version, which the build writes);
    ``0+unknown`` for a checkout that is not installed."""
    try:
        from tftools._version import __version__ as installed
    except ImportError:
        return "0+unknown"
    return str(installed)


_exported, __dir__ = lazy.exports(__name__, {name: _PACKAGE.get(name, "tftools.core") for name in __all__}, __all__)


def __getattr__(name: str) -> Any:
    if name == "__version__":
        globals()[name] = value = version()
        return value
    return _exported(name)
