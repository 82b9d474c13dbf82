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
