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
