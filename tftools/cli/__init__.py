"""The ``tfx`` command line: parses options, calls the library, renders."""

from __future__ import annotations

from tftools import __version__

#: What ``tfx --version`` prints (``cli.app`` answers it before the parser loads; ``cli.commands`` after).
VERSION_LINE = f"tfx {__version__}"
