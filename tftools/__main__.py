"""``python -m tftools``: the ``tfx`` command."""

from tftools.cli.app import main

main()
