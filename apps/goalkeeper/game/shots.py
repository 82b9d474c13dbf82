"""The shots of a round: where each ball starts, where it aims, how fast, with what spin.

Pure numbers, no physics: :func:`plan_round` draws ``n`` shots from the game's
random generator with difficulty ramping from the first shot to the last (faster
balls, targets farther from the keeper's body, more spin, less time between shots).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bodyplay.errors import ConfigError

__all__ = ["Goal", "Shot", "plan_round", "GRAVITY"]

GRAVITY = 9.81


@dataclass(frozen=True)
class Goal:
    """The goal mouth: ``width`` x ``height`` m centred on x = 0, its line at ``line_z``;
    the keeper stands at z = 0 and shots start ``distance`` m in front (+Z)."""

    width: float = 2.8
    height: float = 2.0
    line_z: float = -0.7
    distance: float = 6.5


@dataclass(frozen=True)
class Shot:
    """One shot: ``start`` (x, y) on the penalty spot, ``target`` (x, y) on the goal
    line, ``speed`` towards the goal (m/s along -Z), ``spin`` (sideways curl, m/s^2),
    ``wait`` (s before it is kicked), ``level`` (0..1 difficulty)."""

    index: int
    start: tuple[float, float]
    target: tuple[float, float]
    speed: float
    spin: float
    wait: float
    level: float

    def flight_time(self, goal: Goal) -> float:
        """Seconds from the kick to the goal line."""
        return (goal.distance - goal.line_z) / self.speed

    def launch_velocity(self, goal: Goal) -> tuple[float, float]:
        """Sideways and upward velocity (m/s) that brings the ball, under gravity and
        its spin, from ``start`` to ``target`` in :meth:`flight_time`."""
        T = self.flight_time(goal)
        vx = (self.target[0] - self.start[0] - 0.5 * self.spin * T * T) / T
        vy = (self.target[1] - self.start[1] + 0.5 * GRAVITY * T * T) / T
        return vx, vy

    def position(self, goal: Goal, t: float) -> tuple[float, float, float]:
        """Where the unhindered ball is ``t`` seconds after the kick (world x, y, z)."""
        vx, vy = self.launch_velocity(goal)
        x = self.start[0] + vx * t + 0.5 * self.spin * t * t
        y = self.start[1] + vy * t - 0.5 * GRAVITY * t * t
        return x, y, goal.distance - self.speed * t


def plan_round(
    rng: np.random.Generator, n: int = 20, goal: Goal | None = None, *,
    ball_radius: float = 0.11,
) -> list[Shot]:
    """``n`` shots of rising difficulty, all on target (inside the goal mouth)."""
    if not 1 <= n <= 500:
        raise ConfigError(f"a round has 1..500 shots, got {n}")
    goal = goal or Goal()
    shots = []
    half = goal.width / 2 - ball_radius - 0.05
    for i in range(n):
        level = i / max(n - 1, 1)
        speed = (7.0 + 10.0 * level**1.5) * rng.uniform(0.92, 1.08)
        reach = 0.35 + (half - 0.35) * min(1.0, 0.25 + level)
        x = float(rng.uniform(0.25, 1.0) * reach * rng.choice((-1.0, 1.0)))
        y = float(rng.uniform(0.3, goal.height - ball_radius - 0.1))
        spin = float(rng.uniform(-1.0, 1.0) * (0.5 + 3.5 * level))
        wait = float((0.9 - 0.35 * level) * rng.uniform(0.9, 1.1))
        start = (float(rng.uniform(-0.3, 0.3)), ball_radius)
        shots.append(Shot(i, start, (x, y), float(speed), spin, wait, float(level)))
    return shots
