"""Specifications of the silhouette room check's fresh draws (benchmarks/silhouette_rooms.py)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import pytest


@pytest.fixture(scope="module")
def rooms(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/silhouette_rooms.py", with_neighbours=True)


def test_draw_zero_keeps_the_captures_every_room_figure_was_measured_on(rooms) -> None:  # type: ignore[no-untyped-def]
    first = rooms.plan("report", 2)
    assert first == rooms.plan("report", 2, draw=0)
    assert first[0] == ("astronaut", "13_29", 2.0)  # the first report clip from 2 s
    assert all(start >= 0 for _, _, start in first)


def test_a_fresh_draw_shows_each_room_other_clips_from_their_own_part(rooms) -> None:  # type: ignore[no-untyped-def]
    for half in ("tune", "report"):
        base, fresh = rooms.plan(half, 2), rooms.plan(half, 2, draw=1)
        assert [r for r, _, _ in fresh] == [r for r, _, _ in base]  # the same rooms
        assert all(start == -1.0 for _, _, start in fresh)  # capture() picks the part
        # the rooms' clips move along the list (Bandai clips only when ../shared has them)
        if len({c for _, c, _ in base}) > 1:
            assert [c for _, c, _ in fresh] != [c for _, c, _ in base]


def test_a_negative_draw_is_refused_with_what_it_takes(rooms, capsys) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit) as stop:
        rooms.main(["--list", "--draw", "-1"])
    assert stop.value.code == 2
    assert "--draw must be 0" in capsys.readouterr().err
