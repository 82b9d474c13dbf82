"""Specification of gesture precedence: ``inhibits`` in a definition (docs/gestures.md)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from bodyplay.body import JOINT_INDEX, Skeleton
from bodyplay.errors import BodyplayError, ConfigError
from bodyplay.gestures import GestureRecognizer, load_gestures, parse_gesture
from bodyplay.gestures.definitions import check_gesture_set

FPS = 30.0
LW, RW, HEAD = JOINT_INDEX["l_wrist"], JOINT_INDEX["r_wrist"], JOINT_INDEX["head"]

# A one-arm and a two-arm "up, then down" (the shape of hit and double_hit).
ONE = """
[gesture]
name = "one"
cooldown = 0.3
[[stage]]
name = "up"
when = ["above(r_wrist, head) > 0.0"]
[[stage]]
name = "down"
when = ["above(r_wrist, r_shoulder) < -0.4"]
within = 1.0
"""
BOTH = """
[gesture]
name = "both"
cooldown = 0.5
inhibits = ["one"]
[[stage]]
name = "up"
when = ["above(l_wrist, head) > 0.0", "above(r_wrist, head) > 0.0"]
[[stage]]
name = "down"
when = ["above(l_wrist, l_shoulder) < -0.4", "above(r_wrist, r_shoulder) < -0.4"]
within = 0.5
"""


def _defs(inhibit: bool = True):
    both = parse_gesture(BOTH, "both.toml")
    if not inhibit:
        both = dataclasses.replace(both, inhibits=())
    return [parse_gesture(ONE, "one.toml"), both]


@pytest.fixture(scope="module")
def standing() -> np.ndarray:
    sk = Skeleton.from_shape("m")
    rot = {"l_shoulder": (0, 0, -1.35), "r_shoulder": (0, 0, 1.35)}
    return sk.joint_positions(sk.pose(rotations=rot))


def _pose(standing: np.ndarray, left_up: bool = False, right_up: bool = False) -> np.ndarray:
    j = standing.copy()
    if left_up:
        j[LW, 1] = j[HEAD, 1] + 0.2
    if right_up:
        j[RW, 1] = j[HEAD, 1] + 0.2
    return j


def _run(rec: GestureRecognizer, frames: list[np.ndarray]) -> list[tuple[str, str, float]]:
    out = []
    for k, j in enumerate(frames):
        out += [(e.gesture, e.phase, round(e.t, 3)) for e in rec.update(k / FPS, j)]
    return out


def _performed(events: list[tuple[str, str, float]]) -> list[tuple[str, float]]:
    return [(g, t) for g, phase, t in events if phase == "performed"]


# ---- definitions ---------------------------------------------------------------------
def test_inhibits_is_read_into_the_definition():
    assert parse_gesture(BOTH, "both.toml").inhibits == ("one",)
    assert parse_gesture(ONE, "one.toml").inhibits == ()


def test_builtin_double_hit_inhibits_hit():
    (d,) = load_gestures("double_hit")
    assert d.inhibits == ("hit",)


def test_inhibiting_a_builtin_that_is_not_loaded_is_allowed():
    rec = GestureRecognizer(load_gestures("double_hit"))
    assert [d.name for d in rec.definitions] == ["double_hit"]


def test_inhibits_naming_an_unknown_gesture_is_a_config_error_naming_the_file_and_the_name(
        tmp_path: Path):
    f = tmp_path / "jab.toml"
    f.write_text(BOTH.replace('name = "both"', 'name = "jab"').replace('["one"]', '["hitt"]'))
    with pytest.raises(ConfigError, match="unknown gesture 'hitt'") as err:
        load_gestures([f, "hit"])
    assert str(f) in str(err.value) and "gesture.inhibits" in str(err.value)
    assert isinstance(err.value, BodyplayError)
    # The recognizer checks definitions that did not come through load_gestures too.
    with pytest.raises(ConfigError, match="both.toml: gesture.inhibits: unknown gesture 'one'"):
        GestureRecognizer([parse_gesture(BOTH, "both.toml")])


@pytest.mark.parametrize(
    ("value", "message"),
    [("3", "must be a list of gesture names"), ('["a b"]', "is not a gesture name"),
     ('["both"]', "cannot inhibit itself"), ('["one", "one"]', "names a gesture twice")],
)
def test_bad_inhibits_values_are_config_errors_naming_the_file(value: str, message: str):
    text = BOTH.replace('inhibits = ["one"]', f"inhibits = {value}")
    with pytest.raises(ConfigError, match=message) as err:
        parse_gesture(text, "both.toml")
    assert "both.toml: gesture.inhibits" in str(err.value)


def test_a_cycle_of_inhibitions_is_rejected():
    one = parse_gesture(ONE.replace("cooldown = 0.3", 'cooldown = 0.3\ninhibits = ["both"]'),
                        "one.toml")
    with pytest.raises(ConfigError, match="form a cycle"):
        check_gesture_set([one, parse_gesture(BOTH, "both.toml")])
    with pytest.raises(ConfigError, match="form a cycle"):
        GestureRecognizer([one, parse_gesture(BOTH, "both.toml")])


def test_gesture_set_is_settled_inhibitors_first_and_otherwise_in_the_given_order():
    defs = _defs() + load_gestures(["crouch"])
    assert [d.name for d in check_gesture_set(defs)] == ["both", "one", "crouch"]


# ---- the recognizer ------------------------------------------------------------------
def test_both_fire_on_a_two_arm_strike_without_precedence(standing: np.ndarray):
    frames = [standing] * 5 + [_pose(standing, True, True)] * 6 + [standing] * 5
    events = _run(GestureRecognizer(_defs(inhibit=False)), frames)
    assert sorted(g for g, _ in _performed(events)) == ["both", "one"]


def test_inhibitor_performed_cancels_the_inhibited_gesture_completed_in_the_same_frame(
        standing: np.ndarray):
    frames = [standing] * 5 + [_pose(standing, True, True)] * 6 + [standing] * 5
    events = _run(GestureRecognizer(_defs()), frames)
    assert _performed(events) == [("both", round(11 / FPS, 3))]
    assert ("one", "canceled", round(11 / FPS, 3)) in events
    # The inhibitor's performed comes before the cancellation it causes.
    assert events.index(("both", "performed", round(11 / FPS, 3))) < events.index(
        ("one", "canceled", round(11 / FPS, 3)))


def test_inhibited_gesture_completed_first_is_held_and_canceled_when_the_inhibitor_performs(
        standing: np.ndarray):
    # The right arm comes down 3 frames before the left: "one" completes at frame 11
    # while "both" waits for the left arm, which it gets at frame 14.
    frames = ([standing] * 5 + [_pose(standing, True, True)] * 6
              + [_pose(standing, left_up=True)] * 3 + [standing] * 5)
    rec = GestureRecognizer(_defs())
    events = _run(rec, frames[:12])
    assert _performed(events) == [] and rec.active == {"both": 0.5, "one": 1.0}
    events += _run_from(rec, frames, 12)
    assert _performed(events) == [("both", round(14 / FPS, 3))]
    assert ("one", "canceled", round(14 / FPS, 3)) in events


def _run_from(rec: GestureRecognizer, frames: list[np.ndarray], k0: int
              ) -> list[tuple[str, str, float]]:
    out = []
    for k in range(k0, len(frames)):
        out += [(e.gesture, e.phase, round(e.t, 3)) for e in rec.update(k / FPS, frames[k])]
    return out


def test_held_gesture_is_performed_when_its_inhibitor_is_canceled(standing: np.ndarray):
    # Both arms up, then only the right one comes down: "both" gives up 0.5 s (its
    # `within`) after its "up" stage, and only then is "one" performed (late, not lost).
    frames = ([standing] * 5 + [_pose(standing, True, True)] * 6
              + [_pose(standing, left_up=True)] * 30)
    events = _run(GestureRecognizer(_defs()), frames)
    performed = _performed(events)
    assert [g for g, _ in performed] == ["one"]
    canceled_both = next(t for g, phase, t in events if g == "both" and phase == "canceled")
    assert performed[0][1] == canceled_both
    assert canceled_both - 5 / FPS == pytest.approx(0.5, abs=1.5 / FPS)


def test_inhibited_gesture_alone_is_performed_in_the_same_frame_as_without_precedence(
        standing: np.ndarray):
    frames = [standing] * 5 + [_pose(standing, right_up=True)] * 6 + [standing] * 5
    with_p = _run(GestureRecognizer(_defs()), frames)
    without = _run(GestureRecognizer(_defs(inhibit=False)), frames)
    assert _performed(with_p) == _performed(without) == [("one", round(11 / FPS, 3))]


def test_inhibited_gesture_cannot_start_during_the_inhibitors_cooldown(standing: np.ndarray):
    # A two-arm strike, then the right arm straight up again 0.2 s later (inside the
    # 0.5 s cooldown of "both"): no "one"; a right-arm strike after the cooldown is one.
    strike = [_pose(standing, True, True)] * 6 + [standing] * 6
    again = [_pose(standing, right_up=True)] * 6 + [standing] * 6
    frames = [standing] * 5 + strike + again + [standing] * 10 + again
    events = _run(GestureRecognizer(_defs()), frames)
    assert [g for g, _ in _performed(events)] == ["both", "one"]
    assert _performed(events)[1][1] > 11 / FPS + 0.5


def test_held_gesture_ignores_its_own_timeout_while_it_waits(standing: np.ndarray):
    one = parse_gesture(ONE.replace("cooldown = 0.3", "cooldown = 0.3\ntimeout = 0.3"),
                        "one.toml")
    frames = ([standing] * 5 + [_pose(standing, True, True)] * 6
              + [_pose(standing, left_up=True)] * 30)
    events = _run(GestureRecognizer([one, parse_gesture(BOTH, "both.toml")]), frames)
    assert [g for g, _ in _performed(events)] == ["one"]
