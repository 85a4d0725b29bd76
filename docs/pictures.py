"""Draw the documentation's pictures of tfx's output (run from the clone, after scripts/setup.sh):

    .venv/bin/python docs/pictures.py

Terminal output is run on a pseudo-terminal (its colours as a person sees them), recorded by rich as SVG and
photographed by headless Chromium; view-frames' PDF is turned into a PNG by pdftoppm. Each picture lands in
docs/pictures/."""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from rich.console import Console
from rich.text import Text

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
from tests.cli.terminal import raw_terminal  # noqa: E402  (the tests' pseudo-terminal, from the clone)

OUT = REPO / "docs" / "pictures"
#: The pictures' width in pixels: as wide as a README column shows them.
WIDTH = 900
CORPUS = Path(os.environ.get("TFTOOLS_SHARED_DIR", REPO.parent.parent / "shared")) / "corpus"


def picture(name: str, title: str, args: list[str], columns: int, cwd: Path = REPO) -> None:
    """The terminal's text as ``name``.png: rich's SVG of it, photographed at its size."""
    console = Console(record=True, width=columns, force_terminal=True, file=io.StringIO())
    _, output = raw_terminal(args, columns, 60, cwd, stderr=False)  # its progress bars left out
    console.print(Text.from_ansi(output.rstrip("\n")), soft_wrap=False)
    with tempfile.TemporaryDirectory() as folder:
        svg = Path(folder) / f"{name}.svg"
        svg.write_text(console.export_svg(title=title))
        width, height = _svg_size(svg.read_text())
        height = round(height * WIDTH / width)
        page = Path(folder) / f"{name}.html"
        page.write_text(
            f'<html><body style="margin:0;background:#fff"><img src="{svg.name}" width="{WIDTH}"></body></html>'
        )
        chromium = shutil.which("chromium") or shutil.which("chromium-browser") or "chromium"
        shot = Path(folder) / f"{name}.png"
        subprocess.run(
            [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", f"--screenshot={shot}",
             f"--window-size={WIDTH},{height}", page.as_uri()], check=True, capture_output=True,
        )  # fmt: skip
        shutil.copy(shot, OUT / f"{name}.png")


def _svg_size(svg: str) -> tuple[int, int]:
    import re

    box = re.search(r'viewBox="0 0 ([0-9.]+) ([0-9.]+)"', svg)
    assert box is not None
    return int(float(box.group(1))) + 1, int(float(box.group(2))) + 1


def frames_picture() -> None:
    """view-frames' PDF of a TurtleBot 3 simulation recorded with two robot_state_publishers, as a PNG."""
    with tempfile.TemporaryDirectory() as folder:
        pdf = Path(folder) / "frames.pdf"
        bag = CORPUS / "ros2_db3_tb3_gazebo_two_rsp"
        subprocess.run([sys.executable, "-m", "tftools", "view-frames", "-b", str(bag), "-o", str(pdf)],
                       cwd=REPO, check=True, capture_output=True)  # fmt: skip
        subprocess.run(["pdftoppm", "-png", "-scale-to-x", str(WIDTH), "-scale-to-y", "-1", "-singlefile", str(pdf),
                        str(OUT / "view-frames")], check=True)  # fmt: skip


def report_picture() -> None:
    """The report of the tests' troubled robot (a pause, a stop, a re-parenting, a camera in a frame that is
    not in the tree) as Chromium shows it 1400 pixels wide: docs/report.png."""
    from tests.browser import screenshot
    from tests.render.report_scenes import troubled_bags

    with tempfile.TemporaryDirectory() as folder:
        bag = troubled_bags(Path(folder))["ros1"]
        subprocess.run([sys.executable, "-m", "tftools", "report", "-b", bag.name, "-o", "robot.html"], cwd=bag.parent,
                       capture_output=True)  # fmt: skip
        screenshot(bag.parent / "robot.html", REPO / "docs" / "report.png", width=1400, height=2100)


def main() -> None:
    OUT.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:  # the recordings under short names
        shutil.copy(CORPUS / "ros1_gazebo_kobuki_repeated_stamps.bag", Path(folder) / "kobuki.bag")
        shutil.copy(CORPUS / "ros1_neato_square_dance.bag", Path(folder) / "neato.bag")
        picture("wtf", "tfx wtf kobuki.bag neato.bag", ["wtf", "kobuki.bag", "neato.bag"], 100, Path(folder))
    picture("monitor", "tfx monitor -b sample_bags/robot.bag", ["monitor", "-b", "sample_bags/robot.bag"], 100)
    frames_picture()
    report_picture()


if __name__ == "__main__":
    main()
