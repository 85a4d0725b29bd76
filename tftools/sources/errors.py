"""Errors of the sources: each says what is wrong and what to do, in one line."""

from __future__ import annotations

import os
from collections.abc import Sequence

from tftools.core.errors import TfToolsError


class SourceError(TfToolsError):
    """A source could not deliver transforms."""


class BagError(SourceError):
    """A bag could not be read."""

    def __init__(self, path: str, problem: str, hint: str = "") -> None:
        super().__init__(f"{path}: {problem}")
        self.path = path
        self.problem = problem
        self.hint = hint

    def said_of(self, path: str) -> BagError:
        """This error (its class kept) said of ``path`` (a URL) rather than of the local copy it was met in."""
        said = type(self).__new__(type(self))  # not copy.copy: it calls __init__ with the message alone
        said.__dict__.update(self.__dict__)
        said.path, said.problem = path, self.problem.replace(self.path, path)
        said.args = (f"{path}: {said.problem}",)
        return said


class BagNotFoundError(BagError):
    def __init__(self, path: str) -> None:
        super().__init__(
            path, "no such file or directory", "check the path; globs like logs/*.bag are expanded by the shell"
        )


class UnknownBagFormatError(BagError):
    def __init__(self, path: str, detail: str = "") -> None:
        super().__init__(
            path,
            "not a ROS1 bag, ROS2 bag (sqlite3 or mcap) or MCAP file" + (f" ({detail})" if detail else ""),
            "tftools reads .bag, .db3, .mcap files and ROS2 bag directories",
        )


class OldRos1BagError(UnknownBagFormatError):
    """A ROS 1 bag of a format before 2.0 (``#ROSRECORD V1.x``, written before ROS C Turtle, 2010)."""

    def __init__(self, path: str, version: str) -> None:
        hint = (  # Noetic's rosbag (1.15) lists a 1.2 bag but raises a TypeError on its messages, in fix and filter
            "convert it to 2.0 with rosbag fix OLD.bag NEW.bag of a ROS 1 older than Noetic (Noetic's fails on"
            " 1.2 bags' messages); rosbag info lists what it holds"
            if version == "1.2"
            else "ROS 1's rosbag reads formats 1.2 and 2.0 only"
        )
        BagError.__init__(
            self, path, f"a ROS 1 bag of the old format {version}, which tftools does not read (it reads 2.0)", hint
        )


class CorruptBagError(BagError):
    """Nothing could be read; a bag that is only partly damaged is read as far as it goes."""

    def __init__(self, path: str, detail: str, hint: str = "") -> None:
        super().__init__(path, f"corrupt or unreadable ({detail})", hint or repair_hint(path))
        self.detail = detail


def repair_hint(path: str) -> str:
    """What to do about a damaged recording, in its format's tools (by its name: a ROS 1 bag's tool on a
    ROS 2 bag helps no one)."""
    if path.endswith(".bag"):
        return "re-copy the file if it was cut short; else run `rosbag reindex` on a copy"
    if path.endswith((".mcap", ".mcap.zstd")) or _holds_mcap(path):
        return "re-copy the file if it was cut short; else `mcap recover` (the mcap CLI) rescues what it can read"
    return (  # a .db3, or a ROS 2 bag directory
        "re-copy the bag if it was cut short; else sqlite3's .recover rescues what a damaged .db3 still holds"
        " (sqlite3 COPY.db3 .recover | sqlite3 FIXED.db3)"
    )


def _holds_mcap(path: str) -> bool:
    """A ROS 2 bag directory of MCAP files (none of sqlite3)."""
    try:
        names = os.listdir(path) if os.path.isdir(path) else []
    except OSError:
        return False
    return any(n.endswith((".mcap", ".mcap.zstd")) for n in names) and not any(n.endswith(".db3") for n in names)


class UnreadableFileError(CorruptBagError):
    """A file the system does not let tfx read (its permissions): nothing need be wrong with its bytes."""

    def __init__(self, path: str, detail: str) -> None:
        BagError.__init__(
            self,
            path,
            f"cannot be opened ({detail})",
            "check its permissions (ls -l): make it readable (chmod +r) or run tfx as a user who may read it",
        )
        self.detail = detail


def record_command(ros2: bool) -> str:
    """The command that records topics, in the words of the recording's ROS."""
    return "ros2 bag record" if ros2 else "rosbag record"


def play_command(ros2: bool) -> str:
    """The command that replays a recording on its own clock (/clock), in the words of the recording's ROS."""
    return "ros2 bag play --clock" if ros2 else "rosbag play --clock"


