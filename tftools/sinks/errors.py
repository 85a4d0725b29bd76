"""Errors of the sinks that the command line words its own way (``cli.errors``): light, so that it can."""

from __future__ import annotations

from tftools.core.errors import TfToolsError

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
