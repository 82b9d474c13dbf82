"""Specifications of the silhouette tracker in rooms where the first frame's guess fails:
the still body is held back from learning and the distance comes from the shape."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.background import BackgroundModel
from bodyplay.trackers.silhouette.options import BackgroundOptions, SilhouetteOptions
from bodyplay.trackers.silhouette.shapestart import shape_distance, window_at_distance
from bodyplay.trackers.silhouette.window import WindowGeometry, _homography


def _room(seed: int) -> np.ndarray:
    base = np.random.default_rng(seed).integers(40, 220, (60, 80, 3)).astype(np.uint8)
    return np.kron(base, np.ones((8, 8, 1), np.uint8))  # 480x640 blocky texture


def _arms_over_still_legs(model: BackgroundModel, frames: int) -> None:
    """A player whose legs stand still under arms that swing: no guess, no pose."""
    room = _room(5)
    for i in range(frames):
        img = room.copy()
        img[260:420, 290:350] = (30, 30, 60)  # still legs
        y = 150 + 6 * (i % 10)
        img[y : y + 30, 200:440] = (200, 60, 40)  # arms swinging up and down
        model.apply(img)


def test_background_holds_still_pixels_under_what_moves_until_a_pose() -> None:
    # no first guess: the still legs under the moving arms are not learned as the
    # room while the tracker has no pose (they would vanish from the silhouette)
    model = BackgroundModel(BackgroundOptions(bootstrap=False))
    _arms_over_still_legs(model, 30)
    assert model.known is not None and model.held is not None
    legs = (slice(135, 205), slice(150, 170))  # working resolution (320x240)
    assert not model.known[legs].any()
    assert model.held[legs].all()
    assert model.known[:, :60].all()  # the room far from the player is learned


def test_background_learns_still_legs_when_holding_below_is_off() -> None:
    model = BackgroundModel(BackgroundOptions(bootstrap=False, hold_below=False))
    _arms_over_still_legs(model, 30)
    assert model.known is not None and model.known[135:205, 150:170].mean() > 0.9


def _camera() -> Camera:
    R, t = look_at((0.0, 1.2, 3.0), (0.0, 0.9, 0.0))
    return Camera.from_fov("cam0", 640, 480, 60.0, R, t)


def _shown(tree, cam: Camera, leaf: int, distance: float) -> tuple[np.ndarray, float]:  # type: ignore[no-untyped-def]
    """A leaf's template seen by ``cam`` with its floor point ``distance`` m away, in
    the working image (320x240)."""
    geometry = WindowGeometry()
    scale = 0.5
    direction = np.array([0.0, 0.0, -1.0])
    g = cam.center + direction * distance
    g[1] = 0.0
    view = geometry.view(cam.center, g, 2)
    mask = tree.bodies["m"].runs[2].masks(np.array([leaf]))[0]
    H = _homography(cam, view, scale)
    img = cv2.warpPerspective(mask * np.uint8(255), np.linalg.inv(H), (320, 240)) >= 128
    return img.astype(np.uint8), scale


@pytest.mark.parametrize("distance", [2.2, 3.0, 3.8])
def test_shape_distance_finds_how_far_a_player_stands_from_the_upper_body_alone(
        silhouette_tree, distance: float) -> None:  # type: ignore[no-untyped-def]
    cam = _camera()
    tree = silhouette_tree
    leaf = tree.num_leaves // 3
    shown, scale = _shown(tree, cam, leaf, distance)
    rows = np.flatnonzero(shown.any(axis=1))
    cut = rows[0] + (rows[-1] - rows[0]) // 2
    upper = shown.copy()
    upper[cut:] = 0  # the still legs are not seen ...
    unknown = np.zeros_like(shown)
    unknown[cut:, :] = 1  # ... they are "don't care" below what moves
    d = shape_distance(tree.bodies["m"], WindowGeometry(), cam, upper, unknown, scale,
                       1.0, 6.0, steps=24)
    assert d is not None and abs(d - distance) < 0.2 * distance
    win = window_at_distance(WindowGeometry(), cam, upper, unknown, scale, d)
    assert win is not None and win.distance == pytest.approx(d)


def test_shape_distance_needs_a_silhouette() -> None:
    empty = np.zeros((240, 320), np.uint8)
    assert window_at_distance(WindowGeometry(), _camera(), empty, empty, 0.5, 2.0) is None


def test_options_reject_a_negative_shape_start() -> None:
    with pytest.raises(ConfigError, match="shape_frames"):
        SilhouetteOptions(shape_frames=-1)
