"""Specifications of importing Pose2Sim and Sports2D recordings as capture folders."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bodyplay.capture import read_calib
from bodyplay.capture.camera import Camera
from bodyplay.capture.external import import_capture, read_toml_calib, scale_about_center
from bodyplay.capture.sources import CaptureFolderSource
from bodyplay.errors import CalibrationError, CaptureError


def test_scaling_about_the_centre_maps_the_image_centre_to_the_new_centre() -> None:
    cam = Camera.from_fov("c", 1088, 1920, 40.0)
    scaled = scale_about_center(cam, 1080, 1920, 1080 / 1088)
    p = np.array([[0.3, -0.2, 4.0]])
    uv = cam.project(p)[0]
    uv2 = scaled.project(p)[0]
    expected = (uv - [1088 / 2, 1920 / 2]) * (1080 / 1088) + [1080 / 2, 1920 / 2]
    np.testing.assert_allclose(uv2, expected, atol=1e-6)


def test_toml_calibration_with_a_missing_key_names_the_table(tmp_path: Path) -> None:
    f = tmp_path / "Calib.toml"
    f.write_text('[cam]\nname = "cam"\nsize = [640, 480]\n')
    with pytest.raises(CalibrationError, match=r"\[cam\]"):
        read_toml_calib(f)


def test_import_rejects_a_folder_without_calibration(tmp_path: Path) -> None:
    with pytest.raises(CaptureError, match="found neither"):
        import_capture(tmp_path, tmp_path / "out")


def test_pose2sim_project_becomes_a_readable_capture_folder(
    shared_data: Path, tmp_path: Path
) -> None:
    out = import_capture(shared_data / "video" / "pose2sim_single", tmp_path / "cap",
                         cameras=["cam01", "cam03"])
    cams = read_calib(out)
    assert [c.name for c in cams] == ["cam0", "cam1"]
    assert (cams[0].width, cams[0].height) == (1080, 1920)  # fitted to the 1080-wide video
    assert (cams[1].width, cams[1].height) == (1088, 1920)
    with CaptureFolderSource(out) as src:
        first = next(iter(src))
    assert len(first) == 2 and first.frames[0].image.shape == (1920, 1080, 3)


def test_sports2d_demo_becomes_a_capture_folder(shared_data: Path, tmp_path: Path) -> None:
    out = import_capture(shared_data / "video" / "sports2d", tmp_path / "cap")
    (cam,) = read_calib(out)
    assert (cam.width, cam.height) == (1768, 994)


def test_sports2d_import_gives_a_y_up_world_with_the_floor_at_y_0(
    shared_data: Path, tmp_path: Path
) -> None:
    out = import_capture(shared_data / "video" / "sports2d", tmp_path / "cap")
    (cam,) = read_calib(out)
    centre = -cam.R.T @ cam.t
    assert 1.0 < centre[1] < 2.5  # the camera at about eye height above the floor
    down = cam.R[1]  # the image's down direction in the world
    assert down[1] < -0.99  # image down is world -Y: Y is up
    # the floor 10 m in front of the camera (where the walker's feet are) is in the
    # lower part of the image, near its bottom edge, and above it the horizon
    floor = centre + 10.0 * cam.R[2] * np.array([1.0, 0.0, 1.0])
    floor[1] = 0.0
    u, v = cam.project(floor[None])[0]
    assert 0 <= u < cam.width and 0.85 * cam.height < v < cam.height


def test_toml_calibration_axis_swap_keeps_the_projection(tmp_path: Path) -> None:
    f = tmp_path / "Calib.toml"
    f.write_text('[c]\nname = "c"\nsize = [640, 480]\n'
                 "matrix = [[500.0, 0.0, 320.0], [0.0, 500.0, 240.0], [0.0, 0.0, 1.0]]\n"
                 "distortions = [0.0, 0.0, 0.0, 0.0]\nrotation = [1.2, 1.2, -1.2]\n"
                 "translation = [-0.5, 1.5, 6.0]\n")
    (zup,) = read_toml_calib(f, y_up=False)
    (yup,) = read_toml_calib(f)
    p_zup = np.array([[0.3, -0.2, 1.1]])
    p_yup = p_zup[:, [1, 2, 0]]  # (old y, old z, old x)
    np.testing.assert_allclose(yup.project(p_yup), zup.project(p_zup), atol=1e-9)
