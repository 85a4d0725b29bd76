"""``--plot``: ``tfx echo``'s transform and ``tfx monitor``'s rates and delays over time, drawn by matplotlib
into a PNG, SVG or PDF file (the ``plot`` extra: ``pip install 'tftools[plot]'``)."""

from __future__ import annotations

import io
import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from tftools.analysis.echo import EchoSeries
from tftools.analysis.timelines import EdgeSeries
from tftools.core.errors import TfToolsError
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S, format_sec
from tftools.render.escape import printable
from tftools.render.files import write_atomically

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


#: The pictures ``--plot`` writes, by the output's suffix.
SUFFIXES = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
INSTALL_HINT = "install it: pip install 'tftools[plot]'"
WIDTH_IN = 11.0
DPI = 110
#: Edges drawn in one monitor plot, and named in its legend; a larger tree's busiest edges.
MOST_EDGES = 20


class PlotUnavailableError(TfToolsError):
    """matplotlib is not installed: nothing can be plotted."""

    hint = INSTALL_HINT


def require_matplotlib() -> None:
    """Raise ``PlotUnavailableError`` now, before any work, when matplotlib cannot be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise PlotUnavailableError("plotting needs matplotlib, which is not installed") from None


def plot_format(path: str | os.PathLike[str]) -> str | None:
    """The picture format ``path``'s suffix names (None: not one ``--plot`` writes)."""
    return SUFFIXES.get(Path(path).suffix.lower())


def echo_figure(series: EchoSeries) -> Figure:
    """Translation (m) and roll, pitch, yaw (degrees) of ``series`` over time; failed lookups leave gaps."""
    figure, moves, turns = _figure()
    times = (series.times - (series.times[0] if len(series) else 0)) / NS_PER_S
    translations = np.where(series.valid[:, None], series.translations, np.nan)
    angles = np.degrees(np.where(series.valid[:, None], series.rpy, np.nan))
    marker = "." if len(times) < 200 else None
    for axis, values, names, unit in (
        (moves, translations, "xyz", "translation (m)"),
        (turns, angles, ("roll", "pitch", "yaw"), "rotation (degrees)"),
    ):
        for column, name in enumerate(names):
            axis.plot(times, values[:, column], label=name, marker=marker, markersize=3, linewidth=1.2)
        axis.set_ylabel(unit)
        axis.grid(True, alpha=0.3)
        axis.legend(loc="upper left", fontsize=8, ncols=3)
    turns.set_xlabel(_time_label(int(series.times[0]) if len(series) else None))
    failed = int((~series.valid).sum())
    said = f", {failed} of {len(series)} lookups failed" if failed else ""
    moves.set_title(printable(f"{series.source} in {series.target} ({series.target} <- {series.source}){said}"))
    return figure


def monitor_figure(edges: Sequence[EdgeSeries], title: str) -> Figure:
    """Each edge's rate (Hz) and mean delay (ms) over time, the ``MOST_EDGES`` fastest of them."""
    figure, rates, delays = _figure()
    shown = sorted(edges, key=lambda e: -float(np.nan_to_num(np.nanmax(e.rate_hz, initial=0.0))))[:MOST_EDGES]
    origin = min((int(e.times[0]) for e in shown if len(e.times)), default=0)
    for e in shown:
        times = (e.times - origin) / NS_PER_S
        line = rates.plot(times, e.rate_hz, linewidth=1.2, label=printable(f"{e.parent} -> {e.child}"))[0]
        delays.plot(times, seconds(e.delay) * 1000, linewidth=1.2, color=line.get_color())
    rates.set_ylabel("rate (Hz)")
    delays.set_ylabel("mean delay (ms)")
    for axis in (rates, delays):
        axis.grid(True, alpha=0.3)
        axis.set_ylim(bottom=0)
    delays.set_xlabel(_time_label(origin))
    left = len(edges) - len(shown)
    rates.set_title(printable(title) + (f" ({left} slower edges not drawn)" if left else ""))
    if shown:
        rates.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    if all(math.isnan(v) for e in shown for v in e.delay.tolist()):
        delays.text(0.5, 0.5, "delays unavailable", transform=delays.transAxes, ha="center", color="#777777")
    return figure


def write_figure(figure: Figure, path: str | os.PathLike[str]) -> Path:
    """Write ``figure`` in the format of ``path``'s suffix, whole or not at all."""
    picture = io.BytesIO()
    figure.savefig(picture, format=plot_format(path) or "png", dpi=DPI, bbox_inches="tight")
    return write_atomically(path, picture.getvalue())


def _figure() -> tuple[Figure, Axes, Axes]:
    """A figure of two plots, one above the other, on one time axis."""
    from matplotlib.figure import Figure  # a figure of its own: no pyplot, no display, no global state

    figure = Figure(figsize=(WIDTH_IN, 6.4), layout="constrained")
    top, bottom = figure.subplots(2, 1, sharex=True)
    return figure, top, bottom


def _time_label(origin: int | None) -> str:
    return "time (s)" if origin is None else f"time (s) from {format_sec(origin, 3)}"
