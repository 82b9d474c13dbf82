"""Checkerboard intrinsics of the real Pose2Sim rig agree with its Qualisys calibration.

Measured with benchmarks/calibration_pose2sim.py (docs/calibration.md): focal lengths
within 0.5 %, principal points within 50 px, k1 within 0.011, RMS about 0.2 px. The
tolerances below leave a margin over those figures.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bodyplay.capture import Board, Camera, calibrate_intrinsics, read_qualisys_calib

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "video" / "pose2sim_single"
CALIB = DATA / "calibration"
BOARD = Board(7, 4, 0.06)  # Config.toml: intrinsics_corners_nb = [4, 7], square 60 mm


@pytest.fixture(scope="module")
def qualisys() -> dict[str, Camera]:
    if not (CALIB / "Calib.qca.txt").is_file():
        pytest.skip(f"Pose2Sim data not found at {CALIB}")
    return {c.name: c for c in read_qualisys_calib(CALIB / "Calib.qca.txt")}


def test_qualisys_reader_gives_y_up_cameras_above_the_treadmill_looking_down(
    qualisys: dict[str, Camera],
) -> None:
    cams = list(qualisys.values())
    assert [c.name for c in cams] == ["cam01", "cam02", "cam03", "cam04"]
    # scene points of Config.toml (Qualisys Z-up metres) -> Y-up (old y, old z, old x)
    scene = np.array([[-2.0, 0.3, 0.0], [-2.0, -0.3, 0.0], [0.0, 0.3, 0.0], [0.0, -0.3, 0.0]])
    scene = scene[:, [1, 2, 0]]
    for cam in cams:
        assert (cam.width, cam.height) == (1088, 1920)
        assert 1.6 < cam.center[1] < 2.2
        assert cam.R[2, 1] < -0.3  # the optical axis points down
        assert np.all(cam.in_view(scene))


@pytest.mark.parametrize("name", ["cam01", "cam02", "cam03", "cam04"])
def test_checkerboard_intrinsics_agree_with_qualisys(qualisys: dict[str, Camera], name: str
                                                     ) -> None:
    files = sorted((CALIB / "intrinsics" / f"int_{name}_img").glob("*.jpg"))
    result = calibrate_intrinsics(files, BOARD, name)
    ours, ref = result.camera, qualisys[name]
    assert result.rms_px < 0.4 and len(result.used) >= 5
    assert (ours.width, ours.height) == (1088, 1920)
    np.testing.assert_allclose(np.diag(ours.K)[:2], np.diag(ref.K)[:2], rtol=0.01)
    assert np.hypot(*(ours.K[:2, 2] - ref.K[:2, 2])) < 70
    assert abs(ours.dist[0] - ref.dist[0]) < 0.02
