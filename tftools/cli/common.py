"""What every subcommand shares: progress bars, errors, exit codes, frames and formats (reading a recording:
``cli.reading``)."""

from __future__ import annotations

import enum
import functools
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

import typer
from rich.console import Console
from rich.text import Text

from tftools.core.errors import TfToolsError
from tftools.core.frames import frame_name, known_frame
from tftools.render.escape import printable

if TYPE_CHECKING:  # the readers load when a command reads: its --help needs none of them (nor numpy)
    from tftools.core.semantics import Semantics
    from tftools.sources.bag import ProgressCallback


def _console(*, to_stderr: bool) -> Console:
    """Plain strings print as they are: no markup, emoji codes or highlighting (names come from files);
    styles only through ``rich.text.Text`` or an explicit ``markup=True``."""
    console = Console(stderr=to_stderr, highlight=False, soft_wrap=True, markup=False, emoji=False)
    if not console.is_terminal:  # piped or captured: never crop lines to a guessed 80 columns
        console.width = 200
    return console


stdout = _console(to_stderr=False)
stderr = _console(to_stderr=True)


class Exit(enum.IntEnum):
    """Exit codes that scripts and CI can rely on."""

    OK = 0
    PROBLEMS = 1  # the command ran and found problems (failed lookups, wtf errors)
    UNUSABLE = 2  # bad arguments or input that could not be used


class TextOrJson(str, enum.Enum):
    """``--format`` of a command that prints text or one JSON document."""

    text = "text"
    json = "json"


class InternalError(TfToolsError):
    """An exception tfx did not expect: a bug, reported on one line."""

    def __init__(self, error: BaseException) -> None:
        if isinstance(error, MemoryError):
            super().__init__("out of memory")
            self.hint = "narrow the input (fewer bags, --start/--end, --topic), or report it to tftools if it is small"
        else:
            super().__init__(f"internal error: {type(error).__name__}: {error}")
            self.hint = "this is a bug in tfx: please report it with the command; TFX_DEBUG=1 shows the traceback"


def say_failure(error: TfToolsError) -> None:
    """The error and its hint as ``say_error``'s one line."""
    say_error(hinted(str(error), error.hint))


def hinted(message: str, hint: str) -> str:
    """``message (hint)``, or the message alone when there is no hint; ``message; hint`` where parentheses
    would nest (a hint with its own) or follow others (a message that ends with some)."""
    if not hint:
        return message
    return f"{message}; {hint}" if "(" in hint or message.endswith(")") else f"{message} ({hint})"


#: An error line longer than this is cut (tf2's loop error names every frame of a 10,000-frame chain).
MAX_ERROR_CHARS = 2000


def say_error(message: str) -> None:
    """``tfx: error: MESSAGE`` on stderr, on one line whatever the message holds, cut if very long."""
    line = printable(message)
    if len(line) > MAX_ERROR_CHARS:
        cut = len(line) - MAX_ERROR_CHARS + 200
        line = f"{line[: MAX_ERROR_CHARS - 200]} ... ({cut} more characters) ... {line[-200:]}"
    stderr.print(Text("tfx: error:", style="bold red"), Text(line))


def warn(message: str) -> None:
    """``tfx: warning: MESSAGE`` on stderr, on one line whatever the message holds."""
    stderr.print(Text("tfx: warning:", style="yellow"), Text(printable(message)))


def say_hint(message: str) -> None:
    """``hint: MESSAGE`` on stderr, on one line: what a command's output (tf2's words, kept as tf2 says them)
    does not say."""
    stderr.print(Text("hint:", style="dim"), Text(printable(message)))


def say_written(where: str, what: str) -> None:
    """``wrote WHERE: WHAT`` on stderr, once a command has written its file."""
    stderr.print(f"wrote {printable(where)}: {printable(what)}")


#: Local bags larger than this together are read with a progress bar.
LARGE_BYTES = 20_000_000


@contextmanager
def progress_bar(bags: Sequence[str], then: str = "analysing") -> Iterator[ProgressCallback | None]:
    """A bar on stderr of the bytes read, when the local ``bags`` are large and stderr is a terminal; once
    all is read, it says so and ``then`` (what runs next: seconds of checks on a long bag), and pulses."""
    with _bar("reading", None, enabled=sum(local_size(p) for p in bags) > LARGE_BYTES) as update:
        if update is None:
            yield None
            return

        def read(done: int, total: int) -> None:
            if total and done >= total:
                update(completed=done, total=None, description=f"read {total / 1e6:.1f} MB, {then}")
            else:
                update(completed=done, total=total)

        yield read


@contextmanager
def count_bar(what: str, total: int) -> Iterator[Callable[[], None]]:
    """A bar on stderr counting ``what`` done of ``total``, when there are several and stderr is a terminal;
    yields ``advance()``."""
    with _bar(what, total, enabled=total > 1) as update:
        yield (lambda: None) if update is None else lambda: update(advance=1)


@contextmanager
def _bar(label: str, total: int | None, enabled: bool) -> Iterator[Callable[..., None] | None]:
    """A transient bar on stderr, of bytes (``total`` None: known later) or of a count; yields its task's
    ``update`` (None when not drawn)."""
    if not enabled or not stderr.is_terminal:
        yield None
        return
    # imported only when a bar is drawn
    from rich.progress import BarColumn, DownloadColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    counter = DownloadColumn() if total is None else MofNCompleteColumn()
    with Progress(
        TextColumn("{task.description}"), BarColumn(), counter, TimeRemainingColumn(), console=stderr, transient=True
    ) as bar:
        yield functools.partial(bar.update, bar.add_task(label, total=total))


def local_size(location: str) -> int:
    """Bytes of a local bag file or directory; 0 for a URL or what cannot be read."""
    path = Path(location)
    try:
        return path.stat().st_size if path.is_file() else sum(p.stat().st_size for p in path.iterdir())
    except OSError:
        return 0


def frame_arguments(frames: Sequence[str], given: Sequence[str], semantics: Semantics) -> list[str]:
    """Frames given on the command line, each of which must be one of ``frames``: a leading ``/`` dropped, as ROS
    1's tf_echo drops it; said where the data's tf2 is ROS 2's, which refuses it (``slash_dropped``)."""
    names = [known_frame(frames, frame) for frame in given]
    slash_dropped(given, semantics)
    return names


def slash_dropped(given: Sequence[str], semantics: Semantics) -> None:
    """One hint where frames ``given`` with a leading ``/`` are looked up without it on ROS 2's tf2, whose lookups
    refuse such a name (tf2_echo /map waits for ever, each second "in tf2 frame_ids cannot start with a '/'")."""
    slashed = [frame for frame in given if frame.startswith("/")]
    if not slashed or semantics != "ros2":
        return
    names = [frame_name(frame) for frame in slashed]
    say_hint(
        f"{', '.join(slashed)} looked up as {', '.join(names)}, as ROS 1's tf_echo does: ROS 2's tf2 refuses a "
        f"frame id that starts with '/' (\"in tf2 frame_ids cannot start with a '/'\"), so a ROS 2 node asks for "
        f"{' and '.join(names)}"
    )


def exit_with(code: Exit) -> NoReturn:
    raise typer.Exit(int(code))
