"""The cloth mirror's game part (no window): the game, its scene and its summary."""

from apps.cloth_mirror.game.game import ClothMirrorGame, mirror_timeline

__all__ = ["ClothMirrorGame", "mirror_timeline"]
