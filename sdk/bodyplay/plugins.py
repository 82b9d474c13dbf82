"""Plugins: trackers, filters, gesture sets and sources found through entry points.

A package extends bodyplay by declaring entry points in its ``pyproject.toml``::

    [project.entry-points."bodyplay.filters"]
    my_filter = "my_package.filters:MyFilter"

Groups and what the loaded object must be (a factory: a class or a function):

* ``bodyplay.trackers``: ``factory(cameras=..., **options)`` -> object with
  ``process(frames)`` (a :class:`~bodyplay.trackers.base.Tracker`);
* ``bodyplay.filters``: ``factory(**options)`` -> object with ``filter(t, joints,
  state)`` and ``reset()`` (a :class:`~bodyplay.filters.base.JointFilter`);
* ``bodyplay.gestures``: ``factory(**options)`` -> object with ``update(t, joints,
  state)`` (a :class:`~bodyplay.runtime.session.GestureRecognizer`);
* ``bodyplay.sources``: ``factory(path_or_object, **options)`` -> an iterable of
  PoseSample or FrameSet.

bodyplay's own implementations are declared the same way in its pyproject.toml. A
:class:`PluginRegistry` belongs to whoever creates it (a session factory, a CLI
command): there is no global registry.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from importlib import metadata
from typing import Any

from bodyplay.errors import PluginError

__all__ = ["GROUPS", "PluginRegistry"]

GROUPS: dict[str, tuple[str, ...]] = {
    "bodyplay.trackers": ("process",),
    "bodyplay.filters": ("filter", "reset"),
    "bodyplay.gestures": ("update",),
    "bodyplay.sources": ("__iter__",),
}
"""Entry-point groups and the methods an object created by each group's factory needs."""


def _group(group: str) -> str:
    full = group if group.startswith("bodyplay.") else f"bodyplay.{group}"
    if full not in GROUPS:
        raise PluginError(
            f"unknown plugin group {group!r}; groups are {', '.join(sorted(GROUPS))}"
        )
    return full


def _kind(group: str) -> str:
    return group.split(".", 1)[1].rstrip("s")


class PluginRegistry:
    """Finds, loads and checks plugins of the four groups.

    ``entry_points`` replaces the installed ones (tests); by default the registry
    reads ``importlib.metadata`` the first time a group is used (``refresh()``
    forgets that). :meth:`register` adds an in-process plugin (game code).
    """

    def __init__(self, entry_points: Iterable[metadata.EntryPoint] | None = None) -> None:
        self._given = None if entry_points is None else tuple(entry_points)
        self._found: dict[str, dict[str, metadata.EntryPoint]] = {}
        self._local: dict[str, dict[str, Callable[..., Any]]] = {g: {} for g in GROUPS}
        self._loaded: dict[tuple[str, str], Callable[..., Any]] = {}

    def refresh(self) -> None:
        """Forget the entry points read so far (after installing a package)."""
        self._found.clear()
        self._loaded.clear()

    def _entry_points(self, group: str) -> dict[str, metadata.EntryPoint]:
        if group not in self._found:
            if self._given is not None:
                eps: Iterable[metadata.EntryPoint] = [e for e in self._given if e.group == group]
            else:
                eps = metadata.entry_points(group=group)
            found: dict[str, metadata.EntryPoint] = {}
            for ep in eps:
                found.setdefault(ep.name, ep)  # first on sys.path wins, like imports
            self._found[group] = found
        return self._found[group]

    def names(self, group: str) -> tuple[str, ...]:
        """Names available in ``group`` (``"filters"`` or ``"bodyplay.filters"``), sorted."""
        g = _group(group)
        return tuple(sorted({*self._entry_points(g), *self._local[g]}))

    def available(self) -> dict[str, tuple[str, ...]]:
        """Every group's available names."""
        return {g: self.names(g) for g in GROUPS}

    def register(self, group: str, name: str, factory: Callable[..., Any]) -> None:
        """Make ``factory`` available as ``name`` in ``group`` for this registry only."""
        g = _group(group)
        self._check_factory(g, name, factory, f"registered {_kind(g)} {name!r}")
        self._local[g][name] = factory

    def load(self, group: str, name: str) -> Callable[..., Any]:
        """The factory behind ``name`` in ``group``, imported and checked.

        Raises PluginError naming the entry point if it is not installed, fails to
        import, or is not a factory of the right kind.
        """
        g = _group(group)
        key = (g, name)
        if key in self._loaded:
            return self._loaded[key]
        if name in self._local[g]:
            return self._local[g][name]
        ep = self._entry_points(g).get(name)
        if ep is None:
            have = self.names(g)
            raise PluginError(
                f"no {_kind(g)} named {name!r} is installed (entry point group {g}); "
                f"available: {', '.join(have) if have else 'none'}; install the package "
                "that provides it"
            )
        where = f"entry point {name} = {ep.value!r} in group {g}"
        try:
            obj = ep.load()
        except Exception as exc:
            raise PluginError(f"{where} failed to load: {exc!r}") from exc
        self._check_factory(g, name, obj, where)
        self._loaded[key] = obj
        return obj

    def create(self, group: str, name: str, *args: Any, **kwargs: Any) -> Any:
        """Load ``name`` and call its factory; check the result is of the group's kind."""
        g = _group(group)
        factory = self.load(g, name)
        try:
            obj = factory(*args, **kwargs)
        except PluginError:
            raise
        except TypeError as exc:
            raise PluginError(f"{_kind(g)} plugin {name!r} rejected its arguments: {exc}") from exc
        missing = [m for m in GROUPS[g] if not callable(getattr(obj, m, None))]
        if missing:
            raise PluginError(
                f"{_kind(g)} plugin {name!r} ({factory!r}) made {type(obj).__name__}, which "
                f"lacks {', '.join(missing)}; a {_kind(g)} needs {', '.join(GROUPS[g])}"
            )
        return obj

    @staticmethod
    def _check_factory(group: str, name: str, obj: object, where: str) -> None:
        if not callable(obj):
            raise PluginError(
                f"{where} is a {type(obj).__name__}, not a factory (class or function) "
                f"making a {_kind(group)}"
            )
        if isinstance(obj, type):
            missing = [m for m in GROUPS[group] if not callable(getattr(obj, m, None))]
            if missing:
                raise PluginError(
                    f"{where} is class {obj.__qualname__}, which lacks {', '.join(missing)}; "
                    f"a {_kind(group)} needs {', '.join(GROUPS[group])}"
                )
