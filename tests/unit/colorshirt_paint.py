"""Painting synthetic shirt images with numpy for the color-shirt unit tests."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import SHIRT_COLORS
from bodyplay.capture.camera import Camera, look_at


def webcam_rig(n: int = 2) -> tuple[Camera, ...]:
    """The first ``n`` of two 640x480 webcams 2.8 m in front of a standing person."""
    out = []
    for i, x in enumerate((-0.6, 0.7)[:n]):
        R, t = look_at((x, 1.35, 2.8), (0, 1.15, 0))
        out.append(Camera.from_fov(f"cam{i}", 640, 480, 60, R, t))
    return tuple(out)


def clutter(h: int, w: int, rng: np.random.Generator) -> NDArray[np.uint8]:
    """A dull, smoothly varying background (greys and browns, like a room)."""
    base = rng.uniform(60, 140, size=(h // 40 + 2, w // 40 + 2, 1))
    tint = np.array([1.0, 0.95, 0.85])
    img = np.kron(base, np.ones((40, 40, 1)))[:h, :w] * tint
    img += rng.normal(0, 4, size=img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def paint_shirt(
    image: NDArray[np.uint8],
    x0: int,
    y0: int,
    cell: int,
    rng: np.random.Generator,
    gains: tuple[float, float, float] = (1.0, 1.0, 1.0),
    noise: float = 4.0,
) -> NDArray[np.int64]:
    """Paint a 4 x 5 grid of the ten shirt colors (each twice) with shading and noise.

    Returns the (H, W) color-index label image (-1 off the shirt).
    """
    h, w = image.shape[:2]
    labels = np.full((h, w), -1, np.int64)
    order = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 4, 9, 0, 6, 2, 8, 1, 7, 3, 5]
    g = np.asarray(gains)
    for i, k in enumerate(order):
        r, c = divmod(i, 4)
        ys, xs = y0 + r * cell, x0 + c * cell
        shade = rng.uniform(0.8, 1.05)
        col = np.asarray(SHIRT_COLORS[k].rgb, float) * shade * g
        patch = col + rng.normal(0, noise, size=(cell, cell, 3))
        image[ys : ys + cell, xs : xs + cell] = np.clip(patch, 0, 255).astype(np.uint8)
        labels[ys : ys + cell, xs : xs + cell] = k
    return labels
