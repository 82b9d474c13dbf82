"""The virtual ninja: a scripted player who answers the opponent, one motion at a time.

:class:`NinjaPlayer` is a pose controller (``pose_at(t)`` gives the actor skeleton's
pose vector, the contract of ``bodyplay.app`` virtual players) built on a
:class:`~bodyplay.testing.Timeline`. The game calls :meth:`NinjaPlayer.react` every
step with its rules; the player then appends the next motion to its timeline, never
in the past: it transfigures, dodges each telegraphed attack with the right motion
after a human reaction time (crouch under a high attack, a side step away from a
sweep, alternating left and right so it stays near the middle), and between attacks
throws fire rings (a double hit whenever its cool-down allows). Every motion it
starts is logged in :attr:`NinjaPlayer.script` with its start and end, so a test can
check the game's summary against what the player really did.

``style`` makes the deliberately bad players the tests need: ``"idle"`` transfigures
and then stands still, ``"wrong"`` answers every attack with the wrong dodge,
``"still"`` never even transfigures.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.testing import GESTURE_MOTIONS, Timeline, key_pose

if TYPE_CHECKING:
    from apps.ninja.game.rules import NinjaRules

__all__ = ["NinjaPlayer", "MOTION_LENGTH", "MOTION_END"]

Style = Literal["fighter", "idle", "wrong", "still"]
_STYLES = ("fighter", "idle", "wrong", "still")

MOTION_LENGTH: dict[str, float] = {
    g: float(GESTURE_MOTIONS[g][-1][0])  # type: ignore[index]
    for g in ("transfigure", "crouch", "step_left", "step_right", "hit", "double_hit")
}
"""Seconds each of the five motions takes at speed 1 (its last key)."""

MOTION_END: dict[str, float] = {
    "transfigure": 1.3, "crouch": 0.4, "step_left": 0.6, "step_right": 0.6, "hit": 0.8,
    "double_hit": 0.85,
}
"""Seconds from a motion's start to the end of its defining movement (arms folded,
squat reached, feet together, arm down): the reference for gesture latency."""

_STEP = 0.5  # metres a side step moves the player (the key poses idle_left / idle_right)


class NinjaPlayer:
    """A reactive scripted ninja (see the module docstring).

    ``reaction`` s pass between an attack's telegraph and the start of the dodge;
    ``rest`` s of stillness follow each motion (so the recognizer re-arms);
    ``transfigure_at`` is when it starts; ``skeleton`` is the actor's.
    """

    def __init__(self, skeleton: Skeleton | None = None, *, style: Style = "fighter",
                 reaction: float = 0.35, rest: float = 0.35, transfigure_at: float = 1.0,
                 speed: float = 1.0) -> None:
        if style not in _STYLES:
            raise ConfigError(f"unknown player style {style!r}; choose one of {_STYLES}")
        for name, v in (("reaction", reaction), ("rest", rest),
                        ("transfigure_at", transfigure_at)):
            if not (np.isfinite(v) and v >= 0):
                raise ConfigError(f"{name} must be >= 0 seconds, got {v}")
        if not (np.isfinite(speed) and speed > 0):
            raise ConfigError(f"speed must be positive, got {speed}")
        self.timeline = Timeline(skeleton, blend=0.15)
        self.skeleton = self.timeline.skeleton
        self.style: Style = style
        self.reaction = float(reaction)
        self.rest = float(rest)
        self.speed = float(speed)
        self.transfigure_at = float(transfigure_at)
        self.script: list[dict[str, Any]] = []
        self.x = 0.0
        self._busy_until = 0.0
        self._answered: set[int] = set()
        if style != "still":
            self._perform("transfigure", self.transfigure_at)

    # ---- the controller protocol -------------------------------------------------------
    def pose_at(self, t: float) -> NDArray[np.float64]:
        """The actor's pose vector at time ``t``."""
        return self.timeline.pose_at(t)

    def joints_at(self, t: float) -> NDArray[np.float64]:
        """(17, 3) joints of the pose at ``t`` (the truth)."""
        return self.timeline.joints_at(t)

    def frame_joints(self) -> NDArray[np.float64]:
        """Joints spanning where the player will be: the extreme poses of the five
        motions, a side step either way (the synthetic camera frames its rig on them)."""
        out = []
        for pose in ("idle", "double_up", "arms_out", "squat"):
            for x in (-_STEP, 0.0, _STEP):
                v = key_pose(pose, self.skeleton).copy()
                v[0] += x
                out.append(self.skeleton.joint_positions(v))
        return np.stack(out)

    # ---- behaviour ---------------------------------------------------------------------
    def _perform(self, gesture: str, start: float) -> None:
        length = MOTION_LENGTH[gesture] / self.speed
        self.timeline.gesture(gesture, start=start, speed=self.speed, at=(self.x, 0.0))
        self.script.append({"gesture": gesture, "start": round(start, 4),
                            "end": round(start + length, 4),
                            "motion_end": round(start + MOTION_END[gesture] / self.speed, 4)})
        if gesture == "step_left":
            self.x += _STEP
        elif gesture == "step_right":
            self.x -= _STEP
        self._busy_until = start + length + self.rest

    def react(self, t: float, rules: NinjaRules) -> None:
        """Look at the fight at time ``t`` and plan the next motion (never in the past)."""
        if self.style in ("still", "idle") or rules.over or rules.phase != "fight":
            return
        attack = rules.current_attack
        if attack is not None and len(rules.attacks) - 1 not in self._answered:
            if t < attack.telegraph_t + self.reaction:
                return
            self._answered.add(len(rules.attacks) - 1)
            if attack.kind == "high":
                dodge = "step_left" if self.style == "wrong" else "crouch"
            elif self.style == "wrong":
                dodge = "crouch"
            else:
                dodge = "step_right" if self.x > 0 else "step_left"
            self._perform(dodge, max(t, self._busy_until))
            return
        if t < self._busy_until:
            return
        if attack is not None and attack.strike_t + rules.options.grace > t:
            return  # dodged already; wait for the strike to pass before striking back
        ready = rules.double_ready_in(t + MOTION_END["double_hit"] / self.speed) == 0.0
        self._perform("double_hit" if ready else "hit", t)
