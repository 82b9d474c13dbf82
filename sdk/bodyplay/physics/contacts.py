"""Contact bookkeeping of the physics world: which body part touches which game
object, turned into ``begin`` / ``end`` ContactEvent pairs.

pymunk reports collisions per shape pair while it steps (``begin``, ``post_solve``,
``separate``); :class:`ContactBook` counts them per (part, object) key, collects
what began or ended during a step with its impulse and contact point, and at the
step's end (:meth:`ContactBook._flush`) emits ends first, then begins, each sorted
by part and object. :class:`bodyplay.physics.world.PhysicsWorld` mixes it in and
supplies the space, the parts, the objects and :meth:`_send`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import pymunk

from bodyplay.physics.options import PART_NAMES

__all__ = ["ContactBook", "Key", "Pending", "sort_key"]

_PART_ORDER = {n: i for i, n in enumerate(PART_NAMES)}

Key = tuple[str, str]  # (part, object name)


@dataclass(eq=False)
class _Touch:
    began: bool = False
    impulse: float = 0.0
    begin_uv: tuple[float, float] | None = None
    end_uv: tuple[float, float] | None = None


@dataclass(eq=False)
class Pending:
    """The contacts touched during a step, by key, awaiting the next flush."""

    touches: dict[Key, _Touch] = field(default_factory=dict)


class _Toggled(Protocol):
    enabled: bool


class ContactBook:
    """The contact state of a physics world and pymunk's collision callbacks for the
    body-part collision type (a mixin of :class:`~bodyplay.physics.world.PhysicsWorld`,
    which initializes the attributes below)."""

    space: pymunk.Space
    _parts: Mapping[str, _Toggled]
    _objects: Mapping[str, object]
    _shape_part: dict[pymunk.Shape, str]
    _shape_obj: dict[pymunk.Shape, str]
    _counts: dict[Key, int]
    _active: set[Key]
    _pending: Pending
    _begin_uv: dict[Key, tuple[float, float] | None]
    _graveyard: list[pymunk.Shape]
    _dirty: bool
    _flushing: bool
    _stepping: bool

    def _send(self, t: float, key: Key, phase: str, uv: tuple[float, float] | None,
              impulse: float) -> None:
        """Emit one ContactEvent; the world that mixes this book in defines how."""
        raise TypeError(f"{type(self).__name__} must define _send to emit contact events")

    def _key(self, arbiter: pymunk.Arbiter) -> tuple[Key, pymunk.Shape, pymunk.Shape] | None:
        a, b = arbiter.shapes
        part = self._shape_part.get(a)
        other = b
        if part is None:
            part, other = self._shape_part.get(b), a
            if part is None:
                return None
        obj = self._shape_obj.get(other)
        if obj is None:
            return None
        return (part, obj), (a if other is b else b), other

    def _on_begin(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        k = self._key(arbiter)
        if k is None:
            return
        key = k[0]
        n = self._counts.get(key, 0)
        self._counts[key] = n + 1
        touch = self._pending.touches.setdefault(key, _Touch())
        if n == 0 and not touch.began:
            touch.began = True
            pts = arbiter.contact_point_set.points
            if pts:
                pa, pb = pts[0].point_a, pts[0].point_b
                touch.begin_uv = (0.5 * (pa.x + pb.x), 0.5 * (pa.y + pb.y))
            else:
                touch.begin_uv = _closest(k[1], k[2])

    def _on_post_solve(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        if not self._pending.touches:
            return
        k = self._key(arbiter)
        if k is None:
            return
        touch = self._pending.touches.get(k[0])
        if touch is not None and touch.began:
            touch.impulse += abs(arbiter.total_impulse)

    def _on_separate(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        k = self._key(arbiter)
        if k is None:
            return
        key = k[0]
        n = self._counts.get(key, 0)
        if n <= 0:
            return
        if n == 1:
            del self._counts[key]
        else:
            self._counts[key] = n - 1
        self._pending.touches.setdefault(key, _Touch()).end_uv = _closest(k[1], k[2])

    def _flush(self, t: float) -> None:
        """Emit the contacts that began or ended since the last flush (ends first, then
        begins, each sorted by part and object). Game callbacks may remove objects
        meanwhile: their ends are emitted in a further round of the same flush."""
        if self._flushing or self._stepping or not (self._pending.touches or self._dirty):
            return
        self._flushing = True
        try:
            while self._pending.touches or self._dirty:
                if self._pending.touches:
                    self._flush_round(t)
                else:
                    self._sweep(t)
        finally:
            self._flushing = False

    def _flush_round(self, t: float) -> None:
        touches = self._pending.touches
        self._pending = Pending()
        ends: list[Key] = []
        begins: list[Key] = []
        transient: list[Key] = []
        for key, touch in touches.items():
            live = key in self._counts
            was = key in self._active
            if was and not live:
                ends.append(key)
            elif live and not was:
                begins.append(key)
            elif touch.began and not live and not was:
                transient.append(key)
        for key in sorted(ends, key=sort_key):
            self._end(t, key, touches[key].end_uv)
        for key in sorted(begins, key=sort_key):
            self._active.add(key)
            self._begin_uv[key] = touches[key].begin_uv
            self._send(t, key, "begin", touches[key].begin_uv, touches[key].impulse)
        for key in sorted(transient, key=sort_key):
            touch = touches[key]
            self._send(t, key, "begin", touch.begin_uv, touch.impulse)
            self._send(t, key, "end", touch.end_uv, 0.0)

    def _end(self, t: float, key: Key, uv: tuple[float, float] | None) -> None:
        self._active.discard(key)
        self._counts.pop(key, None)
        begin_uv = self._begin_uv.pop(key, None)
        self._send(t, key, "end", uv if uv is not None else begin_uv, 0.0)

    def _sweep(self, t: float) -> None:
        """After a removal: forget the names of removed shapes and end any contact
        whose part or object is gone but that pymunk did not separate."""
        self._dirty = False
        if self._stepping:
            return
        live_shapes = set(self.space.shapes)
        for shape in self._graveyard:
            if shape not in live_shapes:
                self._shape_obj.pop(shape, None)
        self._graveyard = [s for s in self._graveyard if s in live_shapes]
        enabled = {n for n, p in self._parts.items() if p.enabled}
        for key in sorted(self._active, key=sort_key):
            if key[0] not in enabled or key[1] not in self._objects:
                self._end(t, key, None)


def _closest(part: pymunk.Shape, other: pymunk.Shape) -> tuple[float, float]:
    """Where ``part``'s surface is nearest the other shape's body (a contact point
    when pymunk gives none, e.g. once the shapes have parted)."""
    body = other.body
    q = part.point_query(body.position if body is not None else other.bb.center())
    return float(q.point.x), float(q.point.y)


def sort_key(key: Key) -> tuple[int, str]:
    """Order of contact keys: by part (PART_NAMES order), then object name."""
    return _PART_ORDER[key[0]], key[1]
