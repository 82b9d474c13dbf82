"""A scripted player performing named gestures triggers the built-in recognizer."""

from __future__ import annotations

import pytest

from bodyplay.events import GestureEvent
from bodyplay.testing import Timeline, scripted_session


def test_scripted_raise_squat_and_jump_are_performed_for_the_builtin_gestures() -> None:
    recognizer_mod = pytest.importorskip("bodyplay.gestures.recognizer")
    script = (Timeline().hold("idle", 1.0).gesture("raise_both_hands").gesture("squat")
              .gesture("jump").hold("idle", 1.0))
    s = scripted_session(script, fps=30.0, gestures=recognizer_mod.GestureRecognizer())
    performed: list[GestureEvent] = []
    s.subscribe("gesture", lambda e: performed.append(e) if e.phase == "performed" else None)
    s.run()
    names = [e.gesture for e in performed]
    assert "raise_arms" in names and "crouch" in names and "jump" in names
    assert names.index("raise_arms") < names.index("crouch") < names.index("jump")


def _performed_ninja(script: Timeline) -> list[str]:
    from bodyplay.gestures import GestureRecognizer, load_gestures

    rec = GestureRecognizer(load_gestures(["transfigure", "crouch", "step_left", "step_right",
                                           "hit", "double_hit"]))
    s = scripted_session(script, fps=30.0, gestures=rec)
    performed: list[str] = []
    s.subscribe("gesture", lambda e: performed.append(e.gesture) if e.phase == "performed"
                else None)
    s.run()
    return performed


@pytest.mark.parametrize("speed", [0.8, 1.0, 1.25])
def test_a_hit_swung_at_any_pace_is_a_hit(speed: float) -> None:
    script = Timeline().hold("idle", 1.0).gesture("hit", speed=speed).hold("idle", 1.0)
    assert _performed_ninja(script) == ["hit"]


@pytest.mark.parametrize("speed", [0.8, 1.0, 1.25])
def test_a_right_hand_raised_and_lowered_again_is_no_hit(speed: float) -> None:
    # The hand stays over the head (~0.7 s at speed 1.25, longer slower); a hit's swing
    # comes back under the head within 0.6 s of rising over it.
    script = (Timeline().hold("idle", 1.0).gesture("raise_right_hand", speed=speed)
              .hold("idle", 1.0))
    assert _performed_ninja(script) == []


@pytest.mark.parametrize("speed", [0.8, 1.25])
def test_a_double_hit_is_reported_once_as_a_double_hit(speed: float) -> None:
    script = Timeline().hold("idle", 1.0).gesture("double_hit", speed=speed).hold("idle", 1.0)
    assert _performed_ninja(script) == ["double_hit"]
