"""``tftools.values``: classes made by ``value`` and ``record`` behave as ``dataclasses.dataclass`` makes them
(the same class body made both ways, compared on what the code relies on)."""

from __future__ import annotations

import copy
import dataclasses
import pickle
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from tftools.values import record, value

Maker = Callable[[type], type]
FROZEN: dict[str, Maker] = {"dataclass": dataclasses.dataclass(frozen=True), "value": value}
PLAIN: dict[str, Maker] = {"dataclass": dataclasses.dataclass, "value": record}


def shapes(make: Maker) -> dict[str, type]:
    """Classes of the shapes tftools' values take: defaults, factories, fields left out of the repr or the
    comparison, a base class's fields, a class body's own ``__eq__`` or ``__hash__``, a ``__post_init__``."""

    class Base:
        """A base."""

        name: str
        count: int = 3
        tags: list[str] = dataclasses.field(default_factory=list)

    base = make(Base)

    class Derived(base):  # type: ignore[valid-type,misc]
        """Its fields after the base's."""

        extra: float = 0.5
        hidden: int = dataclasses.field(default=7, repr=False, compare=False)

    class OwnEq:
        """Equality of its own: no hash of its own."""

        a: int

        def __eq__(self, other: object) -> bool:
            return isinstance(other, OwnEq) and self.a % 10 == other.a % 10

    class OwnHash:
        """A hash of its own, kept."""

        a: int

        def __hash__(self) -> int:
            return 42

    class Later:
        """A field not given to ``__init__`` and a ``__post_init__``."""

        a: int
        b: int = dataclasses.field(init=False, default=0)
        seen: list[int] = dataclasses.field(init=False, default_factory=list, repr=False)

        def __post_init__(self) -> None:
            self.seen.append(self.a)

    return {
        "Base": base,
        "Derived": make(Derived),
        "OwnEq": make(OwnEq),
        "OwnHash": make(OwnHash),
        "Later": make(Later),
    }


def behaviour(classes: dict[str, type], frozen: bool) -> list[Any]:
    """What each class's instances do, as comparable values (errors by their type)."""

    def outcome(action: Callable[[], Any]) -> Any:
        try:
            return ("ok", action())
        except Exception as e:  # the kind of failure is what is compared
            return ("raised", type(e).__name__)

    base, derived, own_eq, own_hash, later = (classes[n] for n in ("Base", "Derived", "OwnEq", "OwnHash", "Later"))
    a, b = base("x", 4, ["t"]), base(name="x", count=4, tags=["t"])
    d = derived("y", extra=1.5, hidden=9)
    seen = [
        repr(a),
        repr(base("z")),
        repr(d),
        a == b,
        a != base("x"),
        a == ("x", 4, ["t"]),
        d == derived("y", extra=1.5, hidden=1),  # hidden is not compared
        d == base("y"),
        outcome(lambda: hash(base("x"))),
        outcome(lambda: hash(d) == hash(derived("y", extra=1.5, hidden=1))),
        outcome(lambda: hash(own_eq(1))),
        own_eq(1) == own_eq(11),
        outcome(lambda: hash(own_hash(1))),
        repr(later(5)),
        later(5).seen,
        later(5) == later(5),
        outcome(lambda: later(5, 6)),
        [f.name for f in dataclasses.fields(derived)],
        getattr(derived, "__match_args__"),  # noqa: B009 (a class of either kind)
        dataclasses.asdict(d),
        dataclasses.replace(d, extra=2.5) == derived("y", extra=2.5),
        repr(dataclasses.replace(a, count=9)),
        outcome(lambda: base()),
        outcome(lambda: base("x", 1, [], 4)),
        outcome(lambda: base("x", name="y")),
        outcome(lambda: base("x", colour="red")),
        dataclasses.is_dataclass(a),
        copy.copy(d) == d,
        copy.deepcopy(a) == a,
        base("x").tags is not base("x").tags,  # a factory per instance
    ]

    def assign() -> None:
        a.count = 5

    def remove() -> None:
        del a.count

    def other() -> None:
        a.colour = "red"

    seen += [outcome(assign), outcome(remove), outcome(other), a.count if frozen else None]
    return seen


@pytest.mark.parametrize("frozen", [True, False], ids=["value", "record"])
def test_made_as_dataclasses_makes_them(frozen: bool) -> None:
    makers = FROZEN if frozen else PLAIN
    expected = behaviour(shapes(makers["dataclass"]), frozen)
    assert behaviour(shapes(makers["value"]), frozen) == expected
    assert ("raised", "FrozenInstanceError") in expected if frozen else ("raised", "TypeError") in expected


def test_a_value_that_holds_itself_and_arrays() -> None:
    """A repr that meets its own value says ``...`` as dataclasses' does; arrays compare as in a dataclass (a
    tuple of arrays: ambiguous unless they are the same object)."""
    for make in FROZEN.values():

        class Holder:
            items: list[Any]

        held = make(Holder)
        h = held([])
        h.items.append(h)
        assert repr(h) == "test_a_value_that_holds_itself_and_arrays.<locals>.Holder(items=[...])"

        class Arrays:
            a: np.ndarray[Any, Any]

        arrays = make(Arrays)
        values = np.arange(3)
        assert arrays(values) == arrays(values)
        with pytest.raises(ValueError, match="ambiguous"):
            _ = arrays(values) == arrays(values.copy())


def test_unsupported_fields_are_refused() -> None:
    class KeywordOnly:
        a: int = dataclasses.field(kw_only=True)

    with pytest.raises(TypeError, match="kw_only"):
        value(KeywordOnly)

    class OwnSetattr:
        a: int

        def __setattr__(self, name: str, v: object) -> None:
            object.__setattr__(self, name, v)

    with pytest.raises(TypeError, match="__setattr__"):
        value(OwnSetattr)


def test_tftools_values_pickle() -> None:
    """Values cross processes (a Dask worker's results): a frozen value and a record come back equal."""
    from tftools.sources.contents import Recorded, SourceInfo

    recorded = Recorded("/tf", "tf2_msgs/msg/TFMessage", "cdr", "definition", "RIHS01_ab", qos="- depth: 1")
    info = SourceInfo("a.bag", "ros1", 1, 2, 3, topics={"/tf": "tf2_msgs/TFMessage"}, transform_count=3, problems=["p"])
    assert pickle.loads(pickle.dumps(recorded)) == recorded
    assert pickle.loads(pickle.dumps(info)) == info
    with pytest.raises(dataclasses.FrozenInstanceError):
        recorded.topic = "/other"  # type: ignore[misc]
