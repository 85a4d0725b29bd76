"""A rosbag2 ``metadata.yaml`` read within limits: its size, nesting and aliases (a "billion laughs")."""

from __future__ import annotations

from pathlib import Path
from typing import Any

MAX_BYTES = 4 << 20  # a metadata.yaml of a thousand topics is well under 1 MiB
MAX_DEPTH = 64  # rosbag2 writes 5 levels
MAX_NODES = 1 << 20  # nodes once every alias is expanded: a billion laughs has 10**9


class MetadataError(Exception):
    """A metadata.yaml that is not read (the message says why, in a few words)."""


def load(path: Path) -> Any:
    """The document of the YAML file at ``path``. Raises ``MetadataError`` for a file too large,
    too deep, expanding to too many nodes through its aliases, or not YAML."""
    try:
        if not path.is_file():  # a FIFO would block: refused unopened
            raise MetadataError("not a regular file")
        with path.open("rb") as f:
            raw = f.read(MAX_BYTES + 1)
    except OSError as e:
        raise MetadataError(e.strerror or str(e)) from None
    if len(raw) > MAX_BYTES:
        raise MetadataError(f"larger than {MAX_BYTES >> 20} MiB")
    return load_text(raw.decode("utf-8", "replace"))


def load_text(text: str) -> Any:
    """The document of YAML ``text`` (a QoS profile list that metadata.yaml holds as a string),
    within the same limits as ``load``."""
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    if len(text) > MAX_BYTES:
        raise MetadataError(f"larger than {MAX_BYTES >> 20} MiB")
    try:
        # An alias is constructed as a reference to its anchor's value, not a copy: the document
        # is built in the time its text takes, however far its aliases would expand.
        document = YAML(typ="safe").load(text)
    except RecursionError:  # the composer recurses once per level
        raise MetadataError(f"nested deeper than {MAX_DEPTH} levels") from None
    except (YAMLError, ValueError) as e:
        raise MetadataError(f"not valid YAML ({type(e).__name__})") from None
    _check(document)
    return document


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
                raise MetadataError(f"its aliases expand to more than {MAX_NODES} nodes")
        elif key in open_:
            raise MetadataError("it holds itself (an alias inside its own anchor)")
        elif depth + sizes.get(key, (0, 1))[1] - 1 > MAX_DEPTH:
            raise MetadataError(f"nested deeper than {MAX_DEPTH} levels")
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
