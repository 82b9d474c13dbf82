"""Placing database poses in the world: the step between retrieval and the 6-DOF fit.

Database entries are stored relative to a canonical camera (:func:`canonical_camera`)
together with where their root falls in the normalized 40x40 map and how deep it
is. A camera's query tells where the shirt is in that camera's image and how large:
that fixes each entry's root in the world (the ray through the root, at the depth
that makes the shirt as large as observed) and its orientation (same relation to
the camera as to the canonical one).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.rotations import matrix_to_rotvec, rotvec_to_matrix
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.database import (
    PoseDatabase,
    blend_poses,
    canonical_camera,
    mismatch,
    render_normalized,
)
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["DatabasePlacement"]


class DatabasePlacement:
    """Turns a camera view's database neighbours into world poses (one tracker's cameras)."""

    def __init__(self, database: PoseDatabase, cameras: tuple[Camera, ...]) -> None:
        self.database = database
        self.cameras = cameras
        self._canonical = canonical_camera()

    def place_entries(self, view: CameraView, pose: NDArray[np.float64],
                      root_crop: NDArray[np.float64], root_depth: NDArray[np.float64],
                      crop_scale: NDArray[np.float64]) -> NDArray[np.float64]:
        """Place database poses (C, D), relative to the canonical camera, in the world.

        The root goes where the entry's root falls in ``view``'s normalized query, at
        the depth that makes the shirt as large as observed; the orientation keeps
        its relation to the camera.
        """
        cam = self.cameras[view.index]
        s_img = view.query_scale * view.window.scale  # query px per image px
        uv = view.window.to_image((root_crop - view.query_offset) / view.query_scale)
        f_ratio = cam.K[0, 0] / self._canonical.K[0, 0]
        depth = root_depth * f_ratio * s_img / crop_scale
        rays = np.concatenate([uv, np.ones((len(uv), 1))], axis=1) @ np.linalg.inv(cam.K).T
        roots = (rays * depth[:, None] - cam.t) @ cam.R
        R_body = cam.R.T @ self._canonical.R @ rotvec_to_matrix(pose[:, 3:6])
        q = pose.copy()
        q[:, 0:3] = roots
        q[:, 3:6] = matrix_to_rotvec(R_body)
        return q

    def place(self, view: CameraView) -> NDArray[np.float64]:
        """Blend ``view``'s neighbours and place the blend in the world through its camera."""
        b = self.database.blend(view.neighbours)  # type: ignore[arg-type]
        return self.place_entries(view, b.pose[None], b.root_crop[None],
                                  np.array([b.root_depth]), np.array([b.crop_scale]))[0]

    def multiview_blend(self, views: list[CameraView], skeleton: Skeleton
                        ) -> NDArray[np.float64]:
        """With several cameras, rank every camera's neighbours by their mismatch in all.

        Each candidate is placed through the camera that proposed it, rendered (with
        ``skeleton``) as a normalized 40x40 map in every camera and scored by its
        summed mismatch against the cameras' queries; the best ``neighbours`` are
        blended in world coordinates. A pose that only one view explains (an arm
        hidden in it) loses.
        """
        db = self.database
        seen: set[int] = set()
        placed = []
        for v in views:
            idx = np.array([i for i in v.neighbours.index if i not in seen])  # type: ignore[attr-defined]
            if not len(idx):
                continue
            seen.update(int(i) for i in idx)
            placed.append(self.place_entries(
                v, db.poses[idx].astype(np.float64), db.root_crop[idx].astype(np.float64),
                db.root_depth[idx].astype(np.float64), db.crop_scale[idx].astype(np.float64)))
        Q = np.concatenate(placed)
        total = np.zeros(len(Q))
        for v in views:
            assert v.query is not None
            maps = render_normalized(skeleton, Q, self.cameras[v.index], db.options)
            total += mismatch(maps, v.query[None]) / float(v.query.size)
        total /= len(views)
        best = np.argsort(total, kind="stable")[: db.options.neighbours]
        return blend_poses(Q[best], 1.0 / (total[best] + 0.02))
