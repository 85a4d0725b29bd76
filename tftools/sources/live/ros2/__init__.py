"""Live ROS 2 over DDS, without ROS 2: Eclipse Cyclone DDS's Python package (extra ``ros2``) joins the
system as a participant speaking ROS 2's topic names, types and QoS."""

from __future__ import annotations

from tftools.sources.live.errors import CycloneDdsMissingError


def require_cyclonedds() -> None:
    """Raise ``CycloneDdsMissingError`` (one line: how to install the extra) where it cannot load."""
    try:
        import cyclonedds.domain  # noqa: F401 - loads the C library too
    except (ImportError, OSError) as error:
        raise CycloneDdsMissingError(error) from None
