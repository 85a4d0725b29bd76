"""The ``tfx`` command line: parses options, calls the library, renders."""

from __future__ import annotations


def version_line() -> str:
    """What ``tfx --version`` prints (``cli.app`` answers it before the parser loads; ``cli.commands`` after)."""
    from tftools import version

    return f"tfx {version()}"
