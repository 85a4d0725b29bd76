"""``tfx``: the entry point, and the one place errors become exit codes.

``tfx --version`` answers before anything else loads; any other command line goes to the typer
application (``tftools.cli.commands``), which imports only the subcommand it runs."""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import typer

    from tftools.core.errors import TfToolsError


def version_line() -> str:
    """``tfx --version``'s answer."""
    from tftools import version

    return f"tfx {version()}"


def main() -> None:
    """Run ``tfx``: tftools' errors and wrong arguments print as one line and exit with code 2; so does
    any other exception (an internal error, named as such; ``TFX_DEBUG=1`` shows its traceback)."""
    if sys.argv[1:] == ["--version"]:  # the one answer that needs neither the parser nor a subcommand
        print(version_line())
        sys.exit(0)
    import typer

    from tftools.cli.commands import app
    from tftools.cli.common import Exit, InternalError
    from tftools.core.errors import TfToolsError

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


def _failed(error: TfToolsError) -> int:
    """The error's one line, and its exit code."""
    from tftools.cli.common import Exit, say_failure

    say_failure(error)
    return int(Exit.UNUSABLE)


def _usage_error(error: typer.TyperException) -> int:
    """Click's usage errors as tfx's one line, naming the command's --help (no arguments: click printed the help)."""
    from tftools.cli.common import Exit, UsageError

    if type(error).__name__ == "NoArgsIsHelpError":
        return int(Exit.UNUSABLE)
    context = getattr(error, "ctx", None)
    command = getattr(context, "command_path", "") or "tfx"
    message = error.format_message() if hasattr(error, "format_message") else str(error)
    return _failed(UsageError(message, f"see {command} --help"))
