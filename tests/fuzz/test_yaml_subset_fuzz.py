"""The block YAML read without a YAML library (``sources/yaml_subset.py``) against ruamel's reading of
the same text: documents of rosbag2's shapes written in several styles, and mutants of them (a line
re-indented, dropped or doubled, a character put in); wherever the subset reads a text, ruamel reads
the same values of the same types, and wherever ruamel refuses a text the subset does not read it.

``TFTOOLS_FUZZ_EXAMPLES`` raises the number of examples (default: a quick run for CI).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from ruamel.yaml import YAML

from tests.corpus.fetch import shared_dir
from tftools.sources import yaml_subset

EXAMPLES = int(os.environ.get("TFTOOLS_FUZZ_EXAMPLES", "300"))
FUZZ = settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ROOT = Path(__file__).resolve().parents[2]
CORPUS = shared_dir() / "corpus"  # the real recordings, where this checkout has them

#: Keys and scalars as rosbag2 writes them, mostly; among them, some that the subset leaves to the library.
KEYS = ["name", "type", "version", "files", "a_b", "x1", "key"] * 4 + ["true", "null", "y", "on", "No", "1", "a b"]
INSIDE = [
    "0", "7", "-3", "1700000000001000000", "12345678901234567890123456789", "true", "False", "TRUE", "null",
    "Null", "~", "nan", "inf", "sqlite3", "/tf", "tf2_msgs/msg/TFMessage", "RIHS01_e369d0f0", "robot_300s.db3",
    "a-b", "_x", "[]", "{}", "''", '""', "'it''s'", "'a: b, c'", '"say \\"hi\\""', '"a\\nb"', '"tab\\tx"',
    '"- history: 3\\n  depth: 0"',
]  # fmt: skip
#: Scalars outside the subset (the library's to read or refuse), and words with a meaning of their own.
ODD = [
    "0123", "+5", "1_000", "0x1f", "0o17", "1.5", "1e3", ".inf", "-.inf", ".nan", "tRue", "yes", "No", "on",
    "OFF", "y", "n", "-", "a b", "a:b", "a: b", "x #c", "[1]", "{a: 1}", "'a'b'", '"\\x41"', '"\\/"',
    '"unterminated', "'open", "2023-01-01", "&a x", "*a", "!!str 5", "|", ">", "%x", "@x", "`x", "?x", "é",
    "a\tb",
]  # fmt: skip
SCALARS = INSIDE * 10 + ODD


def _canonical(value: Any) -> Any:
    """``value`` with each scalar's type beside it, so that 1, 1.0 and True differ."""
    if isinstance(value, dict):
        return ("map", [(_canonical(k), _canonical(v)) for k, v in value.items()])
    if isinstance(value, list):
        return ("seq", [_canonical(v) for v in value])
    return (type(value).__name__, value)


def _ruamel(text: str) -> tuple[bool, Any]:
    try:
        return True, YAML(typ="safe").load(text)
    except Exception:  # any refusal: the subset must not read the text
        return False, None


def _render(value: Any, draw: st.DrawFn, indent: int = 0) -> list[str]:
    """Lines of ``value`` (a mapping or sequence of scalars' texts), each style drawn."""
    pad = " " * indent
    lines: list[str] = []
    items = value.items() if isinstance(value, dict) else [(None, v) for v in value]
    for key, item in items:
        head = f"{pad}{key}:" if key is not None else f"{pad}-" + " " * draw(st.integers(1, 3))
        if isinstance(item, dict | list) and item:
            if key is None:
                inner = _render(item, draw, len(head))
                lines.append(head + inner[0].lstrip(" "))
                lines += inner[1:]
            else:
                under = 0 if isinstance(item, list) and draw(st.booleans()) else draw(st.integers(1, 4))
                lines.append(head)
                lines += _render(item, draw, indent + under)
        elif isinstance(item, str) and key is not None and draw(st.integers(0, 9)) == 0:
            lines.append(head)  # the scalar on the lines after its key, folded
            lines += [f"{pad}  {word}" for word in item.split(" ")]
        else:
            lines.append(f"{head}{item}" if key is None else f"{head} {item}")
    return lines


