"""Errors of live sources (ROS 1 and ROS 2), each one line saying what is wrong and what to do."""

from __future__ import annotations

from collections.abc import Sequence

from tftools.sources.errors import SourceError


class LiveError(SourceError):
    """A live system could not be joined or listened to."""

    def __init__(self, message: str, hint: str = "") -> None:
        super().__init__(message)
        self.hint = hint


class MasterUnreachableError(LiveError):
    def __init__(self, uri: str, reason: str) -> None:
        super().__init__(
            f"cannot reach the ROS master at {uri} ({reason})",
            "start roscore, or point ROS_MASTER_URI at the running master",
        )


class MasterTimeoutError(MasterUnreachableError):
    def __init__(self, uri: str, seconds: float) -> None:
        LiveError.__init__(
            self,
            f"the ROS master at {uri} did not answer within {seconds:g} s",
            "is ROS_MASTER_URI the master's address, and is the master not overloaded?",
        )


class MasterReplyError(LiveError):
    def __init__(self, uri: str, call: str, reason: str) -> None:
        super().__init__(
            f"the ROS master at {uri} answered {call} with something tfx cannot use: {reason}",
            "is ROS_MASTER_URI a ROS master's address?",
        )


class MasterRefusedError(LiveError):
    def __init__(self, uri: str, call: str, reason: str) -> None:
        super().__init__(f"the ROS master at {uri} refused {call}: {reason}", "check the master's log")


class NoRosSelectedError(LiveError):
    def __init__(self) -> None:
        super().__init__(
            "no live ROS system to listen to: ROS_MASTER_URI is not set (nor ROS_VERSION, nor ROS_DOMAIN_ID)",
            "read a recording, or set ROS_MASTER_URI (e.g. http://localhost:11311), or name the ROS (ros='ros1', "
            "or ros='ros2' for ROS 2: DDS domain ROS_DOMAIN_ID, default 0)",
        )


class CycloneDdsMissingError(LiveError):
    def __init__(self, error: BaseException) -> None:
        state = "is not installed" if isinstance(error, ModuleNotFoundError) else f"cannot be loaded: {error}"
        super().__init__(
            f"live ROS 2 needs Eclipse Cyclone DDS's Python package (cyclonedds), which {state}",
            "install the extra: pip install 'tftools[ros2]'",
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


def replay_with_clock(ros2: bool | None) -> str:
    """How to replay a recording with ``/clock``, in the words of the ROS the waiting clock serves (``ros2``;
    None: not told, each ROS's way)."""
    ros1_way, ros2_way = "rosbag play --clock BAG", "ros2 bag play --clock BAG"
    if ros2 is None:
        return f"replay with the clock (ROS 1: {ros1_way}; ROS 2: {ros2_way})"
    return f"replay with the clock ({ros2_way if ros2 else ros1_way})"


class NoClockError(LiveError):
    """Simulated time asked for on ROS 1 (``ros2`` False), ROS 2 (True) or a clock not told which (None),
    and no ``/clock`` in ``seconds``."""

    def __init__(self, seconds: float, ros2: bool | None = None) -> None:
        off = {
            None: "use_sim_time=False; ROS 1: rosparam set /use_sim_time false",
            False: "rosparam set /use_sim_time false",
            True: "use_sim_time=False, a ROS 2 node's default",
        }[ros2]
        super().__init__(
            f"simulated time is on (use_sim_time), but no /clock came in {seconds:g} s: time stands still at 0",
            f"{replay_with_clock(ros2)}, or run without simulated time ({off})",
        )
        self.ros2 = ros2


class NoTransformsHeardError(LiveError):
    """A capture heard no transform on its ``topics`` from the live system ``source`` in ``duration`` s; its hint
    in the words of that system's ROS (``ros2``; None: not told, each ROS's way)."""

    def __init__(self, topics: Sequence[str], source: str, duration: float, ros2: bool | None = None) -> None:
        ask = {
            None: "rostopic info /tf on ROS 1, ros2 topic info /tf --verbose on ROS 2",
            False: "rostopic info /tf",
            True: "ros2 topic info /tf --verbose",
        }[ros2]
        super().__init__(
            f"no transforms on {', '.join(topics)} from {source} in {duration:g} s",
            f"is anything publishing? ({ask}) listen longer",
        )
        self.topics, self.source, self.duration = list(topics), source, duration


class TransformNotHeardError(LiveError):
    """``wait_for_transform`` gave up: ``target`` <- ``source`` was not there after ``waited`` s, for ``reason``
    (tf2's, its first line)."""

    def __init__(self, target: str, source: str, waited: float, reason: str) -> None:
        super().__init__(
            f"no transform {target} <- {source} after {waited:.1f} s: {reason}",
            "check the frame names, or wait longer",
        )
        self.target, self.source, self.waited, self.reason = target, source, waited, reason
