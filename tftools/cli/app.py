"""``tfx``: the entry point, and the one place errors become exit codes.

``tfx --version`` answers before anything else loads; any other command line goes to the typer
application (``tftools.cli.commands``), which imports only the subcommand it runs."""

from __future__ import annotations

import os
import re
import shlex
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from tftools.cli import version_line

if TYPE_CHECKING:
    import typer

    from tftools.core.errors import TfToolsError

#: The exit code of a command stopped by Ctrl-C (SIGINT), as a shell gives it: 128 + 2.
INTERRUPTED = 130


def main() -> None:
    """Run ``tfx``: tftools' errors and wrong arguments print as one line and exit with code 2; so does
    any other exception (an internal error, named as such; ``TFX_DEBUG=1`` shows its traceback), and
    standard output that cannot be written. Ctrl-C, even while tfx starts, is one line and code 130."""
    try:
        code = _run()
    except KeyboardInterrupt:
        code = _interrupted()
    sys.exit(code)


def _blas_threads_sleep_when_idle() -> None:
    """numpy's OpenBLAS, loaded at numpy's import, starts a thread per core that spins ~0.1 s for work before it
    sleeps (its thread timeout, 2**28 cycles): ~65 ms of CPU on the other core while tfx starts and its read
    begins, where the read's decode thread wants it. tfx calls no threaded BLAS, so its idle threads may sleep at
    once (2**4 cycles, OpenBLAS's least). Set here, in tfx's own process, not at ``import tftools``: a library
    does not change its user's process (the user's own value is kept either way)."""
    if "numpy" not in sys.modules:  # OpenBLAS reads it once, when numpy loads it
        os.environ.setdefault("OPENBLAS_THREAD_TIMEOUT", "4")


def _run() -> int:
    if sys.argv[1:] == ["--version"]:  # the one answer that needs neither the parser nor a subcommand
        print(version_line())
        return 0
    _blas_threads_sleep_when_idle()
    from tftools.cli.streams import OutputError, ReaderGone, checked_stdout

    checked_stdout()
    import typer

    from tftools.cli.commands import app
    from tftools.cli.common import Exit, InternalError
    from tftools.core.errors import TfToolsError

    try:
        _ros_arguments()
        _bag_among_frames()
        with _warnings_as_notices():
            code = app(standalone_mode=False, prog_name="tfx")
        if code == INTERRUPTED:  # typer's answer to Ctrl-C in a command: that code, silently
            raise KeyboardInterrupt
        sys.stdout.flush()  # what is still buffered fails here, not after the exit code is decided
    except OutputError as error:
        silence_stdout()
        code = _failed(error)
    except TfToolsError as error:
        code = _failed(error)
    except typer.Abort:
        code = Exit.PROBLEMS
    except typer.TyperException as error:  # click's: an unknown option, a value that is not a number, ...
        code = _usage_error(error)
    except (ReaderGone, BrokenPipeError):  # e.g. `tfx echo ... | head`: the reader had enough
        silence_stdout()
        code = Exit.OK
    except KeyboardInterrupt:
        raise
    except Exception as error:  # a bug in tfx, or a reader's: still never a traceback, unless asked for
        if os.environ.get("TFX_DEBUG"):
            raise
        code = _failed(InternalError(error))
    return int(code or 0)


def _interrupted() -> int:
    """Ctrl-C: one line, whatever was running (even the imports), and what was printed so far kept."""
    try:
        sys.stdout.flush()
    except (OSError, ValueError, KeyboardInterrupt):
        silence_stdout()
    try:
        sys.stderr.write("tfx: interrupted\n")
        sys.stderr.flush()
    except (OSError, ValueError, KeyboardInterrupt):
        pass
    return INTERRUPTED


