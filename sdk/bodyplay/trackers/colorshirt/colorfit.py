"""Labeled shirt pixels for fitting the color model: synthetic renders (labeled by the
actor's rasterized patch ids) or a user's scribble masks over photos of a real shirt.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import SHIRT_COLORS, patch_color_index
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt.colors import ColorModel
from bodyplay.trackers.colorshirt.whitebalance import white_balance_from_ids

__all__ = ["synthetic_color_samples", "scribble_labels", "scribble_samples"]


def synthetic_color_samples(
    n_poses: int = 24,
    backgrounds: Sequence[str] = ("brick", "grass", "gravel"),
    lighting: str = "steady",
    seed: int = 0,
    erode: int = 2,
    per_image: int = 4000,
    reference: ColorModel | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """RGB pixels (N, 3) and color labels (N,) of the shirt in synthetic renders:
    ``n_poses`` poses over ``backgrounds``, patches eroded by ``erode`` px, at most
    ``per_image`` pixels an image, each image white-balanced onto ``reference`` if given.
    """
    from bodyplay.motion import sample_poses
    from bodyplay.render.idmap import render_idmaps
    from bodyplay.synth.camera import SyntheticCamera
    from bodyplay.synth.options import make_synthetic_camera_options

    if n_poses < 1 or not backgrounds:
        raise ConfigError("need at least one pose and one background")
    rng = np.random.default_rng(seed)
    cidx = patch_color_index()
    kernel = np.ones((2 * erode + 1, 2 * erode + 1), np.uint8)
    px_all: list[NDArray[np.float64]] = []
    lab_all: list[NDArray[np.int64]] = []
    per_bg = int(np.ceil(n_poses / len(backgrounds)))
    for b, bg in enumerate(backgrounds):
        opts = make_synthetic_camera_options(
            cameras=1, background=bg, lighting=lighting, seed=seed + b, max_subframes=1
        )
        with SyntheticCamera(opts) as cam:
            poses = sample_poses(cam.skeleton, per_bg, rng, yaw_range=(-1.3, 1.3))
            poses[:, 0:3] = cam.skeleton.rest_pose()[0:3]
            for sf in cam.render(poses):
                verts = cam.actor.mesh.pose(cam.skeleton, sf.pose)
                ids = render_idmaps(verts[None], cam.actor.mesh.faces, cam.actor.mesh.face_part,
                                    cam.cameras[0])[0]
                lab = np.full(ids.shape, -1, np.int64)
                for p in np.unique(ids):
                    if p == 0:
                        continue
                    inner = cv2.erode((ids == p).astype(np.uint8), kernel) > 0
                    lab[inner] = cidx[p]
                img = sf.frames[0].image
                px = img.reshape(-1, 3).astype(np.float64)
                if reference is not None:
                    W = white_balance_from_ids(img, np.where(lab >= 0, lab + 1, 0).astype(np.uint8),
                                               reference, min_colors=4)
                    if W is None:
                        continue
                    px = px @ W.T
                sel = np.flatnonzero(lab.ravel() >= 0)
                if len(sel) > per_image:
                    sel = rng.choice(sel, per_image, replace=False)
                px_all.append(px[sel])
                lab_all.append(lab.ravel()[sel])
    return np.concatenate(px_all), np.concatenate(lab_all)


def scribble_labels(mask_rgb: NDArray[np.uint8], tolerance: float = 60.0) -> NDArray[np.int64]:
    """(H, W) color index of each scribbled pixel of an RGB scribble mask, -1 elsewhere.

    A scribble pixel carries the nominal sRGB of its shirt color; pixels farther
    than ``tolerance`` from every color (black background included) are unlabeled.
    """
    ref = np.array([c.rgb for c in SHIRT_COLORS], np.float64)
    flat = mask_rgb.reshape(-1, 3).astype(np.float64)
    d = np.linalg.norm(flat[:, None, :] - ref[None], axis=-1)
    k = d.argmin(axis=1)
    k[d.min(axis=1) > tolerance] = -1
    k[flat.sum(axis=1) < 30] = -1
    return k.reshape(mask_rgb.shape[:2])


def _read_rgb(path: Path) -> NDArray[np.uint8]:
    img = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if img is None:
        raise ConfigError(f"{path}: cannot read this image")
    return np.asarray(cv2.cvtColor(img, cv2.COLOR_BGR2RGB), dtype=np.uint8)


def scribble_samples(
    pairs: Sequence[tuple[str | Path, str | Path]],
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Pixels and labels from (photo, scribble mask) file pairs of a white-balanced shirt."""
    px_all: list[NDArray[np.float64]] = []
    lab_all: list[NDArray[np.int64]] = []
    for photo, mask in pairs:
        img = _read_rgb(Path(photo))
        lab = scribble_labels(_read_rgb(Path(mask)))
        if lab.shape != img.shape[:2]:
            raise ConfigError(f"{mask}: scribble mask size differs from {photo}")
        on = lab.ravel() >= 0
        px_all.append(img.reshape(-1, 3)[on].astype(np.float64))
        lab_all.append(lab.ravel()[on])
    if not px_all:
        raise ConfigError("give at least one photo:mask pair")
    return np.concatenate(px_all), np.concatenate(lab_all)
