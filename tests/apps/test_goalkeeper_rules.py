"""Specifications of the goalkeeper's pure parts and its command line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from apps.goalkeeper.__main__ import main
from apps.goalkeeper.game import Goal, GoalkeeperOptions, part_group, plan_round

from bodyplay.errors import ConfigError


def test_every_planned_shot_reaches_its_target_inside_the_goal() -> None:
    goal = Goal()
    for shot in plan_round(np.random.default_rng(1), 30, goal):
        T = shot.flight_time(goal)
        x, y, z = shot.position(goal, T)
        assert (x, y) == pytest.approx(shot.target, abs=1e-9)
        assert z == pytest.approx(goal.line_z)
        assert abs(x) < goal.width / 2 and 0 < y < goal.height


def test_plan_is_a_function_of_the_seed() -> None:
    a = plan_round(np.random.default_rng(3), 10)
    b = plan_round(np.random.default_rng(3), 10)
    c = plan_round(np.random.default_rng(4), 10)
    assert a == b and a != c


def test_bad_round_options_raise_config_error() -> None:
    with pytest.raises(ConfigError, match="shots"):
        GoalkeeperOptions(shots=0)
    with pytest.raises(ConfigError, match="window"):
        GoalkeeperOptions(window=5.0)


def test_body_parts_map_to_the_groups_of_the_summary() -> None:
    assert [part_group(p) for p in ("l_hand", "r_forearm", "l_upper_arm", "torso", "head",
                                    "r_shin")] == ["hand", "arm", "arm", "body", "head", "leg"]


def test_missing_webcam_exits_2_naming_the_virtual_default(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["--input", "97", "--headless", "--out", str(tmp_path), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2
    assert "webcam 97" in err and "--input virtual" in err
    assert "Traceback" not in err