@st.composite
def documents(draw: st.DrawFn) -> str:
    scalar = st.sampled_from(SCALARS)
    tree = st.recursive(
        st.dictionaries(st.sampled_from(KEYS), scalar, min_size=1, max_size=4)
        | st.lists(scalar, min_size=1, max_size=3),
        lambda inner: (
            st.dictionaries(st.sampled_from(KEYS), inner | scalar, min_size=1, max_size=4)
            | st.lists(inner | scalar, min_size=1, max_size=3)
        ),
        max_leaves=12,
    )
    lines = _render(draw(tree), draw)
    for _ in range(draw(st.integers(0, 2))):  # mutants
        at = draw(st.integers(0, len(lines) - 1))
        kind = draw(st.integers(0, 4))
        if kind == 0:
            lines[at] = " " * draw(st.integers(0, 6)) + lines[at].lstrip(" ")
        elif kind == 1 and len(lines) > 1:
            del lines[at]
        elif kind == 2:
            lines.insert(at, lines[at])
        elif kind == 3:
            where = draw(st.integers(0, len(lines[at])))
            lines[at] = lines[at][:where] + draw(st.sampled_from(":- '\"#\\\t")) + lines[at][where:]
        else:
            lines.insert(at, draw(st.sampled_from(["", "  ", "---", "# note", "..."])))
    return "\n".join(lines) + draw(st.sampled_from(["", "\n", "\n\n"]))


@FUZZ
@given(documents())
def test_what_the_subset_reads_ruamel_reads_alike(text: str) -> None:
    read = yaml_subset.parsed(text)
    if read is None:
        return
    ok, expected = _ruamel(text)
    assert ok, f"ruamel refuses what the subset read:\n{text}"
    assert _canonical(read) == _canonical(expected), text


def test_rosbag2_metadata_of_the_sample_bags_and_corpus_is_read_as_ruamel_reads_it() -> None:
    files = sorted(ROOT.glob("sample_bags/*/metadata.yaml")) + sorted(
        Path("/work/shared/corpus").glob("*/metadata.yaml")
    )
    read = 0
    for path in files:
        text = path.read_text()
        document = yaml_subset.parsed(text)
        if document is None:
            continue
        read += 1
        assert isinstance(document, dict)
        assert _canonical(document) == _canonical(_ruamel(text)[1]), path
        for topic in document["rosbag2_bagfile_information"]["topics_with_message_count"]:
            profiles = topic["topic_metadata"]["offered_qos_profiles"]
            if isinstance(profiles, str) and profiles:
                assert _canonical(yaml_subset.parsed(profiles)) == _canonical(_ruamel(profiles)[1])
    assert read >= 2  # the sample bags' at least


@pytest.mark.parametrize(
    "text",
    [
        "a: 1\nb:\n  - x\n  - k2: 2\n    z: ~\nc:\n- 'q''s'\n- \"e\\n\"\nd: []\ne:\n  long\n  words\n",
        "- -\n  - 1\n-\n  k: v\n-\n",
    ],
)
def test_documents_of_the_subset_are_read_as_ruamel_reads_them(text: str) -> None:
    read = yaml_subset.parsed(text)
    assert read is not None
    assert _canonical(read) == _canonical(_ruamel(text)[1])


@pytest.mark.parametrize(
    "text",
    [
        "a: &x 1\nb: *x\n",  # aliases
        "a: 1 # note\n",
        "a: 1\n\nb: 2\n",  # a blank line
        "a: yes\n",  # YAML 1.1 and 1.2 differ
        "a: 1.5\n",
        "a: |\n  text\n",
        "--- \na: 1\n",
        "a: 1\n  b: 2\n",  # not YAML
        "a:\n\tb: 1\n",
        "just a scalar\n",
    ],
)
def test_what_is_outside_the_subset_is_left_to_the_library(text: str) -> None:
    assert yaml_subset.parsed(text) is None
