"""Live ROS 2 over DDS, without ROS 2: Eclipse Cyclone DDS's Python package (extra ``ros2``) joins the
system as a participant speaking ROS 2's topic names, types and QoS."""

from __future__ import annotations

from collections.abc import Sequence

from tftools.sources.live.base import LiveSource, OnNotice
from tftools.sources.live.ros2.errors import CycloneDdsMissingError


def require_cyclonedds() -> None:
    """Raise ``CycloneDdsMissingError`` (one line: how to install the extra) where it cannot load."""
    try:
        import cyclonedds.domain  # noqa: F401 - loads the C library too
    except (ImportError, OSError) as error:
        raise CycloneDdsMissingError(error) from None


def open_source(
    topics: Sequence[str] | None = None,
    use_sim_time: bool | None = None,
    on_notice: OnNotice | None = None,
    domain_id: int | None = None,
) -> LiveSource:
    """A ``Ros2Source`` on ``domain_id`` (``ROS_DOMAIN_ID``), not yet started."""
    require_cyclonedds()
    from tftools.sources.live.ros2.source import Ros2Source

    return Ros2Source(topics, use_sim_time, on_notice, domain_id)


__all__ = ["CycloneDdsMissingError", "open_source", "require_cyclonedds"]
