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


@pytest.fixture
def play_goalkeeper(tmp_path):  # type: ignore[no-untyped-def]
    """``play_goalkeeper(reach=True, shots=20, seed=0, source=None, game=None)``: a
    pose-level round (no camera, no tracker) against the virtual keeper; ``reach``
    False keeps the keeper in its idle motion. Returns the GameResult."""
    from apps.goalkeeper.game import GoalkeeperGame, GoalkeeperOptions

    from bodyplay.app import make_game_options, run_game
    from bodyplay.virtual import ReachController, VirtualPoseSource

    runs = iter(range(1000))

    def play(reach: bool = True, shots: int = 20, seed: int = 0, source: Any = None,
             game: Any = None, controller: Any = None) -> Any:
        ctl = controller if controller is not None else ReachController()
        g = game if game is not None else GoalkeeperGame(GoalkeeperOptions(shots=shots))
        g.logic.controller = ctl if reach else None
        src = source if source is not None else VirtualPoseSource(
            ctl, seed=seed, upper_body_only=True, noise=0.01)
        opts = make_game_options(headless=True, out=tmp_path / f"run{next(runs)}", seed=seed,
                                 video=False, progress=False)
        return run_game(g, opts, source=src)

    return play
