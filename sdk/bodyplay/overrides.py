"""Options from ``NAME=VALUE`` strings: what ``bodyplay track --set`` and the benchmark
scripts' ``--set`` do to any tracker's frozen options dataclass.

One parser for every options class, so that the command line reaches every field
of every tracker the same way: ``max_speed=4`` sets a field of the options
themselves, ``locate.tau=0.12`` or ``background.learn_after=8`` a field of a
nested options dataclass. Each value is read as its field's type: ``true`` /
``false`` for switches, ``none`` for optional fields, comma-separated values for
tuples (of the tuple's element type; rows separated by ``;`` for a matrix).
Unknown names and unreadable values raise :class:`~bodyplay.errors.ConfigError`
naming the valid choices; the options' own validation then runs as usual.
"""

from __future__ import annotations

import dataclasses
import typing
from collections.abc import Iterable
from typing import Any, TypeVar

from bodyplay.errors import ConfigError

__all__ = ["options_with_overrides"]

T = TypeVar("T")

_TRUE = {"1", "true", "yes", "on"}
_FALSE = {"0", "false", "no", "off"}


def _label(cls: type) -> str:
    """``ColorShirtOptions`` -> ``colorshirt``: how error messages name an options class."""
    name = cls.__name__
    return (name[: -len("Options")] if name.endswith("Options") else name).lower()


def _scalar(text: str, hint: Any) -> Any:
    if hint is bool:
        if text.lower() in _TRUE | _FALSE:
            return text.lower() in _TRUE
        raise ValueError(text)
    if hint is int:
        return int(text)
    if hint is float:
        return float(text)
    return text


def _kind(hint: Any) -> str:
    origin = typing.get_origin(hint) or hint
    if hint is bool:
        return "true or false"
    if hint in (int, float):
        return f"a number ({hint.__name__})"
    if origin is tuple:
        return "comma-separated values"
    return str(hint)


def _convert(name: str, text: str, hint: Any) -> Any:
    """One value converted to the type of the field it sets."""
    t = text.strip()
    args = typing.get_args(hint)
    if type(None) in args:
        if t.lower() in ("none", "null", ""):
            return None
        hint = next(a for a in args if a is not type(None))
    try:
        if (typing.get_origin(hint) or hint) is tuple:
            inner = [a for a in typing.get_args(hint) if a is not Ellipsis] or [str]
            if typing.get_origin(inner[0]) is tuple:  # a matrix, rows separated by ';'
                row_type = typing.get_args(inner[0])[0]
                return tuple(tuple(_scalar(v.strip(), row_type) for v in row.split(",")
                                   if v.strip()) for row in t.split(";"))
            parts = [p.strip() for p in t.strip("()[]").split(",") if p.strip()]
            return tuple(_scalar(p, inner[min(i, len(inner) - 1)])
                         for i, p in enumerate(parts))
        return _scalar(t, hint)
    except ValueError:
        raise ConfigError(f"option {name}: cannot read {text!r}; expected "
                          f"{_kind(hint)}") from None


def _nested(cls: type) -> dict[str, type]:
    """The fields of ``cls`` that are options dataclasses themselves."""
    hints = typing.get_type_hints(cls)
    return {f.name: hints[f.name] for f in dataclasses.fields(cls)
            if isinstance(hints[f.name], type) and dataclasses.is_dataclass(hints[f.name])}


def options_with_overrides(base: T, items: Iterable[str]) -> T:
    """``base`` (a frozen options dataclass) with ``NAME=VALUE`` strings applied
    (see the module docstring); ``base`` itself when ``items`` is empty."""
    cls = type(base)
    if not dataclasses.is_dataclass(cls):
        raise ConfigError(f"{cls.__name__} is not an options dataclass")
    hints = typing.get_type_hints(cls)
    nested = _nested(cls)
    top: dict[str, Any] = {}
    inner: dict[str, list[str]] = {}
    for item in items:
        if "=" not in item:
            raise ConfigError(f"--set {item!r}: write NAME=VALUE, e.g. --set "
                              f"{next(iter(hints))}=...")
        key, value = (part.strip() for part in item.split("=", 1))
        head, dot, rest = key.partition(".")
        if dot and head in nested:
            inner.setdefault(head, []).append(f"{rest}={value}")
        elif not dot and key in hints and key not in nested:
            top[key] = _convert(key, value, hints[key])
        else:
            names = [f.name for f in dataclasses.fields(cls) if f.name not in nested]
            more = "".join(f" or {n}.NAME" for n in nested)
            raise ConfigError(f"unknown {_label(cls)} option {key!r}; choose one of "
                              f"{', '.join(names)}{more}")
    for head, sub in inner.items():
        top[head] = options_with_overrides(getattr(base, head), sub)
    if not top:
        return base
    return dataclasses.replace(base, **top)  # type: ignore[type-var]
