"""Errors of the sources: each says what is wrong and what to do, in one line."""

from __future__ import annotations

from tftools.core.errors import TfToolsError


class SourceError(TfToolsError):
    """A source could not deliver transforms."""


class BagError(SourceError):
    """A bag could not be read."""

    def __init__(self, path: str, problem: str, hint: str = "") -> None:
        super().__init__(f"{path}: {problem}")
        self.path = path
        self.hint = hint


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


class CorruptBagError(BagError):
    """Nothing could be read; a bag that is only partly damaged is read as far as it goes."""

    def __init__(self, path: str, detail: str) -> None:
        super().__init__(
            path,
            f"corrupt or unreadable ({detail})",
            "for a ROS1 bag try `rosbag reindex`; re-copy the file if it was cut short",
        )


class NoTransformsError(SourceError):
    def __init__(self, paths: str, topics: str, found: str = "") -> None:
        super().__init__(f"{paths}: no transforms on {topics}" + (f"; topics present: {found}" if found else ""))
        self.hint = "was /tf recorded? pick other topics with --topic"
