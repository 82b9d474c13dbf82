"""A fight without pixels: the virtual ninja's joints go straight to the recognizer.

:func:`simulate_fight` plays a :class:`~apps.ninja.game.player.NinjaPlayer` against the
rules at the pose level (the player's skeleton joints, optionally jittered like a
tracker, through a bodyplay Session with the five gestures and a fixed clock), one
camera frame at a time, with the player reacting to the fight between frames. It is
the fast path for gameplay tests and the gesture benchmarks; the app runs the same
rules and player through the game kit, the synthetic camera and a tracker.
"""

from __future__ import annotations

from typing import Any

from apps.ninja.game.player import NinjaPlayer
from apps.ninja.game.rules import NINJA_GESTURES, NinjaOptions, NinjaRules
from bodyplay.errors import ConfigError
from bodyplay.gestures import GestureRecognizer, load_gestures
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.session import create_session
from bodyplay.testing import ScriptedPlayer

__all__ = ["simulate_fight", "ninja_recognizer"]


def ninja_recognizer() -> GestureRecognizer:
    """A recognizer of the five ninja motions (the built-in definitions)."""
    return GestureRecognizer(load_gestures(list(NINJA_GESTURES)))


def simulate_fight(player: NinjaPlayer, *, seconds: float = 40.0, seed: int = 0,
                   fps: float = 30.0, noise: float = 0.0,
                   options: NinjaOptions | None = None,
                   stop_when_over: bool = True) -> NinjaRules:
    """Play ``seconds`` of the fight at ``fps``; return the rules (their summary is the
    result). ``noise`` is Gaussian joint jitter in metres (seeded by ``seed``)."""
    if not seconds > 0:
        raise ConfigError(f"seconds must be positive, got {seconds}")
    rules = NinjaRules(options, seed=seed)
    source = ScriptedPlayer(player.timeline, fps, duration=seconds, noise=noise, seed=seed)
    session = create_session(source=source, gestures=ninja_recognizer(),
                             filters=["one_euro"] if noise > 0 else [],
                             clock=FixedClock(1.0 / fps))

    def on_gesture(ev: Any) -> None:
        if ev.phase == "performed":
            rules.on_gesture(ev.gesture, ev.t, ev.started_t)

    session.on("gesture")(on_gesture)
    with session:
        while True:
            pose = session.step()
            if session.done:
                break
            if pose is None:
                continue
            rules.update(pose.t)
            player.react(pose.t, rules)
            if stop_when_over and rules.over:
                break
    return rules
