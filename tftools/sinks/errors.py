"""Errors of the sinks that the command line words its own way (``cli.errors``): light, so that it can."""

from __future__ import annotations

from tftools.core.errors import TfToolsError
from tftools.sources.errors import BagError

#: Why a findings file may not be written: what it is, and what to do.
_FINDINGS_FILE = {
    "input": ("is the recording being checked", "give another file name"),
    "folder": ("is a folder", "give a file name"),
    "exists": ("exists", "give another file name, or let it be overwritten (force)"),
}


class FindingsFileError(TfToolsError):
    """The findings MCAP may not be written at ``path``: it is the recording itself (``reason`` "input"), a
    folder ("folder"), or exists and is not to be overwritten ("exists")."""

    def __init__(self, path: str, reason: str) -> None:
        problem, self.hint = _FINDINGS_FILE[reason]
        super().__init__(f"{path} {problem}")
        self.path = path
        self.reason = reason


#: Why a copy with static transforms cannot be made: what to do, in the library's words.
_COPY = {
    "no_statics": "add static transforms to the copy (StaticQuery.transforms)",
    "exists": "choose another output path, or replace it (StaticQuery.force)",
    "not_replaceable": "only an earlier output is replaced (StaticQuery.force)",
    "damaged": "a check of the bag (check) says what is damaged",
    "encoding": "ROS 1 bags, and ROS 2 bags of CDR messages, are copied",
}


class CopyError(BagError):
    """A copy with static transforms that cannot be made of ``path`` (the input or the output): it holds no
    static transforms to repair (``reason`` "no_statics"), the output exists ("exists") and is not an earlier
    output ("not_replaceable"), the input is damaged ("damaged") or holds messages a ROS 2 copy cannot
    ("encoding")."""

    def __init__(self, path: str, problem: str, reason: str) -> None:
        super().__init__(path, problem, _COPY[reason])
        self.reason = reason
