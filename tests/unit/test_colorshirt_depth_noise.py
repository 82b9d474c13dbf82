"""Specifications of one camera's depth-noise split (benchmarks/colorshirt_depth_noise.py)."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest


@pytest.fixture(scope="module")
def depth_noise(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_depth_noise.py")


def test_noise_splits_a_constant_bias_from_frame_to_frame_jitter(depth_noise) -> None:  # type: ignore[no-untyped-def]
    frames = np.arange(60)
    err = 20.0 + np.where(frames % 2 == 0, 3.0, -3.0)  # 20 cm far, +-3 cm each frame
    n = depth_noise.noise(frames, err)
    assert n["bias"] == pytest.approx(20.0)
    assert n["sd"] == pytest.approx(3.0)
    assert n["jitter"] == pytest.approx(6.0)  # every frame jumps by 6 cm
    assert n["drift"] == pytest.approx(6.0)  # 15 frames apart: opposite parity
    # a slow ramp: little jitter, the drift over 0.5 s is the ramp's travel
    ramp = depth_noise.noise(frames, frames.astype(float))
    assert ramp["jitter"] == pytest.approx(1.0) and ramp["drift"] == pytest.approx(15.0)


def test_noise_skips_frames_without_a_pose(depth_noise) -> None:  # type: ignore[no-untyped-def]
    frames = np.array([0, 1, 2, 10, 11])
    n = depth_noise.noise(frames, np.array([0.0, 1.0, 2.0, 50.0, 51.0]))
    assert n["frames"] == 5 and n["jitter"] == pytest.approx(1.0)  # the gap is no jump
    assert np.isnan(depth_noise.noise(frames[:0], np.zeros(0))["bias"])


def test_results_table_needs_rows_with_per_frame_depth(depth_noise, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "r.jsonl"
    row = {"tag": "t", "setting": "steady-1-view", "clip": "c", "half": "tune",
           "per_frame_depth": [[k, 10.0, 8.0 if k < 15 else 4.0, 12.0] for k in range(30)]}
    path.write_text(json.dumps(row) + "\n" + json.dumps({**row, "tag": "old"}) + "\n")
    lines = depth_noise.from_results(path, "t", [], "")
    # 10 cm off: within twice a std of 8 cm, not of 4 cm
    assert any("steady-1-view (tag t), reported root" in x and "honest 0.50" in x
               and "|bias| 10.0" in x for x in lines)
    assert any("depth filter's estimate" in x and "|bias| 12.0" in x for x in lines)
    with pytest.raises(SystemExit):
        depth_noise.from_results(path, "missing", [], "")
