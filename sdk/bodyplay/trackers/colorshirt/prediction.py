"""Predicted id maps: the generic mesh rendered in a camera's crop (for the patch
anchors, the pose-assisted reclassification and the white balance's refit)."""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.mesh import body_mesh
from bodyplay.body.shirt import NUM_COLORS, NUM_PATCHES, PATCHES, patch_color_index
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.render.idmap import project_vertices, rasterize_ids

__all__ = ["CropWindow", "RenderedPose", "PoseRenderer", "PatchStats", "patch_stats"]

@dataclass(frozen=True)
class CropWindow:
    """A working crop of a camera image: image pixel ``p`` is crop pixel ``(p - x0y0) * scale``."""

    x0: float
    y0: float
    scale: float
    width: int
    height: int

    def to_crop(self, uv: NDArray[np.float64]) -> NDArray[np.float64]:
        """Image pixel coordinates (..., 2) to crop pixel coordinates."""
        return (np.asarray(uv, float) - (self.x0, self.y0)) * self.scale

    def to_image(self, uv: NDArray[np.float64]) -> NDArray[np.float64]:
        """Crop pixel coordinates (..., 2) to image pixel coordinates."""
        return np.asarray(uv, float) / self.scale + (self.x0, self.y0)


@dataclass(frozen=True, eq=False)
class PatchStats:
    """Per patch id 0..20: pixel count and centroid (crop pixels) in an id map."""

    count: NDArray[np.int64]
    centroid: NDArray[np.float64]


@numba.njit(cache=True, nogil=True)
def _patch_sums(ids: NDArray[np.uint8], depth: NDArray[np.float32], use_depth: bool,
                n: int) -> NDArray[np.float64]:  # pragma: no cover - compiled
    out = np.zeros((n, 4))  # count, sum x, sum y, sum depth
    h, w = ids.shape
    for y in range(h):
        for x in range(w):
            k = ids[y, x]
            if k >= n:
                continue
            out[k, 0] += 1.0
            out[k, 1] += x
            out[k, 2] += y
            if use_depth:
                d = depth[y, x]
                if np.isfinite(d):
                    out[k, 3] += d
    return out


def patch_stats(ids: NDArray[np.uint8], depth: NDArray[np.float32] | None = None
                ) -> tuple[PatchStats, NDArray[np.float64] | None]:
    """Counts and centroids of every id in a patch map (and mean depths if given)."""
    n = NUM_PATCHES + 1
    ids = np.ascontiguousarray(ids, dtype=np.uint8)
    d = (np.ascontiguousarray(depth, dtype=np.float32) if depth is not None
         else np.zeros((1, 1), np.float32))
    sums = _patch_sums(ids, d, depth is not None, n)
    count = sums[:, 0].astype(np.int64)
    safe = np.maximum(count, 1)[:, None]
    c = sums[:, 1:3] / safe
    mean_depth = sums[:, 3] / safe[:, 0] if depth is not None else None
    return PatchStats(count, c), mean_depth


@dataclass(frozen=True, eq=False)
class RenderedPose:
    """A pose rendered in a crop: patch ids (0 = none), depth, and per-patch stats."""

    patches: NDArray[np.uint8]
    depth: NDArray[np.float32]
    stats: PatchStats
    mean_depth: NDArray[np.float64]

    def color_ids(self) -> NDArray[np.uint8]:
        """The rendered map as color ids (0 = none, k + 1 = color k)."""
        lut = np.zeros(256, np.uint8)
        cidx = patch_color_index()
        lut[1 : NUM_PATCHES + 1] = cidx[1:] + 1
        return lut[self.patches]


