"""The one opener of the files a user gives (a rosbag2 ``metadata.yaml``, a tree file, a list of static
transforms, a URDF, a list of recordings): only a regular file (a FIFO or a device would block, or never
end), within limits on its size, and for YAML on its nesting and aliases (a "billion laughs")."""

from __future__ import annotations

import math
import os
import re
import stat
import warnings
from itertools import accumulate
from typing import Any, BinaryIO

MAX_BYTES = 4 << 20  # a metadata.yaml of a thousand topics is well under 1 MiB
MAX_DEPTH = 64  # rosbag2 writes 5 levels
MAX_NODES = 1 << 20  # nodes once every alias is expanded: a billion laughs has 10**9
#: Lines and flow items (``,``) of YAML parsed at most: ruamel parses ~10,000 a second in pure Python, and
#: a metadata.yaml listing 200,000 files took 20 s (a bag of 1,000 topics and 1,000 split files has ~30,000).
MAX_ITEMS = 50_000

# Quoted scalars and comments, whose brackets do not nest (an approximation: only ever too deep).
_NOT_FLOW = re.compile(r"\"(?:[^\"\\\n]|\\.)*\"|'(?:[^'\n]|'')*'|#[^\n]*")
_NOT_BRACKET = re.compile(r"[^\[\]{}]")


class UserFileError(Exception):
    """A file a user gave that is not read (the message says why, in a few words)."""


class NotAFileError(UserFileError):
    """The path names no regular file: it is missing, a folder, a FIFO or a device."""

    def __init__(self, problem: str, hint: str = "check the path") -> None:
        super().__init__(problem)
        self.hint = hint


def number(value: Any, what: str = "", *, text: bool = True, finite: bool = True) -> float:
    """The one reading of a number a user gave: a YAML or JSON number (not a boolean), or with ``text`` a
    string (a command line's, an XML attribute's, a quoted YAML value); finite unless ``finite`` is false.
    Raises ``ValueError`` naming ``what`` it was ("frame odom: rate_hz: 'x' is not a number")."""
    said = f"{what}: " if what else ""
    try:
        if isinstance(value, bool) or not isinstance(value, (int, float, str) if text else (int, float)):
            raise TypeError
        result = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{said}{value!r} is not a number") from None
    if finite and not math.isfinite(result):
        raise ValueError(f"{said}{value!r} is not a finite number")
    return result


def open_regular(path: str | os.PathLike[str]) -> BinaryIO:
    """The regular file at ``path``, open for reading. Raises ``NotAFileError`` for a missing path, a
    folder, a FIFO or a device (opened without blocking, so a FIFO with no writer is refused at once),
    ``UserFileError`` for one that cannot be opened."""
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise NotAFileError("no such file") from None
    except OSError as e:
        raise UserFileError(e.strerror or str(e)) from None
    mode = os.fstat(descriptor).st_mode
    if not stat.S_ISREG(mode):
        os.close(descriptor)
        if stat.S_ISDIR(mode):
            raise NotAFileError("a folder, not a file")
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a device or socket"
        raise NotAFileError(f"{kind}, not a regular file", "save what it gives to a file, and give that file")
    return os.fdopen(descriptor, "rb")


def read_bytes(path: str | os.PathLike[str], max_bytes: int) -> bytes:
    """The contents of the regular file at ``path`` (``open_regular``), at most ``max_bytes`` of them;
    ``UserFileError`` for a larger file or one that cannot be read."""
    with open_regular(path) as f:
        try:
            raw = f.read(max_bytes + 1)
        except OSError as e:
            raise UserFileError(e.strerror or str(e)) from None
    if len(raw) > max_bytes:
        raise UserFileError(f"larger than {_size(max_bytes)}")
    return raw


def load(path: str | os.PathLike[str]) -> Any:
    """The document of the YAML file at ``path``. Raises ``UserFileError`` for a file that is not a
    regular file, too large, too deep, expanding to too many nodes through its aliases, or not YAML."""
    return load_text(read_bytes(path, MAX_BYTES).decode("utf-8", "replace"))


def load_all(path: str | os.PathLike[str]) -> list[Any]:
    """The documents (``---`` separated) of the YAML file at ``path``, within ``load``'s limits."""
    return _parse(read_bytes(path, MAX_BYTES).decode("utf-8", "replace"), every_document=True)


