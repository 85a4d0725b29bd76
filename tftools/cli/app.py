"""``tfx``: the application, its subcommands, and the one place errors become exit codes."""

from __future__ import annotations

import os
import sys

import typer

from tftools import __version__
from tftools.cli import echo, filter, frames, monitor, report, static, view_frames, wtf
from tftools.cli.common import Exit, UsageError, fail
from tftools.core.errors import TfToolsError

app = typer.Typer(
    name="tfx",
    help="Diagnose ROS tf trees: on bag files (ROS1 .bag, ROS2 .db3/.mcap, MCAP) in seconds, and live "
    "on ROS1 and ROS2 systems (without -b), with tf2's exact semantics.\n\nExamples:\n\n"
    "  tfx frames -b robot.bag\n\n"
    "  tfx echo map base_link -b robot.bag --rate 2\n\n"
    "  tfx wtf logs/*.bag\n\n"
    "  tfx monitor --ros2\n\n"
    "Exit codes: 0 fine, 1 problems found (failed lookups, checker errors), 2 unusable input.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode="rich",
    context_settings={"help_option_names": ["-h", "--help"]},
)
app.command("echo")(echo.command)
app.command("filter")(filter.command)
app.command("frames")(frames.command)
app.command("monitor")(monitor.command)
app.command("report")(report.command)
app.command("view-frames")(view_frames.command)
app.command("wtf")(wtf.command)
app.command("static", context_settings=static.CONTEXT)(static.command)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"tfx {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True, help="Print the version."),
) -> None:
    """Diagnose ROS tf trees."""


def main() -> None:
    """Run ``tfx``: tftools' errors and wrong arguments print as one line and exit with code 2; so does
    any other exception (an internal error, named as such; ``TFX_DEBUG=1`` shows its traceback)."""
    try:
        code = app(standalone_mode=False)
    except TfToolsError as error:
        code = _failed(error)
    except typer.Abort:
        code = Exit.PROBLEMS
    except typer.TyperException as error:  # click's: an unknown option, a value that is not a number, ...
        code = _usage_error(error)
    except BrokenPipeError:  # e.g. `tfx echo ... | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        code = Exit.OK
    except KeyboardInterrupt:
        code = 130
    except Exception as error:  # a bug in tfx, or a reader's: still never a traceback, unless asked for
        if os.environ.get("TFX_DEBUG"):
            raise
        code = _failed(InternalError(error))
    sys.exit(int(code or 0))


class InternalError(TfToolsError):
    """An exception tfx did not expect: a bug, reported on one line."""

    def __init__(self, error: BaseException) -> None:
        if isinstance(error, MemoryError):
            super().__init__("out of memory")
            self.hint = "narrow the input (fewer bags, --start/--end, --topic), or report it to tftools if it is small"
        else:
            super().__init__(f"internal error: {type(error).__name__}: {error}")
            self.hint = "this is a bug in tfx: please report it with the command; TFX_DEBUG=1 shows the traceback"


def _failed(error: TfToolsError) -> int:
    """``fail``'s one line, and its exit code."""
    try:
        fail(error)
    except typer.Exit as done:
        return int(done.exit_code)


def _usage_error(error: typer.TyperException) -> int:
    """Click's usage errors as tfx's one line, naming the command's --help (no arguments: click printed the help)."""
    if type(error).__name__ == "NoArgsIsHelpError":
        return int(Exit.UNUSABLE)
    context = getattr(error, "ctx", None)
    command = getattr(context, "command_path", "") or "tfx"
    message = error.format_message() if hasattr(error, "format_message") else str(error)
    return _failed(UsageError(message, f"see {command} --help"))
