"""Errors of the live ROS 2 source, each one line saying what is wrong and what to do."""

from __future__ import annotations

from tftools.sources.live.errors import LiveError

INSTALL_HINT = "install the extra: pip install 'tftools[ros2]'"


class CycloneDdsMissingError(LiveError):
    def __init__(self, error: BaseException) -> None:
        state = "is not installed" if isinstance(error, ModuleNotFoundError) else f"cannot be loaded: {error}"
        super().__init__(
            f"live ROS 2 needs Eclipse Cyclone DDS's Python package (cyclonedds), which {state}", INSTALL_HINT
        )


class DomainIdError(LiveError):
    def __init__(self, value: str) -> None:
        super().__init__(
            f"ROS_DOMAIN_ID={value!r} is not a ROS 2 domain id", "use a whole number from 0 to 232, e.g. 0"
        )


class DdsError(LiveError):
    def __init__(self, what: str, error: Exception) -> None:
        reason = getattr(error, "msg", None) or str(error)
        code = str(error).split("]")[0].lstrip("[") if str(error).startswith("[") else ""
        super().__init__(
            f"Cyclone DDS could not {what}" + (f" ({code})" if code else f": {reason}"),
            "check CYCLONEDDS_URI (Cyclone printed why above), ROS_AUTOMATIC_DISCOVERY_RANGE and ROS_STATIC_PEERS",
        )