def load_text(text: str) -> Any:
    """The document of YAML ``text`` (a QoS profile list that metadata.yaml holds as a string),
    within the same limits as ``load``."""
    documents = _parse(text, every_document=False)
    return documents[0] if documents else None


def _parse(text: str, *, every_document: bool) -> list[Any]:
    if len(text) > MAX_BYTES:
        raise UserFileError(f"larger than {_size(MAX_BYTES)}")
    if text.count("\n", 0, len(text) - 1) + text.count(",") >= MAX_ITEMS:  # a comma quoted counts: only too many
        raise UserFileError(f"more than {MAX_ITEMS:,} lines and items, more than tfx parses")
    if _flow_depth(text) > MAX_DEPTH:  # ruamel's scanner takes time quadratic in a flow's depth
        raise UserFileError(f"nested deeper than {MAX_DEPTH} levels")
    from tftools.sources import yaml_subset  # here, not with the module: a .bag's load reads no YAML

    if not every_document and (simple := yaml_subset.parsed(text)) is not None:
        _check(simple)
        return [simple]
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # ruamel's ReusedAnchorWarning: the later anchor holds, as YAML says
            # An alias is constructed as a reference to its anchor's value, not a copy: the document
            # is built in the time its text takes, however far its aliases would expand.
            yaml = YAML(typ="safe")
            documents = list(yaml.load_all(text)) if every_document else [yaml.load(text)]
    except RecursionError:  # the composer recurses once per level
        raise UserFileError(f"nested deeper than {MAX_DEPTH} levels") from None
    except (YAMLError, ValueError) as e:
        raise UserFileError(f"not valid YAML ({_where(e)})") from None
    for document in documents:
        _check(document)
    return documents


def _where(error: Exception) -> str:
    """What the parser found wrong, and where: "expected ',' or ']', but got '<stream end>' at line 2"."""
    problem, mark = getattr(error, "problem", None), getattr(error, "problem_mark", None)
    if not isinstance(problem, str):
        return type(error).__name__
    return f"{problem} at line {mark.line + 1}" if mark is not None else problem


def _flow_depth(text: str) -> int:
    """The deepest nesting of flow collections (``[`` ``{``) in ``text``, outside quotes and comments."""
    brackets = _NOT_BRACKET.sub("", _NOT_FLOW.sub("", text))
    return max(accumulate(1 if c in "[{" else -1 for c in brackets), default=0)


def _size(count: int) -> str:
    return f"{count >> 20} MiB" if count >= 1 << 20 else f"{count >> 10} KiB"


def _check(document: Any) -> None:
    """Walk the document (no recursion), each value shared through aliases once: its nesting depth,
    and its nodes once its aliases are expanded. A document that holds itself is refused."""
    sizes: dict[int, tuple[int, int]] = {}  # id of a collection -> its nodes and levels, expanded
    open_: set[int] = set()  # collections being walked: met again inside one, the document holds itself
    walk: list[tuple[Any, int, bool]] = [(document, 1, False)]  # (value, its depth, its parts walked)
    while walk:
        value, depth, walked = walk.pop()
        parts = _parts(value)
        if parts is None:
            continue
        key = id(value)
        if walked:
            open_.discard(key)
            inner = [sizes.get(id(part), (1, 0)) for part in parts]
            sizes[key] = (1 + sum(nodes for nodes, _ in inner), 1 + max((levels for _, levels in inner), default=0))
            if sizes[key][0] > MAX_NODES:
                raise UserFileError(f"its aliases expand to more than {MAX_NODES} nodes")
        elif key in open_:
            raise UserFileError("it holds itself (an alias inside its own anchor)")
        elif depth + sizes.get(key, (0, 1))[1] - 1 > MAX_DEPTH:
            raise UserFileError(f"nested deeper than {MAX_DEPTH} levels")
        elif key not in sizes:
            open_.add(key)
            walk.append((value, depth, True))
            walk += [(part, depth + 1, False) for part in parts]


def _parts(value: Any) -> list[Any] | None:
    """A mapping's keys and values, a sequence's items; None for a scalar."""
    if isinstance(value, dict):
        return [*value.keys(), *value.values()]
    if isinstance(value, list | set | tuple):
        return list(value)
    return None
