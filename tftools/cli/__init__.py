"""The ``tfx`` command line: parses options, calls the library, renders."""
