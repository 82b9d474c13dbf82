"""The goalkeeper's rules: kick, fly, save or goal, score, and the virtual keeper.

The SDK's physics world is a plane through the keeper (world X, Y); a shot's ball
lives there from the kick, with gravity and its spin, while the game tracks its
depth (Z) from the penalty spot to the goal line. The ball collides with the
keeper's body parts only while its depth is within ``window`` of the keeper's
plane (the keeper's body is there); a ``contact`` event with the ball in that
moment is a save, credited to the body part. A ball that reaches the goal line
inside the mouth is a goal.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pymunk

from apps.goalkeeper.game.shots import Goal, Shot, plan_round
from bodyplay.app import GameContext, HandTrace, Marker, plot_hand_motion
from bodyplay.errors import ConfigError
from bodyplay.events.types import ContactEvent
from bodyplay.optiontypes import check_option_types
from bodyplay.physics import PhysicsObject, PhysicsOptions

__all__ = ["GoalkeeperOptions", "Ball", "Rules", "part_group", "PART_GROUPS"]

PART_GROUPS = ("hand", "arm", "body", "head", "leg")
"""How contacts and saves are counted: the body part groups."""

_NO_COLLISION = pymunk.ShapeFilter(mask=0)
_COLLIDE = pymunk.ShapeFilter()


def sim_time(world: Any) -> float:
    """Seconds the physics world has simulated (pauses excluded: no steps then)."""
    return float(world.steps * world.options.dt)


def part_group(part: str) -> str:
    """The group of a physics body part: ``l_hand`` -> hand, ``r_forearm`` -> arm..."""
    if part.endswith("hand"):
        return "hand"
    if part.endswith(("upper_arm", "forearm")):
        return "arm"
    if part == "torso":
        return "body"
    if part == "head":
        return "head"
    return "leg"


@dataclass(frozen=True)
class GoalkeeperOptions:
    """A round: ``shots`` kicks at a ``goal``; the ball of ``ball_radius`` m collides
    with the keeper while within ``window`` m of the keeper's plane in depth; results
    stay on screen ``linger`` s."""

    shots: int = 20
    goal: Goal = Goal()
    ball_radius: float = 0.11
    window: float = 0.3
    linger: float = 0.5

    def __post_init__(self) -> None:
        check_option_types(self)
        if not 1 <= self.shots <= 500:
            raise ConfigError(f"shots must be 1..500, got {self.shots}")
        if not 0.05 <= self.ball_radius <= 0.3:
            raise ConfigError(f"ball_radius must be 0.05..0.3 m, got {self.ball_radius}")
        if not 0.05 <= self.window <= 1.0:
            raise ConfigError(f"window must be 0.05..1 m, got {self.window}")

    def round_seconds(self, shots: list[Shot]) -> float:
        """Game seconds the round lasts (waits, flights and lingering results)."""
        return sum(s.wait + s.flight_time(self.goal) + self.linger for s in shots) + 1.0


@dataclass(eq=False)
class Ball:
    """The ball in play: its shot, physics object, kick time (physics clock), depth."""

    shot: Shot
    obj: PhysicsObject
    kicked: float
    z: float
    kicked_t: float = 0.0
    outcome: str = ""
    part: str = ""
    resolved_t: float = 0.0
    back_speed: float = 0.0

    @property
    def position(self) -> tuple[float, float, float]:
        """World (x, y, z) of the ball now."""
        p = self.obj.body.position
        return float(p.x), float(p.y), self.z


@dataclass(eq=False)
class Rules:
    """The state of a round (everything the summary and the HUD read)."""

    options: GoalkeeperOptions
    shots: list[Shot]
    next_shot: int = 0
    ball: Ball | None = None
    timer: float = 0.0
    saves: int = 0
    goals: int = 0
    wide: int = 0
    streak: int = 0
    best_streak: int = 0
    log: list[dict[str, Any]] = field(default_factory=list)
    contacts: dict[str, int] = field(default_factory=lambda: dict.fromkeys(PART_GROUPS, 0))
    saves_by: dict[str, int] = field(default_factory=lambda: dict.fromkeys(PART_GROUPS, 0))
    markers: list[Marker] = field(default_factory=list)
    done: bool = False

    @classmethod
    def new(cls, options: GoalkeeperOptions, seed: int) -> Rules:
        """A fresh round planned from ``seed``."""
        shots = plan_round(np.random.default_rng(seed), options.shots, options.goal,
                           ball_radius=options.ball_radius)
        return cls(options, shots, timer=shots[0].wait)


class GoalkeeperLogic:
    """Kicks, flights and results on a PhysicsWorld; steers a virtual keeper if given."""

    physics_options = PhysicsOptions()

    def __init__(self, options: GoalkeeperOptions, controller: Any = None) -> None:
        self.options = options
        self.controller = controller
        self.rules: Rules | None = None
        self.trace = HandTrace()
        self._now = 0.0

    # ---- events --------------------------------------------------------------------
    def on_contact(self, ev: ContactEvent) -> None:
        """Count contacts per part group; a touch of the ball in flight is a save."""
        r = self.rules
        if r is None or ev.phase != "begin":
            return
        group = part_group(ev.part)
        r.contacts[group] += 1
        b = r.ball
        if b is None or ev.obj != b.obj.name or b.outcome:
            return
        b.outcome, b.part = "save", ev.part
        b.back_speed = 0.35 * b.shot.speed
        r.saves += 1
        r.saves_by[group] += 1
        r.streak += 1
        r.best_streak = max(r.best_streak, r.streak)
        self._resolve(b, ev.t, impulse=ev.impulse)

    # ---- the round -------------------------------------------------------------------
    def update(self, ctx: GameContext, dt: float) -> None:
        """One fixed step: count down, kick, follow the ball, decide, next shot."""
        r = self.rules
        world = ctx.physics
        if r is None or world is None or r.done:
            return
        b = r.ball
        if b is None:
            r.timer -= dt
            if r.timer <= 0.0:
                if r.next_shot >= len(r.shots):
                    r.done = True
                    ctx.finish()
                    return
                self._kick(ctx, r.shots[r.next_shot])
                r.next_shot += 1
            return
        o = self.options
        goal = o.goal
        now = self._now = sim_time(world)
        if not b.outcome and b.z <= goal.line_z:
            x, y, _ = b.position
            inside = abs(x) <= goal.width / 2 and 0.0 <= y <= goal.height
            b.outcome = "goal" if inside else "wide"
            if inside:
                r.goals += 1
            else:
                r.wide += 1
            r.streak = 0
            self._resolve(b, ctx.pose.t if ctx.pose is not None else now)
        if b.outcome and now - b.resolved_t >= o.linger:
            world.remove(b.obj)
            r.ball = None
            r.timer = r.shots[r.next_shot].wait if r.next_shot < len(r.shots) else 1.0

    def _kick(self, ctx: GameContext, shot: Shot) -> None:
        world = ctx.physics
        assert world is not None and self.rules is not None
        o = self.options
        vx, vy = shot.launch_velocity(o.goal)
        obj = world.add_ball(shot.start, (vx, vy), radius=o.ball_radius, mass=0.43,
                             name=f"ball{shot.index}", elasticity=0.7)
        obj.shapes[0].filter = _NO_COLLISION
        ball = Ball(shot, obj, sim_time(world), o.goal.distance,
                    kicked_t=float(ctx.pose.t) if ctx.pose is not None else 0.0)

        shape = obj.shapes[0]

        def velocity(body: pymunk.Body, gravity: Any, damping: float, dt: float) -> None:
            # every physics step: the depth moves on, and the ball meets the keeper's
            # body parts only while it is within the window around the keeper's plane
            if ball.outcome == "goal" and ball.z <= o.goal.line_z - 0.5:  # in the net
                body.velocity = (0.0, body.velocity.y)
                pymunk.Body.update_velocity(body, gravity, damping, dt)
                return
            ball.z += (ball.back_speed if ball.outcome == "save" else -shot.speed) * dt
            near = abs(ball.z - world.depth) <= o.window
            collide = ball.outcome == "save" or (not ball.outcome and near)
            shape.filter = _COLLIDE if collide else _NO_COLLISION
            spin = shot.spin if not ball.outcome else 0.0
            pymunk.Body.update_velocity(body, (gravity[0] + spin, gravity[1]), damping, dt)

        obj.body.velocity_func = velocity
        self.rules.ball = ball
        if self.controller is not None and ctx.pose is not None:
            # tell the virtual keeper where and when the ball crosses its plane
            t_cross = (o.goal.distance - world.depth) / shot.speed
            x, y, _ = shot.position(o.goal, t_cross)
            now = float(ctx.pose.t)
            with contextlib.suppress(ConfigError):  # refused: the keeper does not move
                self.controller.set_target(now + t_cross, (x, y, world.depth), now=now)

    def _resolve(self, b: Ball, t: float, impulse: float = 0.0) -> None:
        """Log the outcome at pose time ``t`` (linger counts from the simulated now)."""
        r = self.rules
        assert r is not None
        b.resolved_t = self._now
        x, y, z = b.position
        entry: dict[str, Any] = {
            "shot": b.shot.index, "outcome": b.outcome, "t": round(t, 4),
            "kicked_t": round(b.kicked_t, 4),
            "speed": round(b.shot.speed, 3), "spin": round(b.shot.spin, 3),
            "target": [round(v, 3) for v in b.shot.target], "level": round(b.shot.level, 3),
            "ball": [round(x, 3), round(y, 3), round(z, 3)],
        }
        if b.outcome == "save":
            entry["part"] = b.part
            entry["group"] = part_group(b.part)
            entry["impulse"] = round(impulse, 4)
        r.log.append(entry)
        color = {"save": (40, 170, 60), "goal": (220, 40, 40)}.get(b.outcome, (150, 150, 150))
        r.markers.append(Marker(t, b.outcome, color))

    # ---- results ---------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """The round's figures for summary.json."""
        r = self.rules
        if r is None:
            return {}
        taken = r.saves + r.goals + r.wide
        return {
            "shots": taken,
            "shots_planned": len(r.shots),
            "saves": r.saves,
            "goals": r.goals,
            "wide": r.wide,
            "save_rate": round(r.saves / taken, 4) if taken else None,
            "best_streak": r.best_streak,
            "contacts": dict(r.contacts),
            "saves_by": dict(r.saves_by),
            "hand_motion": self.trace.stats(),
            "shot_log": list(r.log),
        }

    def save_plot(self, ctx: GameContext) -> str:
        """The squash-style hand speed and acceleration plot, next to the video."""
        path = ctx.out / "goalkeeper_hands.png"
        r = self.rules
        plot_hand_motion(self.trace, path, r.markers if r is not None else (),
                         title="goalkeeper: hand speed and acceleration "
                               "(green: save, red: goal)")
        return str(path)
