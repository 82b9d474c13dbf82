"""Specifications of the validation set's fresh draws (benchmarks/colorshirt_validation.py)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import pytest


@pytest.fixture(scope="module")
def validation(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_validation.py", with_neighbours=True)


def test_draw_zero_keeps_the_captures_every_figure_was_measured_on(validation) -> None:  # type: ignore[no-untyped-def]
    assert validation.start_fraction(0) == 0.5
    assert [validation.body_for(i) for i in range(4)] == list(validation.BODIES)
    assert validation.room_for("steady", 1) == validation.STEADY_ROOMS[1]
    assert validation.room_for("mixed", 4) == validation.CLUTTER_ROOMS[1]


def test_a_fresh_draw_moves_every_clip_to_another_part_room_and_body(validation) -> None:  # type: ignore[no-untyped-def]
    for draw in (1, 2):
        assert 0.0 <= validation.start_fraction(draw) < 1.0
        assert abs(validation.start_fraction(draw) - 0.5) > 0.1
        for i in range(23):
            assert validation.body_for(i, draw) != validation.body_for(i)
            for lighting in ("steady", "switch", "mixed"):
                assert validation.room_for(lighting, i, draw) != validation.room_for(lighting, i)


def test_a_fresh_draw_generates_other_cluttered_rooms(validation, tmp_path) -> None:  # type: ignore[no-untyped-def]
    import cv2

    first = cv2.imread(validation.room_path(tmp_path, "fruit"))
    fresh = cv2.imread(validation.room_path(tmp_path, "fruit", draw=1))
    assert first.shape == fresh.shape
    assert (first != fresh).mean() > 0.5
    assert validation.room_path(tmp_path, "brick", draw=1) == "brick"  # a shipped photo


def test_validation_rejects_a_negative_draw(validation, capsys) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit):
        validation.main(["--draw", "-1", "--list"])
    assert "--draw must be 0" in capsys.readouterr().err
