"""``frame_name``: the one rule of a frame's leading ``/``, as the buffer applies it to what it stores."""

from __future__ import annotations

import pytest

from tftools.core import Buffer, Transform, frame_name


@pytest.mark.parametrize(("given", "name"), [("/map", "map"), ("map", "map"), ("//map", "/map"), ("", ""), ("/", "")])
def test_one_leading_slash_is_dropped(given: str, name: str) -> None:
    assert frame_name(given) == name


def test_the_buffer_stores_frames_by_that_name() -> None:
    buffer = Buffer()
    buffer.set_transform(Transform.identity(1, "/map", "/odom"), "test")
    assert {frame_name("/map"), frame_name("/odom")} <= set(buffer.frames)
