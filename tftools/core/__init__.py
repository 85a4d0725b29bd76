"""The engine: time, transforms, edge histories and the buffer. Knows nothing of files or networks."""

from tftools.core.batch import BatchBuilder, TransformBatch
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer, LookupBatch
from tftools.core.errors import (
    BackwardExtrapolationError,
    ConnectivityError,
    ExtrapolationError,
    ForwardExtrapolationError,
    InvalidArgumentError,
    NoDataForExtrapolationError,
    TfToolsError,
    TransformError,
    UnknownFrameError,
)
from tftools.core.history import EdgeHistory
from tftools.core.rejection import Rejection, RejectionCode
from tftools.core.semantics import SEMANTICS, Semantics
from tftools.core.time import LATEST, NS_PER_S, Clock, SimClock, WallClock, format_sec, from_sec, to_sec
from tftools.core.transform import Transform

__all__ = [
    "DEFAULT_CACHE_TIME", "LATEST", "NS_PER_S", "SEMANTICS", "BackwardExtrapolationError", "BatchBuilder", "Buffer",
    "Clock", "ConnectivityError", "EdgeHistory", "ExtrapolationError", "ForwardExtrapolationError",
    "InvalidArgumentError", "LookupBatch", "NoDataForExtrapolationError", "Rejection", "RejectionCode", "Semantics",
    "SimClock", "TfToolsError", "Transform", "TransformBatch", "TransformError", "UnknownFrameError", "WallClock",
    "format_sec", "from_sec", "to_sec",
]  # fmt: skip
