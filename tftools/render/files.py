"""Writing an output file whole or not at all: a temporary name in the same folder, then a rename."""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path

from tftools.core.errors import TfToolsError
from tftools.render.escape import printable

_HINTS = {
    errno.ENOSPC: "the disk is full: free some space, or write elsewhere with -o",
    errno.EDQUOT: "the disk quota is used up: free some space, or write elsewhere with -o",
    errno.EACCES: "no permission to write there: write elsewhere with -o",
    errno.EPERM: "no permission to write there: write elsewhere with -o",
    errno.EROFS: "the file system is read-only: write elsewhere with -o",
    errno.ENOENT: "the folder does not exist: create it, or write elsewhere with -o",
    errno.ENOTDIR: "the folder does not exist: create it, or write elsewhere with -o",
    errno.ENAMETOOLONG: "the name is too long: choose a shorter one with -o",
}


class OutputError(TfToolsError):
    """An output file could not be written; nothing was left under its name."""

    def __init__(self, path: str | os.PathLike[str], error: OSError) -> None:
        reason = error.strerror or type(error).__name__
        super().__init__(f"cannot write {printable(str(path))}: {reason}")
        self.hint = _HINTS.get(error.errno or 0, "write elsewhere with -o")
        self.path = str(path)


def write_atomically(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path``: to a temporary file beside it, then renamed over it, so that a
    full disk or an interruption never leaves a half-written file under ``path``. The file gets the
    usual permissions (0666 less the umask); what is at ``path`` is replaced only if it is a regular
    file. Raises ``OutputError`` (one line, with a hint)."""
    target = Path(path)
    if target.exists() and not target.is_file() and not target.is_dir():  # a FIFO or device: never replaced
        raise OutputError(target, OSError(errno.EEXIST, "not a regular file (a FIFO, device or socket)"))
    try:
        handle, scratch = tempfile.mkstemp(prefix=f".{target.name[:64]}.", suffix=".part", dir=target.parent)
    except OSError as error:
        raise OutputError(target, error) from None
    try:
        with os.fdopen(handle, "wb") as out:
            umask = os.umask(0o022)  # read by setting it, then set back
            os.umask(umask)
            os.fchmod(out.fileno(), 0o666 & ~umask)
            out.write(data)
            out.flush()
            os.fsync(out.fileno())  # a full disk is reported here at the latest, not after the rename
        os.replace(scratch, target)
    except OSError as error:
        Path(scratch).unlink(missing_ok=True)
        raise OutputError(target, error) from None
    except BaseException:
        Path(scratch).unlink(missing_ok=True)
        raise
    return target
