"""The core remembers frame and publisher names by their str objects: a name is its own frame or publisher
however many others come between and whichever object spells it."""

from __future__ import annotations

from tftools import Buffer, Transform

S = 1_000_000_000
IDENTITY = (0.0, 0.0, 0.0, 1.0)


def test_many_names_each_its_own_frame_and_publisher() -> None:
    """More frame and publisher names than the core remembers by object (their slots collide), each name
    given as new str objects as well as the same ones: each is its own frame, its own publisher."""
    names = [f"f{i}" for i in range(300)]
    buffer = Buffer(cache_time=None)
    for k, stamp in enumerate((S, 2 * S)):
        for i in range(1, len(names)):
            parent, child = (names[i - 1], names[i]) if k == 0 else (f"f{i - 1}", f"f{i}")
            assert buffer.set_transform(Transform((1.0, 0.0, 0.0), IDENTITY, stamp, parent, child), f"p{i % 150}")
    for i in range(1, len(names)):
        assert buffer.lookup(names[0], f"f{i}", S + S // 2).translation[0] == i
        assert buffer.lookup(f"f{i}", names[0], S).translation[0] == -i
        history = buffer.history(names[i])
        assert history is not None
        assert history.authorities.tolist() == [buffer.authorities.index(f"p{i % 150}")] * 2
    assert len(buffer.authorities) == 150
