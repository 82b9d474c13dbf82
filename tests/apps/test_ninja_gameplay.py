"""Scripted ninja fights at the pose level: the virtual player's joints go to the
recognizer of the five motions and its gestures to the rules."""

from __future__ import annotations

import json

import pytest
from apps.ninja.game import NinjaPlayer


def _answers(rules) -> list[tuple[str, str | None, str]]:  # type: ignore[no-untyped-def]
    return [(a.kind, a.answer, a.outcome) for a in rules.attacks]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_player_who_dodges_every_attack_and_hits_back_wins(play_ninja, seed):
    player = NinjaPlayer()
    rules = play_ninja(player, seconds=60.0, seed=seed)
    assert rules.phase == "won"
    assert rules.player_health == rules.options.player_health
    resolved = [a for a in rules.attacks if a.outcome != "pending"]
    assert len(resolved) >= 2
    for kind, answer, outcome in _answers(rules):
        if outcome != "pending":
            assert outcome == "dodged"
            assert answer in (("crouch",) if kind == "high" else ("step_left", "step_right"))


def test_every_motion_the_player_performed_is_recognized_in_time(play_ninja):
    player = NinjaPlayer()
    rules = play_ninja(player, seconds=60.0, seed=0, noise=0.02)
    seen = [g for g in rules.gestures]
    done = [m for m in player.script if m["end"] + 0.5 <= rules.ended_t]
    assert len(done) >= 8
    for m in done:
        match = [g for g in seen if g["gesture"] == m["gesture"]
                 and m["start"] <= g["t"] <= m["motion_end"] + 0.5]
        assert len(match) == 1, (m, seen)
    assert len(seen) <= len(player.script)


def test_idle_player_loses(play_ninja):
    player = NinjaPlayer(style="idle")
    rules = play_ninja(player, seconds=60.0, seed=0)
    assert rules.phase == "lost" and rules.player_health == 0
    assert all(outcome == "hit" for _, _, outcome in _answers(rules))
    assert rules.opponent_health == rules.options.opponent_health


def test_wrong_dodge_is_punished(play_ninja):
    player = NinjaPlayer(style="wrong")
    rules = play_ninja(player, seconds=60.0, seed=1)
    wrong = [a for a in rules.attacks if a.outcome == "wrong_dodge"]
    assert wrong and all(a.answer is None and a.wrong for a in wrong)
    assert rules.player_health < rules.options.player_health
    assert not [a for a in rules.attacks if a.outcome == "dodged"]


def test_player_who_never_transfigures_never_starts_the_fight(play_ninja):
    rules = play_ninja(NinjaPlayer(style="still"), seconds=8.0, seed=0)
    assert rules.summary()["result"] == "not_started" and not rules.attacks


def test_same_seed_and_input_give_the_same_summary(play_ninja):
    a = play_ninja(NinjaPlayer(), seconds=30.0, seed=5, noise=0.02).summary()
    b = play_ninja(NinjaPlayer(), seconds=30.0, seed=5, noise=0.02).summary()
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)
