"""A real ROS 2 bag (a talker with its /tf_static republished, .db3, 130 messages) given with its metadata.yaml
edited as a hand, a script or another tool leaves it: offered_qos_profiles as a string that is no list of profiles,
as a list, keys missing, counts past any file's. Every command either reads the bag as the intact one (its
transforms come from the .db3, not from metadata.yaml) or refuses in one line; none raises, and none writes to it.
Copies made in tmp_path, never in the corpus."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.sources.bag.damaged import copied

BAG = "ros2_db3_talker_static_republished_uthappa_2024"
_QOS = re.compile(r'offered_qos_profiles: ".*"')


def _qos(to: str) -> Callable[[str], str]:
    return lambda text: _QOS.sub(lambda _: f"offered_qos_profiles: {to}", text)


def _without(key: str) -> Callable[[str], str]:
    """Every line of ``key`` left out, with the lines nested under it."""

    def edit(text: str) -> str:
        kept, under = [], None
        for line in text.splitlines():
            indent = len(line) - len(line.lstrip(" -"))
            if under is not None and indent > under:
                continue
            under = indent if line.strip(" -").startswith(f"{key}:") else None
            if under is None:
                kept.append(line)
        return "\n".join(kept) + "\n"

    return edit


def _counts(to: str) -> Callable[[str], str]:
    return lambda text: re.sub(r"message_count: \d+", f"message_count: {to}", text)


EDITS: dict[str, Callable[[str], str]] = {
    "qos a plain string": _qos('"reliable"'),
    "qos a string of broken yaml": _qos('"- history: [3\\n  depth: {"'),
    "qos a string of a mapping": _qos('"history: 3"'),
    "qos a list of profiles": _qos("[{history: 3, depth: 0, reliability: 1, durability: 1}]"),
    "qos a number": _qos("7"),
    "qos a profile of strings": _qos('"- history: keep_last\\n  durability: transient_local\\n  reliability: x"'),
    "qos missing": _without("offered_qos_profiles"),
    "no topics_with_message_count": _without("topics_with_message_count"),
    "no message_count": _without("message_count"),
    "no starting_time nor duration": lambda text: _without("duration")(_without("starting_time")(text)),
    "no storage_identifier": _without("storage_identifier"),
    "no version": _without("version"),
    "counts of 2**70": _counts(str(2**70)),
    "counts negative": _counts("-5"),
    "counts not numbers": _counts("many"),
    "a duration of 2**64 ns": lambda text: re.sub(r"nanoseconds: \d+", f"nanoseconds: {2**64}", text),
}


def _json(tfx: Tfx, *args: str | Path) -> Any:  # noqa: F811
    result = tfx(*args, "--format", "json")
    assert result.code in (0, 1, 2) and "Traceback" not in result.stderr, result.stderr
    return json.loads(result.stdout) if result.stdout.strip() else None


@pytest.mark.parametrize("case", list(EDITS))
def test_a_bag_with_its_metadata_edited_is_read_from_its_file_or_refused_in_one_line(
    case: str,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    intact = copied(BAG, tmp_path / "intact")
    bag = copied(BAG, tmp_path)
    metadata = bag / "metadata.yaml"
    before = metadata.read_text()
    edited = EDITS[case](before)
    assert edited != before, "the edit changed nothing: the case tests nothing"
    metadata.write_text(edited)
    frames, was = _json(tfx, "frames", "-b", bag), _json(tfx, "frames", "-b", intact)
    checked, healthy = _json(tfx, "wtf", "-b", bag), _json(tfx, "wtf", "-b", intact)
    if checked is not None:  # no finding the intact bag has not: before, counts of 2**70 made 'silent_tf:
        # 1,180,591,620,717,411,303,394 of 1,180,591,620,717,411,303,424 messages on /tf_static carry no
        # transform'
        codes = {f["code"] for f in checked["bags"][0]["findings"]}
        assert codes <= {f["code"] for f in healthy["bags"][0]["findings"]}, checked["bags"][0]["findings"]
        assert checked["bags"][0]["transforms"] == healthy["bags"][0]["transforms"]
    runs = {"wtf": tfx("wtf", "-b", bag), "report": tfx("report", "-b", bag, "-o", tmp_path / "r.html")}
    for command, result in runs.items():
        assert result.code in (0, 1, 2), f"{command}: exit {result.code}: {result.stderr}"
        assert "Traceback" not in result.stderr and "internal error" not in result.stderr, f"{command}: {result.stderr}"
        errors = [line for line in result.stderr.splitlines() if line.startswith("tfx: error")]
        assert len(errors) <= 1 and all(len(e) < 400 for e in errors), result.stderr
    if frames is not None:  # read: from its .db3, whatever metadata.yaml says
        assert sorted(f["frame"] for f in frames["frames"]) == sorted(f["frame"] for f in was["frames"])
    assert metadata.read_text() == edited  # nothing a user gave is changed


@pytest.mark.parametrize("case", ["qos a plain string", "qos a string of a mapping", "qos a number", "counts negative"])
def test_metadata_neither_a_count_nor_profiles_is_said_unreadable_not_counted(case: str, tmp_path: Path) -> None:
    """Before, a plain string of profiles ('reliable') was listed a character each: 8 publishers of /tf_static."""
    from tftools.sources.bag.reader import BagReader

    bag = copied(BAG, tmp_path)
    metadata = bag / "metadata.yaml"
    metadata.write_text(EDITS[case](metadata.read_text()))
    with BagReader([bag]) as reader:
        (offered,) = reader.read().qos.values()
    assert re.search(r"is no list of profiles|message_count of /\S+ is -5", offered.problem), offered.problem
    assert not offered.counts and not offered.profiles