def silence_stdout() -> None:
    """Send what is left to write (and the interpreter's last flush) to /dev/null: after a closed pipe or
    a failed write, nothing more can or should reach standard output."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.close(devnull)
    except OSError:
        pass


@contextmanager
def _warnings_as_notices() -> Iterator[None]:
    """A library's warning (numpy's, ruamel's) as one line, without the source line Python would add."""
    import warnings

    def show(message: Warning | str, category: type[Warning], filename: str, *_: object, **__: object) -> None:
        print(f"tfx: note: {message} ({category.__name__} in {Path(filename).stem})", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        yield


def _failed(error: TfToolsError) -> int:
    """The error's one line, in the command line's words (``errors.table``), and its exit code."""
    from tftools.cli.common import say_failure
    from tftools.cli.errors import worded

    said, code = worded(error)
    say_failure(said)
    return int(code)


def _usage_error(error: typer.TyperException) -> int:
    """Click's usage errors as tfx's one line, naming the command's --help (no arguments: click printed the help)."""
    from tftools.cli.common import Exit
    from tftools.cli.errors import UsageError

    if type(error).__name__ == "NoArgsIsHelpError":
        return int(Exit.UNUSABLE)
    context = getattr(error, "ctx", None)
    command = getattr(context, "command_path", "") or "tfx"
    message = error.format_message() if hasattr(error, "format_message") else str(error)
    message, meant = _meant_option(message, getattr(context, "command", None))
    return _failed(UsageError(message, _forgotten_bag_option(message) or f"{meant}see {command} --help"))


#: Options a user may write for one tfx has: the wrong word, and the right option (with its value, where it has one).
_MEANT = {
    "--time": ("--at", "--start"), "--stamp": ("--at", "--start"), "--hz": ("--rate",), "--frequency": ("--rate",),
    "--out": ("--output",), "--wait-time": ("--duration",),  # ROS 2 view_frames' listening time
    "--json": ("--format json",), "--jsonl": ("--format jsonl",), "--yaml": ("--format yaml",),
}  # fmt: skip


def _meant_option(message: str, command: object) -> tuple[str, str]:
    """Click's "No such option: --time (Possible options: ...)" as the message without its list, and "did
    you mean --at? " where the command has the option meant (else click's possible options)."""
    found = re.fullmatch(r"No such option: (\S+)(?: \(Possible options: (.*)\)|\s*Did you mean (\S+)\?)?", message)
    if found is None:
        return message, ""
    given, possible = found.group(1), found.group(2) or found.group(3) or ""
    options = {o: param for param in getattr(command, "params", []) for o in param.opts}
    meant = [o for o in _MEANT.get(given.split("=")[0], ()) if _takes(options, *o.split())]
    if meant:
        return f"No such option: {given}", f"did you mean {meant[0]}? "
    return f"No such option: {given}", f"did you mean {possible.replace(', ', ' or ')}? " if possible else ""


def _takes(options: dict[str, Any], option: str, value: str = "") -> bool:
    """Whether the command has ``option``, and it takes ``value`` (among its choices, or named in its help)."""
    param = options.get(option)
    if param is None or not value:
        return param is not None
    choices = getattr(param.type, "choices", None)
    return value in choices if choices else value in re.findall(r"\w+", getattr(param, "help", None) or "")


def _forgotten_bag_option(message: str) -> str:
    """For extra arguments that are bags (``tfx frames robot.bag``): the command line with ``-b`` before them."""
    words = sys.argv[1:]
    if "unexpected extra argument" not in message or not words or words[0] in ("wtf", "report", "diff"):
        return ""
    return _with_b(words, {w for w in words if w in message and _is_bag(w)})


def _ros_arguments() -> None:
    """``tfx echo map base_link _precision:=5``, ``... --ros-args -p use_sim_time:=true``: a ROS tool's node
    arguments (``ros_arguments``), refused with the command line in tfx's options."""
    from tftools.cli.commands import SUBCOMMANDS

    words = sys.argv[1:]
    if not words or words[0] not in SUBCOMMANDS or not any(":=" in w or w == "--ros-args" for w in words[1:]):
        return
    from tftools.cli.commands import options_of
    from tftools.cli.ros_arguments import refuse_ros_arguments

    refuse_ros_arguments(words, options_of(words[0]))


#: Commands that read one recording with -b and take no recording of their own: a recording given where their
#: frames (or topics, or nothing) go is read as with -b.
_READ_WITH_B = ("echo", "monitor", "filter", "frames", "view-frames")


def _bag_among_frames() -> None:
    """``tfx frames robot.bag``, ``tfx echo map base_link robot.bag``: one recording given without -b, where the
    command would otherwise listen to a live system or refuse an extra argument, is read as with -b (``sys.argv``
    gains it: every later step sees the command line it stands for). Several are a ``UsageError`` showing both
    readings: the parts of one split recording (-b each), or each on its own."""
    from tftools.cli.errors import UsageError

    words = sys.argv[1:]
    if (
        not words
        or words[0] not in _READ_WITH_B
        or any(w.startswith(("-b", "--bag")) for w in words)  # -b X, -bX, --bag X, --bag=X
    ):
        return
    bags = {w for i, w in enumerate(words[1:], 1) if _is_bag(w) and not words[i - 1].startswith("-")}
    if len(bags) == 1:
        sys.argv[1:] = [part for w in words for part in (["-b", w] if w in bags else [w])]
    elif bags:
        what = "a topic" if words[0] == "filter" else "a frame" if words[0] in ("echo", "monitor") else "an argument"
        raise UsageError(f"{sorted(bags)[0]} is a bag, not {what}", _with_b(words, bags))


def _is_bag(word: str) -> bool:
    from tftools.sources.storage.locations import names_a_recording

    return names_a_recording(word)


def _with_b(words: list[str], bags: set[str]) -> str:
    if not bags:
        return ""
    fixed = [part for w in words for part in (["-b", w] if w in bags else [w])]
    said = "a bag is read with -b: tfx " + " ".join(shlex.quote(w) for w in fixed)
    if len(bags) == 1:
        return said
    # logs/*.bag in CI: repeated -b joins the parts of one split recording, not recordings of their own
    alone = " ".join(shlex.quote(w) for w in words if w not in bags)
    named = " ".join(shlex.quote(w) for w in words if w in bags)
    return f'{said} (the parts of one recording); each on its own: for b in {named}; do tfx {alone} -b "$b"; done'
