"""Placing database poses in the world: the step between retrieval and the 6-DOF fit.

Entries are stored relative to a canonical camera with their root's place and depth
in the normalized map; a camera's query puts the root on its ray at the depth that
makes the shirt as large as observed, turned as to the canonical camera. With
several cameras the root's depth is triangulated instead.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.rotations import matrix_to_rotvec, rotvec_to_matrix
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.database import BlendedPose, PoseDatabase, canonical_camera
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["DatabasePlacement"]

_RAY_GAP = 0.25
"""Metres: the cameras' rays through their blends' roots must pass this close to the
triangulated root (else the views disagree and the leading camera places it)."""


class DatabasePlacement:
    """Turns a camera view's database neighbours into world poses (one tracker's cameras)."""

    def __init__(self, database: PoseDatabase, cameras: tuple[Camera, ...]) -> None:
        self.database = database
        self.cameras = cameras
        self._canonical = canonical_camera()

    def place(self, view: CameraView, others: list[CameraView] | None = None
              ) -> NDArray[np.float64]:
        """Blend ``view``'s neighbours and place the blend in the world through its camera
        (see the module docstring); with ``others`` (the other cameras' views) the root
        moves along the ray to the depth where every view's ray through its own blend's
        root meets (within ``_RAY_GAP``), which a bow or a lean cannot fool.
        """
        b = self.database.blend(view.neighbours)  # type: ignore[arg-type]
        cam = self.cameras[view.index]
        s_img = view.query_scale * view.window.scale  # query px per image px
        uv = view.window.to_image((b.root_crop[None] - view.query_offset) / view.query_scale)
        f_ratio = cam.K[0, 0] / self._canonical.K[0, 0]
        depth = b.root_depth * f_ratio * s_img / b.crop_scale
        rays = np.concatenate([uv, np.ones((1, 1))], axis=1) @ np.linalg.inv(cam.K).T
        R_body = cam.R.T @ self._canonical.R @ rotvec_to_matrix(b.pose[None, 3:6])
        q = b.pose.copy()
        q[0:3] = ((rays * depth - cam.t) @ cam.R)[0]
        q[3:6] = matrix_to_rotvec(R_body)[0]
        if others:
            root = self._triangulate([view, *others], b)
            if root is not None:  # along the leading camera's ray, to the triangulated depth
                z0 = float(cam.world_to_camera(q[:3])[2])
                z1 = float(cam.world_to_camera(root)[2])
                if z0 > 0.3:
                    q[:3] = cam.center + (q[:3] - cam.center) * (z1 / z0)
        return q

    def _triangulate(self, views: list[CameraView], lead: BlendedPose
                     ) -> NDArray[np.float64] | None:
        """The point nearest to every view's ray through its blend's root, or None when
        the rays miss each other by more than ``_RAY_GAP`` or meet behind a camera."""
        centres, dirs = [], []
        for i, v in enumerate(views):
            b = lead if i == 0 else self.database.blend(v.neighbours)  # type: ignore[arg-type]
            cam = self.cameras[v.index]
            uv = v.window.to_image((b.root_crop - v.query_offset) / v.query_scale)
            d = cam.R.T @ (np.linalg.inv(cam.K) @ np.array([uv[0], uv[1], 1.0]))
            centres.append(cam.center)
            dirs.append(d / np.linalg.norm(d))
        A = np.zeros((3, 3))
        rhs = np.zeros(3)
        for c, d in zip(centres, dirs, strict=True):
            P = np.eye(3) - np.outer(d, d)
            A += P
            rhs += P @ c
        if np.linalg.cond(A) > 1e6:
            return None
        p = np.asarray(np.linalg.solve(A, rhs), dtype=np.float64)
        for c, d in zip(centres, dirs, strict=True):
            along = float((p - c) @ d)
            if along <= 0.3 or np.linalg.norm(p - c - along * d) > _RAY_GAP:
                return None
        return p
