"""tfx's typer application: a run imports only the subcommand it runs; ``tfx --help`` none (each one's
summary is its docstring's, read from its source)."""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from collections.abc import Iterator, MutableMapping
from pathlib import Path
from typing import Any

import typer
import typer.core
import typer.main
import typer.models
from typer import _click as click  # the click typer's commands are made of (typer vendors it)

from tftools.cli import version_line

#: Each a module of ``tftools.cli`` (``view-frames``: ``view_frames``): its ``command``, and ``CONTEXT`` if any.
#: In the order a new user needs them (``tfx --help`` lists them so): check, look, the ROS tools' counterparts,
#: then comparing and writing.
SUBCOMMANDS = ("wtf", "report", "frames", "echo", "monitor", "view-frames", "filter", "diff", "static")


class _Subcommands(MutableMapping[str, Any]):
    """The group's click commands by name (click's or typer's: ``Any``), each built from its module on
    first use; listing their names imports nothing."""

    def __init__(self) -> None:
        self._built: dict[str, Any] = {}

    def __getitem__(self, name: str) -> Any:
        if name not in SUBCOMMANDS:
            raise KeyError(name)
        if name not in self._built:
            module = importlib.import_module(f"tftools.cli.{name.replace('-', '_')}")
            info = typer.models.CommandInfo(
                name, callback=module.command, context_settings=getattr(module, "CONTEXT", None)
            )
            command = typer.main.get_command_from_info(info, pretty_exceptions_short=True, rich_markup_mode="rich")
            self._built[name] = _readable_at_80(command)
        return self._built[name]

    def __setitem__(self, name: str, command: Any) -> None:
        self._built[name] = command

    def __delitem__(self, name: str) -> None:
        raise TypeError("tfx's subcommands are fixed")

    def __iter__(self) -> Iterator[str]:
        return iter(SUBCOMMANDS)

    def __len__(self) -> int:
        return len(SUBCOMMANDS)


def options_of(name: str) -> set[str]:
    """The options of subcommand ``name`` (its module imported), both of a pair: --use-sim-time, --wall-time."""
    command = _Subcommands()[name]
    return {o for param in command.params for o in (*param.opts, *param.secondary_opts)}


class _LazyGroup(typer.core.TyperGroup):
    """A typer group whose subcommands are ``_Subcommands``; its help lists them without importing them."""

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        self.commands = _Subcommands()
        self._listing = False

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(SUBCOMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if self._listing and cmd_name in SUBCOMMANDS:  # the help's list: each name and its summary
            return typer.core.TyperCommand(cmd_name, help=_summary(cmd_name))
        return super().get_command(ctx, cmd_name)

    def format_help(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        self._listing = True
        try:
            super().format_help(ctx, formatter)
        finally:
            self._listing = False


#: A choice's values are shown as its type where they are this short, else its name (the help lists them).
_CHOICES_SHOWN = 16
#: What an option's value is, where its help names it so ("Begin at TIME"): rather than ``<str>``.
_VALUES = {"--bag": "BAG", "--start": "TIME", "--end": "TIME", "--at": "TIME", "--topic": "TOPIC", "--sensor": "TOPIC",
           "--target": "FRAME", "--output": "FILE"}  # fmt: skip


def unwrapped(text: str) -> str:
    """A docstring's paragraphs each on one line: rich wraps them to the terminal (lines broken in the
    source at 100 columns would be broken again at 80, raggedly)."""
    paragraphs = [" ".join(line.strip() for line in p.splitlines()) for p in inspect.cleandoc(text).split("\n\n")]
    return "\n\n".join(_examples(p) if p.startswith("Examples:") else p for p in paragraphs)


def _examples(paragraph: str) -> str:
    """An "Examples:" paragraph (each example in ``[cyan]...[/]``, what follows it a remark) as one example a
    line, indented, kept as it is by click (its ``\\b``)."""
    from rich.text import Text

    found = re.findall(r"\[cyan\](.*?)\[/\]([^\[]*)", paragraph)
    lines = [
        f"  {Text.from_markup(example, emoji=False).plain} {remark.strip(' ,')}".rstrip() for example, remark in found
    ]
    return "\b\nExamples:\n" + "\n".join(lines)


def _plain(text: str) -> str:
    """Help text without rich's markup (``[cyan]...[/]``, ``\\[fleet]``), click's ``\\b`` kept (rich drops it). No
    emoji codes (none is meant): replacing them imported their table, 2 ms of every command's start-up."""
    from rich.text import Text

    return "\n\n".join(Text.from_markup(p, emoji=False).plain if p[:1] != "\b" else p for p in text.split("\n\n"))


def _readable_at_80(command: Any) -> Any:
    """``command`` with its help as click lays it out (options and their help in two columns, which
    read at 80 columns where rich's table of five squeezes the help into 20), its docstring unwrapped
    and its choices' long lists of values (``<text|json|jsonl|junit>``) named by their option instead."""
    command.rich_markup_mode = None
    command.help = _plain(unwrapped(command.help or ""))
    for param in command.params:
        if getattr(param, "help", None):
            param.help = _plain(param.help)
    usage = [command.options_metavar]
    for param in command.params:
        if param.param_type_name == "argument":  # TARGET SOURCE, [BAG]...: not {target} {source}, [BAG] for many
            name = (param.metavar or param.name or "").upper()
            param.metavar = name
            usage.append((name if param.required else f"[{name}]") + ("..." if param.nargs != 1 else ""))
        named = [_VALUES[o] for o in param.opts if o in _VALUES]
        if named and param.metavar is None:
            param.metavar = named[0]
        choices = getattr(param.type, "choices", None)
        if choices and param.metavar is None:
            values = "|".join(str(getattr(c, "value", c)) for c in choices)
            param.metavar = (
                f"<{values}>" if len(values) <= _CHOICES_SHOWN else max(param.opts, key=len).strip("-").upper()
            )
    command.collect_usage_pieces = lambda ctx: usage
    return command


def _summary(name: str) -> str:
    """The docstring of the subcommand's ``command``, from its module's source (nothing imported)."""
    source = Path(__file__).with_name(f"{name.replace('-', '_')}.py").read_text(encoding="utf-8")
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef) and node.name == "command":
            return unwrapped(ast.get_docstring(node) or "")
    return ""


app = typer.Typer(
    cls=_LazyGroup,
    name="tfx",
    help="Diagnose ROS tf trees: on bag files (ROS1 .bag, ROS2 .db3/.mcap, MCAP) in seconds, and live "
    "on ROS1 and ROS2 systems (without -b), with tf2's exact semantics.\n\nExamples:\n\n"
    "  tfx wtf logs/*.bag\n\n"
    "  tfx report -b robot.bag -o robot.html\n\n"
    "  tfx echo map base_link -b robot.bag --rate 2\n\n"
    "  tfx monitor --ros2\n\n"
    "Exit codes: 0 fine, 1 problems found (failed lookups, checker errors), 2 unusable input.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode="rich",
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _version(value: bool) -> None:
    if value:
        typer.echo(version_line())
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True, help="Print the version."),
) -> None:
    """Diagnose ROS tf trees."""
