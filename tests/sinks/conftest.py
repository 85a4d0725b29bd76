"""The in-process ``tfx`` fixture, for the sinks written through the command line."""

from tests.cli.conftest import tfx  # noqa: F401
