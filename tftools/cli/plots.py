"""``--plot FILE`` of ``tfx echo`` and ``tfx monitor``: the picture checked before any work, written after."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from tftools.cli.common import say_written
from tftools.cli.errors import UsageError
from tftools.cli.outputs import check_output, check_replaceable

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: What ``--plot`` says of its file in each command's help (``\\[``: not rich markup).
PLOT_FILE = "a .png, .svg or .pdf file; needs matplotlib: pip install 'tftools\\[plot]'"


def check_plot(plot: Path | None, inputs: Sequence[str] | None, force: bool) -> None:
    """A picture ``--plot`` can write (None: none asked for): matplotlib installed, a suffix it draws,
    never over or into an input, nor over a file without ``force``."""
    from tftools.render.plots import SUFFIXES, plot_format, require_matplotlib

    if plot is None:
        return
    if plot_format(plot) is None:
        raise UsageError(
            f"--plot {plot}: not a picture tfx draws", f"name a {', '.join(SUFFIXES)} file, e.g. --plot {plot.stem}.png"
        )
    check_output(plot, inputs or [], option="--plot", file_name="plot.png")
    check_replaceable(plot, force, "--plot")
    require_matplotlib()


def write_plot(figure: Figure, plot: Path, what: str) -> None:
    """Write the picture, and say so on stderr."""
    from tftools.render.plots import write_figure

    write_figure(figure, plot)
    say_written(str(plot), what)
