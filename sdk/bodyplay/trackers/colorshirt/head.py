"""Where the head is: a cue from the background plate for the joint the shirt misses.

The head has no patch, but above the collar it is the only foreground:
:func:`find_head` looks in the plate's foreground near where the fit predicts the
head for a disk of the head's projected size. Beyond the paper; the foreground is
the empty-room plate's, else the room plate's where another camera's view tells
the room (:mod:`.cues`); without either the head follows the blend.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

__all__ = ["HeadPoint", "find_head", "HEAD_RADIUS"]

HEAD_RADIUS = 0.095
"""Radius (m) of the disk a head projects to, for a body of 1.75 m (scaled by height)."""


@dataclass(frozen=True)
class HeadPoint:
    """The head's centre found in one image (full-resolution pixels) and its radius."""

    u: float
    v: float
    radius: float
    fill: float
    """Share of the disk that is foreground (1: a whole head)."""


def find_head(
    fg: NDArray[np.bool_],
    downscale: int,
    head: NDArray[np.float64],
    neck: NDArray[np.float64],
    radius: float,
    reach: float = 2.0,
    cut: float = 0.45,
    min_fill: float = 0.5,
) -> HeadPoint | None:
    """The centre of the head-sized disk of foreground nearest the predicted head.

    ``fg`` is the plate-resolution foreground mask, ``head`` and ``neck`` the
    predicted head and neck joints in full-resolution pixels, ``radius`` the head's
    projected radius there (pixels). Only pixels beyond ``cut`` of the way from the
    neck to the head count (the shirt's collar and the throat are excluded); the
    disk's centre is searched within ``reach`` radii of the prediction, then set to
    the centroid of the foreground inside it (two mean-shift steps). None when the
    best disk is less than ``min_fill`` foreground.
    """
    s = float(downscale)
    h, w = fg.shape
    r = radius / s
    if not (np.all(np.isfinite(head)) and np.all(np.isfinite(neck))) or r < 2.0:
        return None
    hx, hy = head / s
    nx, ny = neck / s
    axis = np.array([hx - nx, hy - ny])
    length = float(np.hypot(*axis))
    if length < 1.0:
        return None
    axis /= length
    pad = reach * r + r + 1
    x0, x1 = max(0, int(hx - pad)), min(w, int(np.ceil(hx + pad)))
    y0, y1 = max(0, int(hy - pad)), min(h, int(np.ceil(hy + pad)))
    if x1 - x0 < 2 * r or y1 - y0 < 2 * r:
        return None
    roi = fg[y0:y1, x0:x1]
    yy, xx = np.mgrid[y0:y1, x0:x1]
    along = (xx - nx) * axis[0] + (yy - ny) * axis[1]
    cand = roi & (along > cut * length)
    k = int(np.ceil(r))
    ky, kx = np.mgrid[-k: k + 1, -k: k + 1]
    disk = ((kx * kx + ky * ky) <= r * r).astype(np.float32)
    area = float(disk.sum())
    score = cv2.filter2D(cand.astype(np.float32), -1, disk, borderType=cv2.BORDER_CONSTANT) / area
    near = (xx - hx) ** 2 + (yy - hy) ** 2 <= (reach * r) ** 2
    score = np.where(near, score, -1.0)
    iy, ix = np.unravel_index(int(np.argmax(score)), score.shape)
    fill = float(score[iy, ix])
    if fill < min_fill:
        return None
    cx, cy = float(ix + x0), float(iy + y0)
    for _ in range(2):
        inside = cand & ((xx - cx) ** 2 + (yy - cy) ** 2 <= r * r)
        if not inside.any():
            return None
        cx, cy = float(xx[inside].mean()), float(yy[inside].mean())
    return HeadPoint((cx + 0.5) * s, (cy + 0.5) * s, radius, fill)
