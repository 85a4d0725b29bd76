"""The block YAML that rosbag2 writes (its ``metadata.yaml``, the QoS profiles it holds as strings), read
without a YAML library: ruamel's pure-Python parser takes ~35M instructions for a 1 KB file, 7% of a
``.db3``'s or ``.mcap``'s load. Only a subset is read here, where its meaning is plain: block mappings of
simple keys, block sequences, and scalars that are quoted, an integer, a boolean, null, ``[]``, ``{}`` or
a word; anything else (``None``) is left to the YAML library, whose answer on the subset this one is
(YAML 1.2; ``tests/fuzz/test_yaml_subset_fuzz.py`` compares the two).
"""

from __future__ import annotations

import re
from typing import Any

#: Text outside the subset: a tab, a character not printable ASCII, a comment, an anchor, an alias, a
#: tag, a block scalar, a directive, a flow collection (but an empty one), a complex key.
_OUTSIDE = re.compile(r"[^\n -~]|#|&|\*|!|\||>|%|\?|\{(?!\}$)|\[(?!\]$)|^(?:---|\.\.\.)|\n\n", re.MULTILINE)
_KEY = re.compile(r"([A-Za-z_][A-Za-z0-9_]*):(?: +(.*))?")
#: A plain scalar read as a string: a word of these characters (no space, colon or quote).
_WORD = re.compile(r"[A-Za-z_/][A-Za-z0-9_./-]*")
_INT = re.compile(r"0|-?[1-9][0-9]{0,99}")  # longer: Python's int() may refuse it, as the library's would
_SINGLE = re.compile(r"'((?:[^']|'')*)'")
_DOUBLE = re.compile(r'"((?:[^"\\]|\\["\\nt])*)"')
_ESCAPES = {'\\"': '"', "\\\\": "\\", "\\n": "\n", "\\t": "\t"}
_WORDS: dict[str, Any] = {
    **dict.fromkeys(("true", "True", "TRUE"), True),
    **dict.fromkeys(("false", "False", "FALSE"), False),
    **dict.fromkeys(("null", "Null", "NULL", "~"), None),
}
#: Words whose reading YAML 1.1 and 1.2 disagree on: left to the library.
_AMBIGUOUS = {w for word in ("y", "n", "yes", "no", "on", "off") for w in (word, word.title(), word.upper())}
_MAX_LEVELS = 64


class _OutsideError(Exception):
    """The text is not of the subset."""


def parsed(text: str) -> dict[Any, Any] | list[Any] | None:
    """The block mapping or sequence of ``text``; None when ``text`` is not of the subset."""
    if _OUTSIDE.search(text.rstrip("\n")) is not None:
        return None
    lines = [(len(line) - len(line.lstrip(" ")), line.strip(" ")) for line in text.rstrip("\n").split("\n")]
    if not lines or not lines[0][1] or lines[0][0] != 0:
        return None
    try:
        value, at = _Block(lines).block(0, 0, 0)
    except _OutsideError:
        return None
    return value if at == len(lines) and isinstance(value, dict | list) else None


class _Block:
    def __init__(self, lines: list[tuple[int, str]]) -> None:
        self.lines = lines

    def block(self, at: int, indent: int, level: int) -> tuple[Any, int]:
        """The mapping or sequence whose first line is ``lines[at]``, at ``indent``; and the next line's index."""
        if level > _MAX_LEVELS:
            raise _OutsideError
        text = self.lines[at][1]
        return self.sequence(at, indent, level) if _item(text) else self.mapping(at, indent, level)

    def mapping(self, at: int, indent: int, level: int) -> tuple[dict[Any, Any], int]:
        out: dict[Any, Any] = {}
        while at < len(self.lines) and self.lines[at][0] == indent:
            found = _KEY.fullmatch(self.lines[at][1])
            if found is None or found[1] in out or found[1] in _WORDS or found[1] in _AMBIGUOUS:
                raise _OutsideError
            key, rest = found[1], found[2]
            if rest:
                out[key] = _scalar(rest)
                at = self.ended(at + 1, indent)
                continue
            at += 1
            following = self.lines[at] if at < len(self.lines) else (-1, "")
            if following[0] > indent:
                out[key], at = self.nested(at, following[0], level)
            elif following[0] == indent and (_item(following[1])):
                out[key], at = self.sequence(at, indent, level + 1)  # a sequence under its key, not indented
            else:
                out[key] = None
        return out, self.ended(at, indent)

    def sequence(self, at: int, indent: int, level: int) -> tuple[list[Any], int]:
        out: list[Any] = []
        while at < len(self.lines) and self.lines[at][0] == indent:
            text = self.lines[at][1]
            if text == "-":
                following = self.lines[at + 1] if at + 1 < len(self.lines) else (-1, "")
                if following[0] > indent:
                    value, at = self.nested(at + 1, following[0], level)
                else:
                    value, at = None, at + 1
            elif text.startswith("- "):
                content = text[2:].lstrip(" ")
                inner = indent + len(text) - len(content)
                if _item(content) or _KEY.fullmatch(content):
                    self.lines[at] = (inner, content)  # the item's first line, as if on a line of its own
                    value, at = self.block(at, inner, level + 1)
                else:
                    value = _scalar(content)
                    at = self.ended(at + 1, indent)
            else:
                break  # the key after a sequence under its key: the caller's
            out.append(value)
        return out, at

    def nested(self, at: int, indent: int, level: int) -> tuple[Any, int]:
        """The value on the lines from ``at`` on, more indented than its key: a block, or a plain
        scalar of words continued over lines (folded into one, a space between)."""
        text = self.lines[at][1]
        if _item(text) or _KEY.fullmatch(text):
            return self.block(at, indent, level + 1)
        words = []
        while at < len(self.lines) and self.lines[at][0] >= indent:
            if _WORD.fullmatch(self.lines[at][1]) is None:
                raise _OutsideError
            words.append(self.lines[at][1])
            at += 1
        if len(words) == 1:
            return _scalar(words[0]), at
        return " ".join(words), at

    def ended(self, at: int, indent: int) -> int:
        """``at``, the line after a block or a scalar at ``indent``: one more indented would continue it."""
        if at < len(self.lines) and self.lines[at][0] > indent:
            raise _OutsideError
        return at


def _item(text: str) -> bool:
    """Whether a line (its indentation left out) is a sequence's item."""
    return text == "-" or text.startswith("- ")


def _scalar(text: str) -> Any:
    """The value of a scalar on one line."""
    if text in _WORDS:
        return _WORDS[text]
    if _INT.fullmatch(text):
        return int(text)
    if text in ("[]", "{}"):
        return [] if text == "[]" else {}
    if (quoted := _SINGLE.fullmatch(text)) is not None:
        return quoted[1].replace("''", "'")
    if (quoted := _DOUBLE.fullmatch(text)) is not None:
        return re.sub(r"\\.", lambda m: _ESCAPES[m[0]], quoted[1])
    if _WORD.fullmatch(text) and text not in _AMBIGUOUS:
        return text
    raise _OutsideError
