"""tftools: diagnose ROS tf trees on bag files and live systems, with tf2's exact semantics.

The names below load on first use (PEP 562), so that ``import tftools`` and ``tfx --version`` cost
no numpy, and a command imports only what it uses. ``__version__`` is pyproject.toml's (the one place
it is written), as the build wrote it into the installed package; read on first use too."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from tftools import lazy

if TYPE_CHECKING:
    from tftools.analysis import (
        check_fleet,
        check_live,
        diff_trees,
        echo_live,
        echo_recording,
        filter_live,
        filter_recording,
        filter_report,
        frame_tree,
        monitor_recording,
        recording_report,
        report_fleet,
        report_live,
    )
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
    from tftools.render.graph import view_frames
    from tftools.sinks import add_static, publish_static, repair_static
    from tftools.sources import Recording, read_recording, stream_recording

__version__: str  # set on first use, by __getattr__

__all__ = [
    "DEFAULT_CACHE_TIME", "LATEST", "NS_PER_S", "SEMANTICS", "BatchBuilder", "Buffer", "ConnectivityError",
    "EdgeHistory", "ExtrapolationError", "InvalidArgumentError", "LookupBatch", "Recording", "Rejection",
    "RejectionCode", "Semantics", "SimClock", "TfToolsError", "Transform", "TransformBatch", "TransformError",
    "UnknownFrameError", "WallClock", "add_static", "check_fleet", "check_live", "diff_trees", "echo_live",
    "echo_recording", "filter_live", "filter_recording", "filter_report", "format_sec", "frame_tree", "from_sec",
    "monitor_recording", "publish_static", "read_recording", "recording_report", "repair_static",
    "report_fleet", "report_live", "stream_recording", "to_sec", "view_frames",
]  # fmt: skip

#: The package each name comes from, when not ``tftools.core``: reading (sources), each command's call
#: (analysis; sinks for ``tfx static``; render for ``tfx view-frames``).
_PACKAGE = {
    **dict.fromkeys(["Recording", "read_recording", "stream_recording"], "tftools.sources"),
    **dict.fromkeys(
        [
            "check_fleet",
            "check_live",
            "diff_trees",
            "echo_live",
            "echo_recording",
            "filter_live",
            "filter_recording",
            "filter_report",
            "frame_tree",
            "monitor_recording",
            "recording_report",
            "report_fleet",
            "report_live",
        ],
        "tftools.analysis",
    ),
    **dict.fromkeys(["add_static", "publish_static", "repair_static"], "tftools.sinks"),
    "view_frames": "tftools.render.graph",
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
