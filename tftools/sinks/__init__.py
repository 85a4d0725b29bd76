"""Where transforms go: static transform publishers on live systems, and copies of bags with static
transforms added. Sinks are apart from sources; they share the live systems' transports with them.

The names load on first use (PEP 562)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy

if TYPE_CHECKING:
    from tftools.sinks.broadcaster import StaticBroadcaster
    from tftools.sinks.static import (
        StaticCopy,
        StaticQuery,
        checked,
        copy_with_statics,
        open_static_broadcaster,
        publish_static,
        static_transform,
    )

__all__ = [
    "StaticBroadcaster",
    "StaticCopy",
    "StaticQuery",
    "checked",
    "copy_with_statics",
    "open_static_broadcaster",
    "publish_static",
    "static_transform",
]

#: Where each name is defined.
_HOME = {
    name: "tftools.sinks.broadcaster" if name == "StaticBroadcaster" else "tftools.sinks.static" for name in __all__
}

__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
