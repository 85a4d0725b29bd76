"""tfx's typer application: a run imports only the subcommand it runs; ``tfx --help`` none (each one's
summary is its docstring's, read from its source)."""

from __future__ import annotations

import ast
import importlib
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
SUBCOMMANDS = ("diff", "echo", "filter", "frames", "monitor", "report", "view-frames", "wtf", "static")


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
            self._built[name] = typer.main.get_command_from_info(
                info, pretty_exceptions_short=True, rich_markup_mode="rich"
            )
        return self._built[name]

    def __setitem__(self, name: str, command: Any) -> None:
        self._built[name] = command

    def __delitem__(self, name: str) -> None:
        raise TypeError("tfx's subcommands are fixed")

    def __iter__(self) -> Iterator[str]:
        return iter(SUBCOMMANDS)

    def __len__(self) -> int:
        return len(SUBCOMMANDS)


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


def _summary(name: str) -> str:
    """The docstring of the subcommand's ``command``, from its module's source (nothing imported)."""
    source = Path(__file__).with_name(f"{name.replace('-', '_')}.py").read_text(encoding="utf-8")
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef) and node.name == "command":
            return ast.get_docstring(node) or ""
    return ""


app = typer.Typer(
    cls=_LazyGroup,
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


def _version(value: bool) -> None:
    if value:
        typer.echo(version_line())
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True, help="Print the version."),
) -> None:
    """Diagnose ROS tf trees."""
