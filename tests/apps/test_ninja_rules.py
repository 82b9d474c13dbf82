"""The ninja fight's rules on their own: gestures and times in, state and summary out."""

from __future__ import annotations

import pytest
from apps.ninja.game import NinjaRules, ninja_options

from bodyplay.errors import ConfigError


def _fight(seed: int = 0, **opts: float) -> NinjaRules:
    rules = NinjaRules(ninja_options(**opts), seed=seed)
    rules.on_gesture("transfigure", 1.0)
    return rules


def _first_attack(rules: NinjaRules) -> tuple[str, float, float]:
    rules.update(rules.started_t + rules.options.first_attack + 0.01)
    a = rules.current_attack
    assert a is not None
    return a.kind, a.telegraph_t, a.strike_t


def test_the_fight_starts_only_with_transfigure():
    rules = NinjaRules(seed=0)
    rules.on_gesture("hit", 0.5)
    rules.update(10.0)
    assert rules.phase == "waiting" and not rules.attacks and not rules.rings
    rules.on_gesture("transfigure", 10.5)
    assert rules.phase == "fight" and rules.started_t == 10.5


def test_right_dodge_avoids_the_attack_and_wrong_dodge_is_punished():
    for right in (True, False):
        rules = _fight(seed=3)
        kind, t0, strike = _first_attack(rules)
        if kind == "high":
            gesture = "crouch" if right else "step_left"
        else:
            gesture = "step_right" if right else "crouch"
        rules.on_gesture(gesture, t0 + 0.8)
        rules.update(strike + 1.0)
        a = rules.attacks[0]
        assert a.outcome == ("dodged" if right else "wrong_dodge")
        assert rules.player_health == rules.options.player_health - (0 if right else 34.0)


def test_a_dodge_after_the_grace_period_is_too_late():
    rules = _fight(seed=1)
    kind, _, strike = _first_attack(rules)
    rules.update(strike + rules.options.grace + 0.01)
    rules.on_gesture("crouch" if kind == "high" else "step_left", strike + 0.4)
    assert rules.attacks[0].outcome == "hit"


def test_fire_ring_flies_then_hurts_the_opponent():
    rules = _fight(ring_flight=0.5)
    rules.on_gesture("hit", 1.5)
    rules.update(1.9)
    assert rules.opponent_health == rules.options.opponent_health
    assert 0.7 < rules.rings[0].progress(1.9) < 0.9
    rules.update(2.01)
    assert rules.opponent_health == rules.options.opponent_health - rules.options.ring_damage
    assert rules.hits[-1]["by"] == "player" and rules.hits[-1]["t"] == pytest.approx(2.0)


def test_double_hit_is_stronger_and_cools_down():
    rules = _fight(double_cooldown=4.0, first_attack=30.0)
    rules.on_gesture("double_hit", 2.0)
    rules.on_gesture("double_hit", 3.0)
    rules.update(6.5)
    assert len(rules.rings) == 1 and rules.rejected[0]["gesture"] == "double_hit"
    assert rules.opponent_health == rules.options.opponent_health - rules.options.double_damage
    rules.on_gesture("double_hit", 6.1)
    assert len(rules.rings) == 2


def test_opponent_health_at_zero_wins_and_player_health_at_zero_loses():
    rules = _fight(opponent_health=20.0, first_attack=30.0)
    rules.on_gesture("hit", 2.0)
    rules.update(5.0)
    assert rules.phase == "won" and rules.summary()["result"] == "won"
    rules = _fight(player_health=30.0)
    rules.update(20.0)
    assert rules.phase == "lost" and rules.hits[0]["by"] == "opponent"


def test_the_time_limit_ends_the_fight_as_lost():
    rules = _fight(time_limit=5.0, attack_damage=1.0)
    rules.update(7.0)
    assert rules.phase == "lost" and rules.ended_t == pytest.approx(6.0)


def test_same_seed_same_attacks_different_seed_different_attacks():
    def attacks(seed: int) -> list[tuple[str, float]]:
        rules = _fight(seed=seed, attack_damage=1.0)
        rules.update(60.0)
        return [(a.kind, a.telegraph_t) for a in rules.attacks]

    assert attacks(7) == attacks(7)
    assert any(attacks(s) != attacks(7) for s in range(3))


def test_summary_lists_gestures_attacks_hits_and_result():
    rules = _fight(seed=2)
    kind, t0, strike = _first_attack(rules)
    rules.on_gesture("crouch" if kind == "high" else "step_left", t0 + 0.5)
    rules.on_gesture("hit", strike + 1.0)
    rules.update(strike + 2.0)
    s = rules.summary()
    assert [g["gesture"] for g in s["gestures"]][:1] == ["transfigure"]
    assert s["attacks"][0]["outcome"] == "dodged" and s["attacks"][0]["kind"] == kind
    assert s["hits"][0]["kind"] == "ring"
    assert s["result"] == "unfinished"


def test_bad_options_and_times_raise_config_errors():
    with pytest.raises(ConfigError, match="telegraph"):
        ninja_options(telegraph=0.0)
    with pytest.raises(ConfigError, match="attack_gap"):
        ninja_options(attack_gap=(3.0, 1.0))
    with pytest.raises(ConfigError, match="unexpected"):
        ninja_options(speed=2.0)
    with pytest.raises(ConfigError, match="finite"):
        NinjaRules().update(float("nan"))
