"""Checkerboard calibration on rendered boards with known cameras, and the CLI."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from bodyplay.capture import Board, Camera, calibrate_rig, find_board_corners, read_calib
from bodyplay.capture.camera import look_at
from bodyplay.cli import main
from bodyplay.errors import CalibrationError, ConfigError

BOARD = Board(7, 4, 0.06)
S = 40  # texture pixels per square


def board_texture(board: Board) -> np.ndarray:
    """White sheet with the checkerboard; the outer square at corner 0 is black."""
    tex = np.full(((board.rows + 3) * S, (board.cols + 3) * S), 255, np.uint8)
    for j in range(board.rows + 1):
        for i in range(board.cols + 1):
            if (i + j) % 2 == 0:
                y, x = (j + 1) * S, (i + 1) * S
                tex[y : y + S, x : x + S] = 0
    return tex


def render(cam: Camera, R_bc: np.ndarray, t_bc: np.ndarray, board: Board = BOARD) -> np.ndarray:
    """The board (board->camera pose R_bc, t_bc) as a BGR image from camera ``cam``."""
    k = board.square / S
    o = (2 * S - 0.5) * k  # texel centres: the board edge at texel 2S lies at 2S - 0.5
    A = np.array([[k, 0, -o], [0, k, -o], [0, 0, 1]])
    H = cam.K @ np.column_stack([R_bc[:, 0], R_bc[:, 1], t_bc]) @ A
    img = cv2.warpPerspective(board_texture(board), H, (cam.width, cam.height),
                              flags=cv2.INTER_AREA, borderValue=110)
    return cv2.cvtColor(img, cv2.COLOR_GRAY2BGR)


def random_views(cam: Camera, n: int, rng: np.random.Generator) -> list[np.ndarray]:
    views = []
    for _ in range(n):
        R, _ = cv2.Rodrigues(rng.uniform(-0.5, 0.5, 3) + [0, 0, rng.uniform(-0.3, 0.3)])
        centre = np.array([rng.uniform(-0.1, 0.1), rng.uniform(-0.08, 0.08), rng.uniform(0.7, 1.0)])
        views.append(render(cam, R, centre - R @ BOARD.center))
    return views


def floor_view(cam: Camera) -> np.ndarray:
    """The board lying on the floor, centred at the world origin, x along X, y along Z."""
    B = np.column_stack([[1.0, 0, 0], [0, 0, 1.0], [0, -1.0, 0]])
    return render(cam, cam.R @ B, cam.R @ (-B @ BOARD.center) + cam.t)


def rig() -> list[Camera]:
    cams = []
    for name, eye in (("left", (-0.5, 1.3, 1.4)), ("back", (0.3, 1.4, -1.5))):
        R, t = look_at(eye, (0, 0, 0))
        K = np.array([[560.0, 0, 322], [0, 560, 236], [0, 0, 1]])
        cams.append(Camera(name, 640, 480, K, R, t))
    return cams


@pytest.mark.parametrize("method", ["classic", "sb"])
@pytest.mark.parametrize("angle", [0.0, 1.2, math.pi, 4.0])
def test_corners_are_ordered_from_the_black_corner_whatever_the_board_rotation(
    method: str, angle: float
) -> None:
    cam = Camera.from_fov("c", 640, 480, 60)
    R = cv2.Rodrigues(np.array([0.5, 0.0, 0.0]))[0] @ cv2.Rodrigues(np.array([0.0, 0.0, angle]))[0]
    t = np.array([0, 0, 0.9]) - R @ BOARD.center
    found = find_board_corners(render(cam, R, t), BOARD, method=method)  # type: ignore[arg-type]
    assert found is not None
    expected = cam.project((BOARD.object_points() @ R.T) + t, distort=False)
    assert np.abs(found.reshape(-1, 2) - expected).max() < 0.5  # a wrong order is >30 px off


def test_rig_calibration_recovers_known_cameras_and_floor_frame() -> None:
    rng = np.random.default_rng(3)
    truth = rig()
    sets = [[floor_view(c), *random_views(c, 6, rng)] for c in truth]
    result = calibrate_rig(sets, BOARD, [c.name for c in truth], board_pose="floor")
    for got, want, intr in zip(result.cameras, truth, result.intrinsics, strict=True):
        assert intr.rms_px < 0.3
        assert got.K[0, 0] == pytest.approx(560, rel=0.01)
        assert np.linalg.norm(got.center - want.center) < 0.02  # metres
        angle = math.degrees(math.acos(np.clip((np.trace(got.R @ want.R.T) - 1) / 2, -1, 1)))
        assert angle < 0.5
    assert all(e < 0.3 for e in result.extrinsic_rms_px)


def test_wall_board_needs_its_height() -> None:
    with pytest.raises(ConfigError, match="board-height"):
        calibrate_rig([[np.zeros((10, 10, 3), np.uint8)]], BOARD, board_pose="wall")


def test_too_few_detections_is_a_calibration_error() -> None:
    blank = np.full((480, 640, 3), 128, np.uint8)
    with pytest.raises(CalibrationError, match="found in 0 of 3"):
        calibrate_rig([[blank] * 3], BOARD, board_pose="none")


def test_board_spec_is_validated() -> None:
    assert Board.parse("9x6", 0.025).size == (9, 6)
    with pytest.raises(ConfigError, match="COLSxROWS"):
        Board.parse("nine", 0.025)
    with pytest.raises(ConfigError, match="metres"):
        Board.parse("9x6", 25)


def test_calibrate_cli_writes_calib_json(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rng = np.random.default_rng(5)
    cam = rig()[0]
    folder = tmp_path / "cam0"
    folder.mkdir()
    for i, img in enumerate([floor_view(cam), *random_views(cam, 5, rng)]):
        cv2.imwrite(str(folder / f"{i:02d}.png"), img)
    out = tmp_path / "calib.json"
    code = main(["calibrate", "--images", str(folder / "*.png"), "--board", "7x4", "--square",
                 "0.06", "--camera-name", "webcam", "--out", str(out), "--json"])
    assert code == 0
    report = json.loads(capsys.readouterr().out)
    assert report["cameras"][0]["rms_px"] < 0.3
    (got,) = read_calib(out)
    assert got.name == "webcam" and np.linalg.norm(got.center - cam.center) < 0.02
    assert main(["calibrate", "--images", str(tmp_path / "none*.png"), "--board", "7x4",
                 "--square", "0.06", "--out", str(out)]) == 2


def test_undistort_maps_take_a_distorted_pixel_back_to_the_pinhole_projection() -> None:
    R, t = look_at((0.5, 1.3, 2.8), (0.0, 1.0, 0.0))
    cam = Camera.from_fov("cam0", 640, 480, 60.0, R, t)
    assert cam.undistort_maps() is None  # nothing to undo
    bent = Camera(cam.name, cam.width, cam.height, cam.K, cam.R, cam.t,
                  np.array([-0.2, 0.05, 0.0, 0.0, 0.0]))
    maps = bent.undistort_maps()
    assert maps is not None and maps[0].shape == (480, 640)
    point = np.array([[0.6, 1.7, 0.2]])  # near the image's corner, where the lens bends most
    ideal = bent.project(point, distort=False)[0]
    seen = bent.project(point)[0]
    assert np.linalg.norm(ideal - seen) > 3.0
    u, v = int(round(ideal[0])), int(round(ideal[1]))
    assert np.hypot(maps[0][v, u] - seen[0], maps[1][v, u] - seen[1]) < 1.0
