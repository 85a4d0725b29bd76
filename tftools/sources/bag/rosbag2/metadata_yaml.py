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
        _check(YAML(typ="safe").parse(text))
        return YAML(typ="safe").load(text)
    except (YAMLError, ValueError, RecursionError) as e:
        raise MetadataError(f"not valid YAML ({type(e).__name__})") from None


def _check(events: Any) -> None:
    """Walk the parser's events (no recursion): the nesting depth, and the nodes the document
    would have once its aliases are expanded, counted per anchor."""
    from ruamel.yaml.events import AliasEvent, CollectionEndEvent, CollectionStartEvent, NodeEvent

    sizes: dict[str, int] = {}  # anchor -> nodes of its node
    open_: list[tuple[str | None, int]] = []  # collections open: (anchor, nodes so far)
    total = 0
    for event in events:
        if isinstance(event, CollectionStartEvent):
            open_.append((event.anchor, 1))
            if len(open_) > MAX_DEPTH:
                raise MetadataError(f"nested deeper than {MAX_DEPTH} levels")
            continue
        if isinstance(event, CollectionEndEvent):
            anchor, nodes = open_.pop()
        elif isinstance(event, AliasEvent):
            anchor, nodes = None, sizes.get(event.anchor, 1)
        elif isinstance(event, NodeEvent):  # a scalar
            anchor, nodes = event.anchor, 1
        else:
            continue
        if anchor is not None:
            sizes[anchor] = nodes
        if open_:
            parent_anchor, parent_nodes = open_[-1]
            open_[-1] = (parent_anchor, parent_nodes + nodes)
        else:
            total += nodes
        if nodes > MAX_NODES or total > MAX_NODES:
            raise MetadataError(f"its aliases expand to more than {MAX_NODES} nodes")
