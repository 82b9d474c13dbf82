"""How a goalkeeper frame looks: the pitch, the goal and its net, the ball with its
shadow, the keeper, the score and the camera picture the tracker sees."""

from __future__ import annotations

import numpy as np

from apps.goalkeeper.game.rules import Rules, part_group
from apps.goalkeeper.game.shots import Goal
from bodyplay.app import GameContext, Scene

__all__ = ["draw_pitch", "draw_ball", "draw_hud"]

_WHITE = (0.95, 0.95, 0.95)
_NET = (0.85, 0.85, 0.88)
_BANNER = {"save": ("SAVE!", (0.3, 1.0, 0.4)), "goal": ("GOAL", (1.0, 0.3, 0.25)),
           "wide": ("WIDE", (0.9, 0.9, 0.9))}


def draw_pitch(scene: Scene, goal: Goal) -> None:
    """Camera behind the penalty spot, mirrored (the player sees a mirror), grass,
    goal frame and net."""
    scene.look((0.0, 1.45, goal.distance + 1.6), (0.0, 0.95, 0.0), hfov_deg=46.0)
    scene.mirror = True
    scene.sky = (0.58, 0.74, 0.92)
    scene.floor((0.30, 0.56, 0.26), (0.27, 0.51, 0.23), size=40.0, tile=1.0)
    w, h, z = goal.width / 2, goal.height, goal.line_z
    back = z - 0.8
    r = 0.05
    scene.capsule((-w, 0, z), (-w, h, z), r, _WHITE)
    scene.capsule((w, 0, z), (w, h, z), r, _WHITE)
    scene.capsule((-w, h, z), (w, h, z), r, _WHITE)
    scene.box((0.0, 0.004, goal.distance), (0.22, 0.008, 0.22), _WHITE)  # penalty spot
    scene.box((0.0, 0.004, z), (2 * w + 0.6, 0.008, 0.06), _WHITE)  # goal line
    for x in np.linspace(-w, w, 17):  # the net: roof, back and sides
        scene.line((x, h, z), (x, h * 0.75, back), _NET)
        scene.line((x, h * 0.75, back), (x, 0, back), _NET)
    for y in np.linspace(0.0, h * 0.75, 7):
        scene.line((-w, y, back), (w, y, back), _NET)
        for side in (-w, w):
            scene.line((side, y, z), (side, y, back), _NET)
    for k in np.linspace(0.0, 1.0, 5):
        scene.line((-w, h, z + (back - z) * k), (w, h - h * 0.25 * k, z + (back - z) * k), _NET)


def draw_ball(scene: Scene, rules: Rules) -> None:
    """The ball in play, never below the grass, with its shadow."""
    b = rules.ball
    if b is None:
        return
    x, y, z = b.position
    rad = rules.options.ball_radius
    scene.sphere((x, max(y, rad), z), rad, (0.97, 0.97, 0.97), shadow=True)


def draw_hud(ctx: GameContext, scene: Scene, rules: Rules) -> None:
    """Score line, streak, difficulty and the last result's banner."""
    r = rules
    taken = r.saves + r.goals + r.wide
    scene.text(f"SHOT {min(r.next_shot, len(r.shots))}/{len(r.shots)}", (14, 30), 0.9)
    scene.text(f"SAVES {r.saves}   GOALS {r.goals}", (14, 58), 0.9, (1.0, 0.95, 0.6))
    scene.text(f"streak {r.streak}  best {r.best_streak}", (14, 84), 0.7)
    b = r.ball
    if taken and b is not None and b.outcome:  # the result, while the ball lingers
        text, color = _BANNER[b.outcome]
        if b.outcome == "save":
            text += f"  ({part_group(b.part)})"
        scene.text(text, (scene.width / 2, 120), 1.8, color, anchor="center")
    level = r.shots[min(r.next_shot, len(r.shots)) - 1].level if r.next_shot else 0.0
    scene.text(f"difficulty {'#' * (1 + int(level * 9))}", (14, scene.height - 16), 0.6,
               (0.95, 0.95, 0.95))