class PoseRenderer:
    """Renders the generic body mesh of a skeleton into camera crops."""

    def __init__(self, skeleton: Skeleton) -> None:
        self.skeleton = skeleton
        self.mesh = body_mesh(skeleton)
        self.patch_node = np.full(NUM_PATCHES + 1, -1, np.int64)
        for p in PATCHES:
            self.patch_node[p.id] = skeleton.node_index(p.bone)
        cidx = patch_color_index()
        self._last: tuple[NDArray[np.float64], NDArray[np.float32]] | None = None
        self.color_patches: list[list[int]] = [
            [p for p in range(1, NUM_PATCHES + 1) if cidx[p] == k] for k in range(NUM_COLORS)
        ]

    def vertices(self, q: NDArray[np.float64]) -> NDArray[np.float32]:
        """Skinned mesh vertices (V, 3) at pose ``q`` (read-only; the last pose's kept)."""
        last = self._last
        if last is not None and np.array_equal(last[0], q):
            return last[1]
        verts = self.mesh.pose(self.skeleton, q)
        verts.flags.writeable = False
        self._last = (np.array(q, np.float64), verts)
        return verts

    def render(self, verts: NDArray[np.float32], camera: Camera, window: CropWindow
               ) -> RenderedPose:
        """Patch ids and depth of posed vertices seen by ``camera`` in ``window``."""
        uvz = project_vertices(verts, camera)
        uvz[:, 0] = (uvz[:, 0] - window.x0) * window.scale
        uvz[:, 1] = (uvz[:, 1] - window.y0) * window.scale
        ids, depth = rasterize_ids(uvz, self.mesh.faces, self.mesh.face_part, window.width,
                                   window.height, return_depth=True)
        stats, mean_depth = patch_stats(ids, depth)
        assert mean_depth is not None
        return RenderedPose(ids, depth, stats, mean_depth)

    def silhouette(self, verts: NDArray[np.float32], camera: Camera, window: CropWindow
                   ) -> NDArray[np.uint8]:
        """1 where posed vertices seen by ``camera`` cover a pixel of ``window`` (any
        face, skin included; where :meth:`render` has a finite depth), else 0."""
        uvz = project_vertices(verts, camera)
        uvz[:, 0] = (uvz[:, 0] - window.x0) * window.scale
        uvz[:, 1] = (uvz[:, 1] - window.y0) * window.scale
        return rasterize_ids(uvz, self.mesh.faces, None, window.width, window.height)

    def anchor_world(self, rendered: RenderedPose, camera: Camera, window: CropWindow,
                     patches: NDArray[np.int64]) -> NDArray[np.float64]:
        """(A, 3) world points that project on the rendered centroids of ``patches``."""
        uv = window.to_image(rendered.stats.centroid[patches])
        z = rendered.mean_depth[patches]
        Kinv = np.linalg.inv(camera.K)
        rays = np.concatenate([uv, np.ones((len(patches), 1))], axis=1) @ Kinv.T
        pc = rays * z[:, None]
        return (pc - camera.t) @ camera.R

    def patch_distances(self, rendered: RenderedPose, min_pixels: int
                        ) -> tuple[NDArray[np.float32], NDArray[np.uint8], NDArray[np.int64]]:
        """The step-3 prior's distances (for :meth:`.colors.ColorModel.classify_near`):
        (M, H, W) distance to each patch rendered on at least ``min_pixels`` pixels,
        with those patches' ids and colors."""
        patch = [p for k, pats in enumerate(self.color_patches) for p in pats
                 if rendered.stats.count[p] >= min_pixels]
        cidx = patch_color_index()
        h, w = rendered.patches.shape
        dists = np.empty((len(patch), h, w), np.float32)
        for j, p in enumerate(patch):
            src = np.not_equal(rendered.patches, p).view(np.uint8)  # 0 on the patch
            out = cv2.distanceTransform(src, cv2.DIST_L2, 3, dst=dists[j])
            if out.ctypes.data != dists[j].ctypes.data:  # not written in place
                dists[j] = out
        return (dists, np.array(patch, np.uint8),
                np.array([cidx[p] for p in patch], np.int64))
