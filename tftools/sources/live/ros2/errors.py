"""Errors of the live ROS 2 source, each one line saying what is wrong and what to do."""

from __future__ import annotations

from tftools.sources.live.errors import LiveError

INSTALL_HINT = "pip install 'tftools[ros2]' (or: pip install cyclonedds)"


class CycloneDdsMissingError(LiveError):
    def __init__(self, reason: str = "") -> None:
        detail = f" ({reason})" if reason else ""
        super().__init__(f"live ROS 2 needs Eclipse Cyclone DDS's Python package, which cannot be loaded{detail}", INSTALL_HINT)


class DomainIdError(LiveError):
    def __init__(self, value: str) -> None:
        super().__init__(f"ROS_DOMAIN_ID={value!r} is not a ROS 2 domain id", "use a whole number from 0 to 232, e.g. 0")


class DdsError(LiveError):
    def __init__(self, what: str, reason: object) -> None:
        super().__init__(
            f"Cyclone DDS could not {what}: {reason}",
            "check CYCLONEDDS_URI, ROS_AUTOMATIC_DISCOVERY_RANGE and ROS_STATIC_PEERS",
        )
