"""Who owns which writer, as ros_discovery_info announces it: a participant's latest announcement holds,
and at most a bounded number of participants are kept, the oldest forgotten, said once."""

from __future__ import annotations

import pytest

pytest.importorskip("cyclonedds.domain", exc_type=ImportError)

from tftools.sources.live.ros2.graph import Announced  # after the skip: needs Cyclone DDS


def test_a_participant_s_latest_announcement_holds() -> None:
    nodes = Announced()
    nodes.announce(b"p1", {b"w1": "/a", b"w2": "/a"})
    nodes.announce(b"p1", {b"w2": "/b"})
    assert (nodes.node_of(b"w1"), nodes.node_of(b"w2")) == ("", "/b")


def test_beyond_the_limit_the_oldest_participant_is_forgotten_and_said_once() -> None:
    notices: list[str] = []
    nodes = Announced(notices.append, limit=3)
    for k in range(10):
        nodes.announce(bytes([k]), {bytes([100 + k]): f"/n{k}"})
    assert len(nodes) == 3 and nodes.forgotten == 7
    assert [nodes.node_of(bytes([100 + k])) for k in range(10)] == [""] * 7 + ["/n7", "/n8", "/n9"]
    assert notices == [
        "more than 3 participants announced on ros_discovery_info: the oldest are forgotten, their writers named"
        " by participant (a flood of participants?)"
    ]


def test_announcing_again_makes_a_participant_the_newest() -> None:
    nodes = Announced(limit=2)
    nodes.announce(b"a", {b"wa": "/a"})
    nodes.announce(b"b", {b"wb": "/b"})
    nodes.announce(b"a", {b"wa": "/a"})
    nodes.announce(b"c", {b"wc": "/c"})
    assert (nodes.node_of(b"wa"), nodes.node_of(b"wb"), nodes.node_of(b"wc")) == ("/a", "", "/c")
