"""Fixtures for the example games' scripted gameplay tests."""

from __future__ import annotations

from typing import Any

import pytest


@pytest.fixture
def play_ninja():  # type: ignore[no-untyped-def]
    """``play_ninja(player, seconds, seed)``: a pose-level fight (no camera, no tracker)
    between ``player`` (a NinjaPlayer) and the opponent; returns (rules, player)."""
    from apps.ninja.game.simulate import simulate_fight

    def play(player: Any, seconds: float = 40.0, seed: int = 0, **kw: Any) -> Any:
        return simulate_fight(player, seconds=seconds, seed=seed, **kw)

    return play
