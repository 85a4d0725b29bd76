"""tftools: diagnose ROS tf trees on bag files and live systems, with tf2's exact semantics.

The names below load on first use (PEP 562), so that ``import tftools`` and ``tfx --version`` cost
no numpy, and a command imports only what it uses."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
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
    from tftools.sources import Recording, load, read_recording

__version__ = "0.1.0"

__all__ = [
    "DEFAULT_CACHE_TIME", "LATEST", "NS_PER_S", "SEMANTICS", "BatchBuilder", "Buffer", "ConnectivityError",
    "EdgeHistory", "ExtrapolationError", "InvalidArgumentError", "LookupBatch", "Recording", "Rejection",
    "RejectionCode", "Semantics", "SimClock", "TfToolsError", "Transform", "TransformBatch", "TransformError",
    "UnknownFrameError", "WallClock", "format_sec", "from_sec", "load", "read_recording", "to_sec",
]  # fmt: skip

#: The names ``tftools.sources`` exports; the others come from ``tftools.core``.
_FROM_SOURCES = {"Recording", "load", "read_recording"}


def __getattr__(name: str) -> Any:
    if name not in __all__:
        raise AttributeError(f"module 'tftools' has no attribute {name!r}")
    value = getattr(importlib.import_module("tftools.sources" if name in _FROM_SOURCES else "tftools.core"), name)
    globals()[name] = value  # looked up once
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
