"""The pymunk bridge: body-part colliders driven by pose events, and ``contact`` events.

A :class:`PhysicsWorld` owns a ``pymunk.Space`` in a 2-D plane through the player
(the frontal plane by default: world X and Y, metres). Each body part is a KINEMATIC
body (infinite mass, moved by us, never by the solver) carrying one capsule or
circle. Pose events move them: between two poses the world advances in fixed steps
of ``options.dt``, the joints interpolated linearly in between, and every part gets
the velocity that carries it to its next position in one step (displacement / dt),
so a swinging hand hits a ball with the impulse its real speed implies. A part whose
joints are lost is taken out of the space (its contacts end) until they come back.

Contacts between a part and a named game object become ContactEvent ``begin`` /
``end`` pairs, emitted after each step once the collision impulse is known (the
impulse pymunk applied in the step the contact began). An ``end`` follows every
``begin``: when the shapes part, when a part is disabled, when an object is removed
and when the world is closed.

Fixed steps counted from the first pose's time make the simulation a function of the
pose stream only: replaying the same poses gives identical contact events.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
import pymunk
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS
from bodyplay.errors import ConfigError, TimestampError
from bodyplay.events.types import ContactEvent, Event, PoseEvent
from bodyplay.physics.contacts import ContactBook, Key, Pending, sort_key
from bodyplay.physics.options import (
    PART_NAMES,
    PART_SPECS,
    PLANES,
    POINT_NAMES,
    PartSpec,
    PhysicsOptions,
    estimate_height,
)

__all__ = ["PhysicsWorld", "PhysicsObject", "attach_physics", "PART_COLLISION_TYPE"]

PART_COLLISION_TYPE = 0xB0D7
"""``collision_type`` of every body-part shape (for games adding their own handlers)."""

_PART_GROUP = pymunk.ShapeFilter(group=PART_COLLISION_TYPE)  # parts never collide together
_POINT_INDEX = {n: i for i, n in enumerate(POINT_NAMES)}
_HANDS = (("l_hand", "l_wrist", "l_elbow"), ("r_hand", "r_wrist", "r_elbow"))


@dataclass(frozen=True, eq=False)
class PhysicsObject:
    """A game object in the world: its unique ``name`` (the ``obj`` of its contact
    events), its pymunk ``body`` and ``shapes``."""

    name: str
    body: pymunk.Body
    shapes: tuple[pymunk.Shape, ...]


@dataclass(eq=False)
class _Part:
    spec: PartSpec
    body: pymunk.Body
    shape: pymunk.Shape
    ia: int
    ib: int
    enabled: bool = False
    pos: tuple[float, float] = (0.0, 0.0)
    angle: float = 0.0
    length: float = 0.0
    nxt: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)



class PhysicsWorld(ContactBook):
    """A pymunk space with the player's body parts as kinematic colliders.

    Feed it poses with :meth:`on_pose` (``attach_physics`` subscribes it to a
    session); add game objects with :meth:`add_ball` / :meth:`add_object` (anything
    else: ``world.space``); contact events go to ``emit`` (``session.emit``), stamped
    ``emitted_t = now()`` (the session clock; the pose time when ``now`` is None).
    Positions in the plane are ``(u, v)`` metres (frontal: world X, Y). Thread-safe:
    hold ``world.lock`` to touch ``world.space`` while a session worker runs.
    """

    def __init__(
        self,
        options: PhysicsOptions | None = None,
        *,
        emit: Callable[[Event], object] | None = None,
        now: Callable[[], float] | None = None,
    ) -> None:
        self.options = (options or PhysicsOptions()).validate()
        o = self.options
        self._emit = emit
        self._now = now
        self._axes = PLANES[o.plane]
        self.space = pymunk.Space()
        self.space.gravity = (float(o.gravity[0]), float(o.gravity[1]))
        self.space.iterations = o.iterations
        self.space.collision_slop = o.collision_slop
        self.space.on_collision(
            PART_COLLISION_TYPE, None,
            begin=self._on_begin, post_solve=self._on_post_solve, separate=self._on_separate,
        )
        self.lock = threading.RLock()
        self.height: float | None = o.body_height
        """Body height in metres used for the part sizes (set at the first pose)."""
        self.depth: float = 0.0 if o.depth is None else float(o.depth)
        """Where the plane lies along its depth axis (m): the ``z`` of frontal contacts."""
        self.steps = 0
        """Simulation steps taken since the first pose."""
        self._parts: dict[str, _Part] = {}
        self._shape_part: dict[pymunk.Shape, str] = {}
        self._shape_obj: dict[pymunk.Shape, str] = {}
        self._objects: dict[str, PhysicsObject] = {}
        self._counts: dict[Key, int] = {}
        self._active: set[Key] = set()
        self._pending = Pending()
        self._begin_uv: dict[Key, tuple[float, float] | None] = {}
        self._graveyard: list[pymunk.Shape] = []
        self._dirty = False
        self._flushing = False
        self._stepping = False
        self._t0: float | None = None
        self._prev_t = 0.0
        self._prev_uv: NDArray[np.float64] | None = None
        self._last_t: float | None = None
        self._auto = 0
        self._closed = False
        self._detach: Callable[[], object] | None = None

    # ---- plane ---------------------------------------------------------------------
    def to_plane(self, point: ArrayLike) -> tuple[float, float]:
        """World (x, y, z) metres -> plane (u, v)."""
        p = np.asarray(point, dtype=np.float64).reshape(3)
        return float(p[self._axes[0]]), float(p[self._axes[1]])

    def to_world(self, uv: ArrayLike) -> tuple[float, float, float]:
        """Plane (u, v) -> world (x, y, z) metres, at the plane's current ``depth``."""
        u, v = np.asarray(uv, dtype=np.float64).reshape(2)
        out = [0.0, 0.0, 0.0]
        out[self._axes[0]], out[self._axes[1]], out[self._axes[2]] = float(u), float(v), self.depth
        return out[0], out[1], out[2]

    @property
    def time(self) -> float:
        """Simulation time (s, on the pose clock): first pose's ``t`` + steps * dt."""
        return (self._t0 or 0.0) + self.steps * self.options.dt

    # ---- game objects --------------------------------------------------------------
    def add_ball(
        self,
        position: ArrayLike,
        velocity: ArrayLike = (0.0, 0.0),
        radius: float = 0.11,
        mass: float = 0.43,
        name: str | None = None,
        *,
        elasticity: float = 0.8,
        friction: float = 0.5,
    ) -> PhysicsObject:
        """Add a dynamic ball at plane ``position`` (u, v) m with ``velocity`` m/s
        (defaults: a size-5 football, 0.11 m, 0.43 kg); ``name`` defaults to
        ``ball<N>``."""
        if not (math.isfinite(radius) and radius > 0):
            raise ConfigError(f"ball radius must be positive metres, got {radius}")
        if not (math.isfinite(mass) and mass > 0):
            raise ConfigError(f"ball mass must be positive kilograms, got {mass}")
        body = pymunk.Body(float(mass), pymunk.moment_for_circle(float(mass), 0.0, float(radius)))
        body.position = _vec(position, "position")
        body.velocity = _vec(velocity, "velocity")
        shape = pymunk.Circle(body, float(radius))
        shape.elasticity = float(elasticity)
        shape.friction = float(friction)
        return self.add_object(body, shape, name=name, prefix="ball")

    def add_object(
        self, body: pymunk.Body, *shapes: pymunk.Shape, name: str | None = None,
        prefix: str = "object",
    ) -> PhysicsObject:
        """Add your own pymunk body and shapes under a unique ``name`` (default
        ``<prefix><N>``); contacts of its shapes with body parts become events."""
        with self.lock:
            self._check_open()
            if name is None:
                while f"{prefix}{self._auto}" in self._objects:
                    self._auto += 1
                name = f"{prefix}{self._auto}"
                self._auto += 1
            if not isinstance(name, str) or not name:
                raise ConfigError(f"object name must be a non-empty string, got {name!r}")
            if name in self._objects:
                raise ConfigError(f"an object named {name!r} is already in the world; "
                                  "remove it first or pick another name")
            if not shapes:
                raise ConfigError(f"object {name!r} needs at least one shape")
            for s in shapes:
                if s.body is not body:
                    raise ConfigError(f"a shape of object {name!r} is attached to another body")
            static = body.body_type == pymunk.Body.STATIC
            add: list[Any] = [] if static or body in self.space.bodies else [body]
            add.extend(s for s in shapes if s not in self.space.shapes)
            for s in shapes:
                self._shape_obj[s] = name
            self.space.add(*add)
            obj = PhysicsObject(name, body, tuple(shapes))
            self._objects[name] = obj
            return obj

    def remove(self, obj: str | PhysicsObject) -> bool:
        """Take an object out of the world (ending its contacts); False if unknown."""
        with self.lock:
            name = obj.name if isinstance(obj, PhysicsObject) else obj
            found = self._objects.pop(name, None)
            if found is None:
                return False
            self._remove_object(found)
            self._flush(self._last_t or 0.0)
            return True

    def _remove_object(self, obj: PhysicsObject) -> None:
        items: list[Any] = [s for s in obj.shapes if s in self.space.shapes]
        if obj.body in self.space.bodies:
            items.append(obj.body)
        self.space.remove(*items)  # deferred to the step's end when called inside a step
        self._graveyard.extend(obj.shapes)  # names kept until pymunk has separated them
        self._dirty = True

    @property
    def objects(self) -> dict[str, PhysicsObject]:
        """The game objects by name (a copy)."""
        return dict(self._objects)

    def part_shape(self, name: str) -> pymunk.Shape | None:
        """The pymunk shape of an enabled body part (None while disabled or unbuilt)."""
        if name not in PART_NAMES:
            raise ConfigError(f"unknown body part {name!r}; known: {', '.join(PART_NAMES)}")
        p = self._parts.get(name)
        return p.shape if p is not None and p.enabled else None

    @property
    def enabled_parts(self) -> tuple[str, ...]:
        """Names of the parts currently in the space, in PART_NAMES order."""
        return tuple(n for n, p in self._parts.items() if p.enabled)

    @property
    def contacts(self) -> tuple[Key, ...]:
        """The (part, object) pairs touching now (begun and not ended), sorted."""
        return tuple(sorted(self._active, key=sort_key))

    # ---- poses -----------------------------------------------------------------------
    def on_pose(self, event: PoseEvent) -> None:
        """Move the body parts to ``event``'s pose, stepping the world up to its time,
        and emit the contacts that began or ended (stamped ``t = event.t``)."""
        if event.player != self.options.player:
            return
        with self.lock:
            if self._closed:
                return
            t, uv = self._take_pose(event)
            present = {n: self._geometry(p, uv) is not None for n, p in self._parts.items()}
            for n, p in self._parts.items():
                if p.enabled and not present[n]:
                    self._disable(p)
            self._flush(t)
            if self._t0 is None:
                self._t0 = t
            else:
                self._advance(t, uv)
            for n, p in self._parts.items():
                if present[n] and not p.enabled:
                    self._enable(p, uv)
            self._prev_uv, self._prev_t, self._last_t = uv, t, t

    def _take_pose(self, event: PoseEvent) -> tuple[float, NDArray[np.float64]]:
        """Check that ``event`` comes after the previous pose, size the body parts to it
        and return its time with the joints projected on the play plane (under the lock)."""
        t = float(event.t)
        if self._last_t is not None and not t > self._last_t:
            raise TimestampError(
                f"physics got pose frame {event.frame} at t = {t:.6f} s, not after the "
                f"previous pose at t = {self._last_t:.6f} s"
            )
        joints = self._joints(event)
        self._build(joints)
        return t, self._points(joints)

    def resume(self, event: PoseEvent) -> None:
        """Take ``event``'s pose without simulating the time since the previous pose
        (after a game pause): objects stay where they were, the body parts jump to the
        new pose, and stepping goes on from this pose's time (:attr:`time` jumps to it)."""
        if event.player != self.options.player:
            return
        with self.lock:
            if self._closed:
                return
            t, uv = self._take_pose(event)
            for p in self._parts.values():
                g = self._geometry(p, uv)
                if p.enabled and g is None:
                    self._disable(p)
                elif p.enabled and g is not None:
                    p.pos, p.angle, p.length = (g[0], g[1]), g[2], g[3]
                    p.body.position = p.pos
                    p.body.angle = p.angle
                    p.body.velocity = (0.0, 0.0)
                    p.body.angular_velocity = 0.0
                    self._set_length(p, p.length)
                elif g is not None:
                    self._enable(p, uv)
            self._flush(t)
            self._t0 = t - self.steps * self.options.dt
            self._prev_uv, self._prev_t, self._last_t = uv, t, t

    @staticmethod
    def _joints(event: PoseEvent) -> NDArray[np.float64]:
        """The (17, 3) joints with NaN wherever the state says ``lost``."""
        j = np.asarray(event.joints, dtype=np.float64)
        if j.shape != (NUM_JOINTS, 3) or len(event.state) != NUM_JOINTS:
            raise ConfigError(f"pose joints must have shape ({NUM_JOINTS}, 3), got {j.shape}")
        lost = np.array([s == "lost" for s in event.state], dtype=bool)
        return np.where(lost[:, None], np.nan, j)

    def _points(self, joints: NDArray[np.float64]) -> NDArray[np.float64]:
        """The POINT_NAMES positions projected to the plane, (19, 2), NaN where lost;
        also moves the plane's depth to the torso's when ``options.depth`` is None."""
        pts = np.full((len(POINT_NAMES), 3), np.nan)
        pts[:NUM_JOINTS] = joints
        off = self.options.hand_offset * (self.height or 1.75)
        for hand, wrist, elbow in _HANDS:
            w, e = pts[JOINT_INDEX[wrist]], pts[JOINT_INDEX[elbow]]
            d = w - e
            n = float(np.linalg.norm(d)) if np.all(np.isfinite(d)) else 0.0
            pts[_POINT_INDEX[hand]] = w + d * (off / n) if n > 1e-6 else w
        if self.options.depth is None:
            torso = pts[[JOINT_INDEX["pelvis"], JOINT_INDEX["neck"]], self._axes[2]]
            torso = torso[np.isfinite(torso)]
            if torso.size:
                self.depth = float(torso.mean())
        return pts[:, [self._axes[0], self._axes[1]]]

    def _build(self, joints: NDArray[np.float64]) -> None:
        if self._parts:
            return
        if self.height is None:
            self.height = estimate_height(joints) or 1.75
        o = self.options
        for spec in PART_SPECS:
            if spec.name not in o.parts:
                continue
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            r = o.radius(spec, self.height)
            shape: pymunk.Shape
            if spec.kind == "circle":
                shape = pymunk.Circle(body, r)
            else:
                shape = pymunk.Segment(body, (0.0, 0.0), (0.0, 0.0), r)
            shape.elasticity = o.elasticity
            shape.friction = o.friction
            shape.collision_type = PART_COLLISION_TYPE
            shape.filter = _PART_GROUP
            self._parts[spec.name] = _Part(
                spec, body, shape, _POINT_INDEX[spec.a], _POINT_INDEX[spec.b]
            )
            self._shape_part[shape] = spec.name

    def _geometry(
        self, p: _Part, uv: NDArray[np.float64]
    ) -> tuple[float, float, float, float] | None:
        """(centre u, centre v, angle, length) of a part on points ``uv``, or None if lost."""
        a, b = uv[p.ia], uv[p.ib]
        if not (math.isfinite(a[0]) and math.isfinite(a[1])
                and math.isfinite(b[0]) and math.isfinite(b[1])):
            return None
        if p.spec.kind == "circle":
            return float(a[0]), float(a[1]), p.angle, 0.0
        du, dv = float(b[0] - a[0]), float(b[1] - a[1])
        length = math.hypot(du, dv)
        angle = p.angle
        if length > 1e-9:  # unwrap so the angular velocity takes the short way round
            d = math.atan2(dv, du) - p.angle
            angle = p.angle + (d + math.pi) % (2.0 * math.pi) - math.pi
        return 0.5 * float(a[0] + b[0]), 0.5 * float(a[1] + b[1]), angle, length

    def _enable(self, p: _Part, uv: NDArray[np.float64]) -> None:
        g = self._geometry(p, uv)
        assert g is not None
        p.pos, p.angle, p.length = (g[0], g[1]), g[2], g[3]
        p.body.position = p.pos
        p.body.angle = p.angle
        p.body.velocity = (0.0, 0.0)
        p.body.angular_velocity = 0.0
        self._set_length(p, p.length)
        self.space.add(p.body, p.shape)
        p.enabled = True

    def _disable(self, p: _Part) -> None:
        p.enabled = False
        self.space.remove(p.shape, p.body)  # pymunk calls separate for its contacts
        self._dirty = True

    @staticmethod
    def _set_length(p: _Part, length: float) -> None:
        if p.spec.kind == "segment":
            h = 0.5 * length
            p.shape.unsafe_set_endpoints((-h, 0.0), (h, 0.0))  # type: ignore[attr-defined]

    def _advance(self, t: float, uv: NDArray[np.float64]) -> None:
        o = self.options
        dt = o.dt
        assert self._t0 is not None and self._prev_uv is not None
        target = int(math.floor((t - self._t0) / dt + 1e-9))
        if target - self.steps > o.max_steps_per_pose:
            self.steps = target - o.max_steps_per_pose
        prev = np.where(np.isnan(self._prev_uv), uv, self._prev_uv)
        span = t - self._prev_t
        parts = [p for p in self._parts.values() if p.enabled]
        while self.steps < target:
            ts = self._t0 + (self.steps + 1) * dt
            f = min(1.0, max(0.0, (ts - self._prev_t) / span))
            at = prev + f * (uv - prev)
            for p in parts:
                g = self._geometry(p, at)
                assert g is not None
                p.nxt = g
                b = p.body
                b.position = p.pos
                b.angle = p.angle
                b.velocity = ((g[0] - p.pos[0]) / dt, (g[1] - p.pos[1]) / dt)
                b.angular_velocity = (g[2] - p.angle) / dt
                if g[3] != p.length:
                    self._set_length(p, g[3])
            self._stepping = True
            try:
                self.space.step(dt)
            finally:
                self._stepping = False
            self.steps += 1
            for p in parts:
                p.pos, p.angle, p.length = (p.nxt[0], p.nxt[1]), p.nxt[2], p.nxt[3]
            self._flush(t)

    # ---- contact events ------------------------------------------------------------
    def _send(self, t: float, key: Key, phase: str, uv: tuple[float, float] | None,
              impulse: float) -> None:
        if self._emit is None:
            return
        point = self.to_world(uv) if uv is not None else (math.nan, math.nan, math.nan)
        self._emit(ContactEvent(
            t=t,
            emitted_t=self._now() if self._now is not None else t,
            part=key[0],
            obj=key[1],
            phase=phase,  # type: ignore[arg-type]
            point=point,
            impulse=float(impulse),
            player=self.options.player,
        ))

    # ---- life cycle ------------------------------------------------------------------
    def _check_open(self) -> None:
        if self._closed:
            raise ConfigError("the physics world is closed; create a new one")

    @property
    def closed(self) -> bool:
        """Whether :meth:`close` was called."""
        return self._closed

    def close(self) -> None:
        """End every contact (emitting the ``end`` events), stop following the session
        and empty the space. Calling it again does nothing."""
        with self.lock:
            if self._closed:
                return
            if self._detach is not None:
                self._detach()
                self._detach = None
            for obj in list(self._objects.values()):
                self._remove_object(obj)
            self._objects.clear()
            for p in self._parts.values():
                if p.enabled:
                    self._disable(p)
            self._flush(self._last_t or 0.0)
            self._closed = True

    def __enter__(self) -> PhysicsWorld:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __iter__(self) -> Iterator[PhysicsObject]:
        """The game objects, in the order they were added."""
        return iter(list(self._objects.values()))


def _vec(value: ArrayLike, what: str) -> tuple[float, float]:
    v = np.asarray(value, dtype=np.float64).reshape(-1)
    if v.shape != (2,) or not np.all(np.isfinite(v)):
        raise ConfigError(f"{what} must be two finite numbers (u, v) in the plane, got {value!r}")
    return float(v[0]), float(v[1])



def attach_physics(session: Any, options: PhysicsOptions | None = None) -> PhysicsWorld:
    """A PhysicsWorld following ``session``'s pose events and emitting ``contact``
    events on its bus (``emitted_t`` from the session clock). ``world.close()``
    unsubscribes it and ends every open contact."""
    world = PhysicsWorld(options, emit=session.emit, now=session.now)
    session.subscribe("pose", world.on_pose)

    def detach() -> None:
        session.bus.unsubscribe("pose", world.on_pose)

    world._detach = detach
    return world
