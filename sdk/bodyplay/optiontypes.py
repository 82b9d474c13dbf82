"""Every options dataclass checks its fields' types when it is made.

The options classes (``ColorShirtOptions``, ``SilhouetteOptions``, ``SessionOptions``,
...) are frozen dataclasses with type hints; their own ``__post_init__`` checks ranges
(a threshold > 0, a probability within 0..1). Without a type check first, a string, a
``None`` or a NaN where a number belongs got through to those range checks, or into
the tracker, and came out as numpy's ``TypeError: ufunc 'isfinite' not supported`` or
not at all (``SilhouetteOptions(lost_after=float("nan"))`` never reported a pose lost).
:func:`check_option_types` reads each field's hint and raises
:class:`~bodyplay.errors.ConfigError` naming the option, what it holds and what it
takes. A list where a tuple is hinted is turned into the tuple (frozen options must
stay hashable). Hints it cannot check (arrays, callables, ``Any``) are left alone.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from pathlib import Path
from types import UnionType
from typing import Any, Literal

import numpy as np

from bodyplay.errors import ConfigError

__all__ = ["check_option_types"]

_UNCHECKED = object()
"""What :func:`_fits` answers for a hint it does not know how to check."""


def _describe(hint: Any) -> str:
    """A hint as a user reads it: ``a number``, ``one of 'a', 'b'``, ``a tuple of 3 values``."""
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if hint is bool:
        return "True or False"
    if hint is int:
        return "a whole number"
    if hint is float:
        return "a number"
    if hint is str:
        return "a string"
    if origin is Literal:
        return "one of " + ", ".join(repr(a) for a in args)
    if origin in (typing.Union, UnionType):
        return " or ".join("None" if a is type(None) else _describe(a) for a in args)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return f"a tuple, each item {_describe(args[0])}"
        return f"a tuple of {len(args)} values"
    if isinstance(hint, type):
        return f"a {hint.__name__}"
    return str(hint)


def _fits(value: Any, hint: Any) -> Any:
    """``value`` itself when it fits ``hint`` (a list where a tuple is hinted: the
    tuple), :data:`_UNCHECKED` for a hint this does not check; raises ``ValueError``
    when it does not fit."""
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if hint is Any:
        return _UNCHECKED
    if hint is bool:
        if isinstance(value, bool | np.bool_):
            return value
        raise ValueError
    if hint is int:
        if isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_):
            return value
        raise ValueError
    if hint is float:
        if (isinstance(value, int | float | np.integer | np.floating)
                and not isinstance(value, bool | np.bool_) and not math.isnan(value)):
            return value
        raise ValueError
    if hint is str:
        if isinstance(value, str):
            return value
        raise ValueError
    if origin is Literal:
        if any(value == a and type(value) is type(a) for a in args):
            return value
        raise ValueError
    if origin in (typing.Union, UnionType):
        unchecked = False
        for arg in args:
            if arg is type(None):
                if value is None:
                    return value
                continue
            try:
                fitted = _fits(value, arg)
            except ValueError:
                continue
            if fitted is _UNCHECKED:
                unchecked = True
                continue
            return fitted
        if unchecked:
            return _UNCHECKED
        raise ValueError
    if origin is tuple:
        if not isinstance(value, tuple | list):
            raise ValueError
        if len(args) == 2 and args[1] is Ellipsis:
            items = [args[0]] * len(value)
        elif args:
            if len(value) != len(args):
                raise ValueError
            items = list(args)
        else:
            return tuple(value)
        out = []
        for item, item_hint in zip(value, items, strict=True):
            fitted = _fits(item, item_hint)
            out.append(item if fitted is _UNCHECKED else fitted)
        return tuple(out)
    if hint is Path:
        if isinstance(value, Path):
            return value
        raise ValueError
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        if isinstance(value, hint):
            return value
        raise ValueError
    return _UNCHECKED


def check_option_types(options: Any) -> None:
    """Raise :class:`~bodyplay.errors.ConfigError` for the first field of the options
    dataclass ``options`` whose value does not fit its type hint (NaN is not a
    number here; infinity is). Call it first in ``__post_init__``."""
    hints = typing.get_type_hints(type(options))
    for field in dataclasses.fields(options):
        hint = hints[field.name]
        value = getattr(options, field.name)
        try:
            fitted = _fits(value, hint)
        except ValueError:
            shown = repr(value) if len(repr(value)) <= 60 else repr(value)[:57] + "..."
            raise ConfigError(
                f"{type(options).__name__}.{field.name} takes {_describe(hint)}, "
                f"got {shown} ({type(value).__name__})") from None
        if isinstance(value, list) and isinstance(fitted, tuple):
            object.__setattr__(options, field.name, fitted)
