"""Strings from files and peers made safe to print: control characters shown as visible escapes."""

from __future__ import annotations

import re
from functools import cache

#: Invisible characters that reorder or hide text on a terminal ("Trojan Source"): shown escaped too.
BIDI_CONTROLS = frozenset("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")
_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}
#: Unicode's line and paragraph separators: a terminal or a log viewer may break the line there.
LINE_SEPARATORS = frozenset("\u2028\u2029")
#: Characters a terminal may act on instead of showing: C0 and C1 controls, DEL, lone surrogates
#: (bytes that were not UTF-8, kept by ``surrogateescape``), bidi controls, line separators.
_UNSAFE = re.compile(r"[\x00-\x1f\x7f-\x9f\ud800-\udfff" + "".join(sorted(BIDI_CONTROLS | LINE_SEPARATORS)) + "]")


@cache
def _escaped(char: str) -> str:
    if char in _NAMED:
        return _NAMED[char]
    code = ord(char)
    if 0xDC80 <= code <= 0xDCFF:  # a byte that was not UTF-8, as ``surrogateescape`` keeps it
        return f"\\x{code - 0xDC00:02x}"
    if code <= 0xFF:
        return f"\\x{code:02x}"
    return f"\\u{code:04x}"


def printable(text: str) -> str:
    """``text`` as it may reach a terminal: one line, nothing a terminal would act on.

    Newlines, tabs and carriage returns become ``\\n``, ``\\t``, ``\\r``; other control characters
    (the ESC of ANSI escape sequences, BEL, DEL, C1) ``\\xNN``; bidi overrides and line separators
    ``\\uNNNN``; bytes that were not UTF-8 ``\\xNN``. Everything else, backslashes included, is left as it is."""
    return _UNSAFE.sub(lambda m: _escaped(m.group()), text)


def printable_lines(text: str) -> str:
    """Each line of ``text`` made ``printable``, each ending in a newline."""
    return "".join(printable(line) + "\n" for line in text.removesuffix("\n").split("\n"))


def is_printable(text: str) -> bool:
    """True when ``printable`` would leave ``text`` unchanged."""
    return _UNSAFE.search(text) is None
