"""tftools: diagnose ROS tf trees on bag files and live systems, with tf2's exact semantics."""

from tftools.core import (
    DEFAULT_CACHE_TIME,
    LATEST,
    NS_PER_S,
    BatchBuilder,
    Buffer,
    ConnectivityError,
    EdgeHistory,
    ExtrapolationError,
    InvalidArgumentError,
    LookupBatch,
    Rejection,
    RejectionCode,
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

from tftools.sources import Recording, load, read_recording

__version__ = "0.1.0"

__all__ = [
    "DEFAULT_CACHE_TIME",
    "LATEST",
    "NS_PER_S",
    "BatchBuilder",
    "Buffer",
    "ConnectivityError",
    "EdgeHistory",
    "ExtrapolationError",
    "InvalidArgumentError",
    "LookupBatch",
    "Recording",
    "Rejection",
    "RejectionCode",
    "SimClock",
    "TfToolsError",
    "Transform",
    "TransformBatch",
    "TransformError",
    "UnknownFrameError",
    "WallClock",
    "format_sec",
    "from_sec",
    "load",
    "read_recording",
    "to_sec",
]
