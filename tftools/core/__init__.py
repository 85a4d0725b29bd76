"""The engine: time, transforms, edge histories and the buffer. Knows nothing of files or networks.

The names load on first use (PEP 562): a light module of the package (``time``, ``errors``,
``semantics``) costs no numpy, so that ``tfx --help`` and its subcommands' help need none."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy

if TYPE_CHECKING:
    from tftools.core.batch import BatchBuilder, TransformBatch
    from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer, LookupBatch
    from tftools.core.errors import (
        BackwardExtrapolationError,
        ConnectivityError,
        ExtrapolationError,
        FleetUnavailableError,
        ForwardExtrapolationError,
        InvalidArgumentError,
        InvalidTransformError,
        NoDataForExtrapolationError,
        TfToolsError,
        TransformError,
        UnknownFrameError,
    )
    from tftools.core.frames import frame_name
    from tftools.core.history import EdgeHistory
    from tftools.core.rejection import Rejection, RejectionCode
    from tftools.core.semantics import SEMANTICS, Semantics
    from tftools.core.time import LATEST, NS_PER_S, Clock, SimClock, WallClock, format_sec, from_sec, to_sec
    from tftools.core.transform import Transform

__all__ = [
    "DEFAULT_CACHE_TIME", "LATEST", "NS_PER_S", "SEMANTICS", "BackwardExtrapolationError", "BatchBuilder", "Buffer",
    "Clock", "ConnectivityError", "EdgeHistory", "ExtrapolationError", "FleetUnavailableError",
    "ForwardExtrapolationError", "InvalidArgumentError", "InvalidTransformError", "LookupBatch",
    "NoDataForExtrapolationError", "Rejection", "RejectionCode", "Semantics", "SimClock", "TfToolsError", "Transform",
    "TransformBatch", "TransformError", "UnknownFrameError", "WallClock", "format_sec", "frame_name", "from_sec",
    "to_sec",
]  # fmt: skip

#: Where each name is defined.
_HOME = {
    "BackwardExtrapolationError": "tftools.core.errors",
    "BatchBuilder": "tftools.core.batch",
    "Buffer": "tftools.core.buffer",
    "Clock": "tftools.core.time",
    "ConnectivityError": "tftools.core.errors",
    "DEFAULT_CACHE_TIME": "tftools.core.buffer",
    "EdgeHistory": "tftools.core.history",
    "ExtrapolationError": "tftools.core.errors",
    "FleetUnavailableError": "tftools.core.errors",
    "ForwardExtrapolationError": "tftools.core.errors",
    "InvalidArgumentError": "tftools.core.errors",
    "InvalidTransformError": "tftools.core.errors",
    "LATEST": "tftools.core.time",
    "LookupBatch": "tftools.core.buffer",
    "NS_PER_S": "tftools.core.time",
    "NoDataForExtrapolationError": "tftools.core.errors",
    "Rejection": "tftools.core.rejection",
    "RejectionCode": "tftools.core.rejection",
    "SEMANTICS": "tftools.core.semantics",
    "Semantics": "tftools.core.semantics",
    "SimClock": "tftools.core.time",
    "TfToolsError": "tftools.core.errors",
    "Transform": "tftools.core.transform",
    "TransformBatch": "tftools.core.batch",
    "TransformError": "tftools.core.errors",
    "UnknownFrameError": "tftools.core.errors",
    "WallClock": "tftools.core.time",
    "format_sec": "tftools.core.time",
    "frame_name": "tftools.core.frames",
    "from_sec": "tftools.core.time",
    "to_sec": "tftools.core.time",
}


__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
