"""What reaches a terminal from a name: line and paragraph separators are escaped like newlines."""

from __future__ import annotations

import pytest

from tftools.render.escape import is_printable, printable


@pytest.mark.parametrize(("name", "shown"), [("a\u2028b", "a\\u2028b"), ("a\u2029b", "a\\u2029b"), ("a\nb", "a\\nb")])
def test_a_name_that_would_break_the_line_is_shown_escaped(name: str, shown: str) -> None:
    assert printable(name) == shown and not is_printable(name)


def test_other_unicode_is_left_as_it_is() -> None:
    assert printable("caméra_ß_链接") == "caméra_ß_链接"
