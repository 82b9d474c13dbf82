"""The ninja fight's rules, virtual player and scene: pure, never imports a window."""

from apps.ninja.game.player import MOTION_END, MOTION_LENGTH, NinjaPlayer
from apps.ninja.game.rules import (
    ATTACK_KINDS,
    DODGES,
    NINJA_GESTURES,
    Attack,
    FireRing,
    NinjaOptions,
    NinjaRules,
    ninja_options,
)

__all__ = [
    "ATTACK_KINDS",
    "DODGES",
    "MOTION_END",
    "MOTION_LENGTH",
    "NINJA_GESTURES",
    "Attack",
    "FireRing",
    "NinjaOptions",
    "NinjaPlayer",
    "NinjaRules",
    "ninja_options",
]
