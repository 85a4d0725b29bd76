"""Renderers: analyses turned into text, JSON, CSV, YAML, graphs and pages.

The names load on first use (PEP 562): each brings only its own modules (Graphviz's, for the graph)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy

if TYPE_CHECKING:
    from tftools.render.drawing import draw, write_graph
    from tftools.render.graph import recording_legend, to_digraph
    from tftools.render.report import page

__all__ = ["draw", "page", "recording_legend", "to_digraph", "write_graph"]

#: Where each name is defined.
_HOME = {
    "draw": "tftools.render.drawing",
    "page": "tftools.render.report",
    "recording_legend": "tftools.render.graph",
    "to_digraph": "tftools.render.graph",
    "write_graph": "tftools.render.drawing",
}

__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