def tf_unrecorded(ros2: bool) -> str:
    """What every command says of a recording without /tf: the question, and the command that records it."""
    return f"was /tf recorded? record it with {record_command(ros2)} /tf /tf_static"


class NoTransformsError(SourceError):
    """Nothing read from ``paths``: ``lost`` lines say what damage took; ``unread`` lines which asked-for
    topics are in a type or encoding tfx does not read; without either, the ``topics`` asked for that
    are among those ``found`` are said to be such. ``cause`` says which: "lost", "unread", "unreadable" (asked-for
    topics present but not read) or "absent". ``ros2``: the
    recording is ROS 2's (the command that records /tf is said in its ROS's words, ``record_command``)."""

    def __init__(
        self,
        paths: Sequence[str],
        topics: Sequence[str],
        found: Sequence[str] = (),
        unread: Sequence[str] = (),
        lost: Sequence[str] = (),
        carriers: Sequence[str] = (),
        *,
        ros2: bool = False,
    ) -> None:
        where = ", ".join(paths)
        self.ros2 = ros2
        #: Where nothing was read, and the topics read: what a second look reads (``analysis.no_transforms``).
        self.paths, self.topics = list(paths), list(topics)
        #: The found topics of a transform type not among those read: what to read instead ("absent" only).
        self.carriers = [t for t in carriers if t in found and t not in topics]
        if lost:  # the transforms were there, but damage took every one
            super().__init__(f"{where}: no transforms could be read: {'; '.join(lost)}")
            self.cause, self.hint = (
                "lost",
                "the file is damaged where its transforms are: re-copy it if it was cut short",
            )
            return
        if unread:
            super().__init__(f"{where}: no transforms read: {'; '.join(unread)}")
            self.cause, self.hint = (
                "unread",
                "convert those topics to a type and encoding tfx reads, or read other topics",
            )
            return
        others = self.carriers + [t for t in found if t not in topics and t not in self.carriers]
        unreadable = [t for t in topics if t in found]
        message = f"{where}: no transforms on {', '.join(topics)}"
        if unreadable:
            message += f" ({', '.join(unreadable)} present, in a type or encoding tfx does not read)"
        super().__init__(message + (f"; topics present: {', '.join(others)}" if others else ""))
        self.cause = "unreadable" if unreadable else "absent"
        self.hint = (
            "a check of the recording (check) names their type and encoding; read other topics"
            if unreadable
            else f"read {' and '.join(self.carriers[:3])}, of a transform type"
            if self.carriers
            else f"{tf_unrecorded(ros2)}, or read other topics"
        )


class MissingExtraError(SourceError):
    """A URL (or a fleet option) given without the packages it needs installed."""

    def __init__(self, what: str) -> None:
        super().__init__(f"{what} needs tftools[fleet]: pip install 'tftools[fleet]'")


class PartOfBagError(BagError):
    """A file of a ROS 2 bag directory given where the whole ``bag`` (the directory) is needed."""

    def __init__(self, path: str, bag: str) -> None:
        super().__init__(path, f"a file of the ROS 2 bag {bag}", "give the bag's directory")
        self.bag = bag


class RemoteError(BagError):
    """A remote recording that could not be listed or fetched (missing, refused, timed out, ...)."""

    def __init__(self, url: str, problem: str) -> None:
        super().__init__(
            url,
            problem,
            "check the URL and the credentials and endpoint in the environment (e.g. AWS_PROFILE, AWS_ENDPOINT_URL)",
        )


#: What a topic the recording lists without a message is: the recorder subscribed and received nothing.
UNRECORDED = "in the recording without a message"


class NoStampedDataError(SourceError):
    """No topic with a header tied to tf to check: ``problems`` says why, as far as the reading tells;
    ``unrecorded``: the topics among them the recording lists without a message."""

    def __init__(self, problems: Sequence[str], unrecorded: Sequence[str] = ()) -> None:
        said = [*problems, *([f"{', '.join(unrecorded)}: {UNRECORDED}"] if unrecorded else [])]
        why = f": {'; '.join(said)}" if said else ""
        super().__init__(f"no topic with a Header to check{why}")
        # naming topics does not help where the named ones hold nothing: the recorder is what to look at
        its, them = ("its", "it") if len(unrecorded) == 1 else ("their", "them")
        self.hint = (
            f"the recorder received none of {its} messages (none published while it recorded, or, in ROS 2, a "
            f"publisher whose QoS it did not match): record {them} again, or name topics that hold messages"
            if unrecorded
            else "name topics of sensor data (a Header with a frame_id), or none to check every such topic"
        )
        self.problems = said
        self.unrecorded = list(unrecorded)
