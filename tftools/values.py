"""Dataclasses whose methods are not compiled: ``value`` (frozen) and ``record`` make a class what
``dataclasses.dataclass`` makes it (its fields, ``__match_args__``, ``dataclasses.replace``, ``asdict``, its
``__init__``, ``__repr__``, ``__eq__``, ``__hash__``, a frozen one's refusal to change), the methods closures
over the fields instead of source that ``dataclasses`` writes and compiles with ``exec`` for each class
(Python 3.11: ~3M instructions a frozen class; 25 such classes were ~7% of a whole script's load). An
instance behaves as the dataclass's would; only the wording of a wrong call's ``TypeError`` differs.
Fields with ``kw_only``, ``InitVar`` or a class's own ``__setattr__`` are not supported (refused when the
class is made)."""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:
    from typing_extensions import dataclass_transform
else:

    def dataclass_transform(**_: object) -> Callable[[Any], Any]:
        return lambda decorated: decorated


T = TypeVar("T")
_MISSING = dataclasses.MISSING


@dataclass_transform(frozen_default=True, field_specifiers=(dataclasses.field,))
def value(cls: type[T]) -> type[T]:
    """``cls`` as ``@dataclass(frozen=True)`` makes it."""
    return _made(cls, frozen=True)


@dataclass_transform(field_specifiers=(dataclasses.field,))
def record(cls: type[T]) -> type[T]:
    """``cls`` as ``@dataclass`` makes it."""
    return _made(cls, frozen=False)


def _made(cls: type[T], *, frozen: bool) -> type[T]:
    own = set(vars(cls))
    # A class that defines __eq__ alone gets __hash__ = None from Python: not a hash of its own (as dataclasses).
    explicit_hash = "__hash__" in own and not (vars(cls)["__hash__"] is None and "__eq__" in own)
    if "__setattr__" in own or "__delattr__" in own:
        raise TypeError(f"{cls.__qualname__}: a value class cannot define __setattr__ or __delattr__")
    dataclasses.dataclass(init=False, repr=False, eq=False)(cls)  # the fields, __match_args__: nothing compiled
    fields = dataclasses.fields(cls)  # type: ignore[arg-type]
    if any(f.kw_only is True for f in fields) or any(isinstance(f.type, dataclasses.InitVar) for f in fields):
        raise TypeError(f"{cls.__qualname__}: kw_only and InitVar fields are not supported")
    methods: dict[str, Any] = {
        "__init__": _init(cls, fields),
        "__repr__": _repr(tuple(f.name for f in fields if f.repr)),
        "__eq__": _eq(tuple(f.name for f in fields if f.compare)),
    }
    if frozen:
        methods["__setattr__"], methods["__delattr__"] = _frozen(cls, frozenset(f.name for f in fields))
    if not explicit_hash:  # as dataclasses: a frozen value hashes its compared fields, a record is unhashable
        hashed = tuple(f.name for f in fields if (f.compare if f.hash is None else f.hash))
        methods["__hash__"] = _hash(hashed) if frozen else None
    for name, method in methods.items():
        if name not in own or name == "__hash__":
            if callable(method):
                method.__name__, method.__qualname__ = name, f"{cls.__qualname__}.{name}"
            setattr(cls, name, method)
    return cls


def _init(cls: type, fields: tuple[dataclasses.Field[Any], ...]) -> Callable[..., None]:
    names = tuple(f.name for f in fields if f.init)
    given = frozenset(names)
    # Per field: its default, or a factory (called per instance), or neither (a required argument).
    defaults = {f.name: f.default for f in fields if f.default is not _MISSING}
    factories = {f.name: f.default_factory for f in fields if f.default_factory is not _MISSING}
    later = tuple(f.name for f in fields if not f.init and (f.name in defaults or f.name in factories))
    post_init = "__post_init__" in {n for klass in cls.__mro__ for n in vars(klass)}
    put = object.__setattr__
    title = cls.__qualname__

    def init(self: Any, *args: Any, **kwargs: Any) -> None:
        if len(args) > len(names):
            raise TypeError(f"{title}.__init__() takes {len(names)} positional arguments but {len(args)} were given")
        for name, argument in zip(names, args, strict=False):
            if name in kwargs:
                raise TypeError(f"{title}.__init__() got multiple values for argument {name!r}")
            put(self, name, argument)
        for name in names[len(args) :]:
            if name in kwargs:
                put(self, name, kwargs[name])
            elif name in factories:
                put(self, name, factories[name]())
            elif name in defaults:
                put(self, name, defaults[name])
            else:
                raise TypeError(f"{title}.__init__() missing required argument: {name!r}")
        if len(kwargs) > len(names) - len(args) or not given.issuperset(kwargs):
            unexpected = sorted(set(kwargs) - given)
            raise TypeError(f"{title}.__init__() got an unexpected keyword argument {unexpected[0]!r}")
        for name in later:
            put(self, name, factories[name]() if name in factories else defaults[name])
        if post_init:
            self.__post_init__()

    return init


_repr_running: set[tuple[int, int]] = set()


def _repr(names: tuple[str, ...]) -> Callable[[Any], str]:
    def shown(self: Any) -> str:
        key = (id(self), threading.get_ident())
        if key in _repr_running:  # a value that holds itself, as dataclasses says it
            return "..."
        _repr_running.add(key)
        try:
            shown = ", ".join(f"{name}={getattr(self, name)!r}" for name in names)
        finally:
            _repr_running.discard(key)
        return f"{self.__class__.__qualname__}({shown})"

    return shown


def _eq(names: tuple[str, ...]) -> Callable[[Any, object], Any]:
    def equal(self: Any, other: object) -> Any:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return tuple(getattr(self, n) for n in names) == tuple(getattr(other, n) for n in names)

    return equal


def _hash(names: tuple[str, ...]) -> Callable[[Any], int]:
    def hashed(self: Any) -> int:
        return hash(tuple(getattr(self, n) for n in names))

    return hashed


def _frozen(cls: type, names: frozenset[str]) -> tuple[Callable[..., None], Callable[..., None]]:
    def refuse_set(self: Any, name: str, value: Any) -> None:
        if type(self) is cls or name in names:
            raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")
        super(cls, self).__setattr__(name, value)  # type: ignore[arg-type]

    def refuse_delete(self: Any, name: str) -> None:
        if type(self) is cls or name in names:
            raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")
        super(cls, self).__delattr__(name)  # type: ignore[arg-type]

    return refuse_set, refuse_delete
