"""Template silhouettes: the tracker's body rendered in the canonical window view.

Each pose is rendered twice with :func:`bodyplay.render.rasterize_ids` (batched
numba z-buffer): once from the canonical view of the origin, to find the pose's
anchor (the floor point under its torso at its lowest row, exactly as
:mod:`.window` finds it in camera images), then from the canonical view of that
anchor, at the three window sizes. The pelvis offset from the anchor is kept so a
matched template places the body in the world.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.mesh import body_mesh
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.render.idmap import rasterize_ids
from bodyplay.trackers.silhouette.distance import TemplateRuns, encode_runs
from bodyplay.trackers.silhouette.window import WindowGeometry, anchor_point, floor_point

__all__ = ["PART_NAMES", "RenderedTemplates", "node_part", "project_view", "render_templates"]

PART_NAMES = ("torso", "l_arm", "r_arm", "l_leg", "r_leg")
"""Body parts of the occlusion-aware dynamic model (eq. 14)."""


def node_part(name: str) -> int:
    """Which of :data:`PART_NAMES` a skeleton node belongs to."""
    for i, p in enumerate(("l_arm", "r_arm", "l_leg", "r_leg")):
        side, limb = p.split("_")
        group = ("clavicle", "shoulder", "elbow", "wrist", "hand") if limb == "arm" else (
            "hip", "knee", "ankle", "toe")
        if name.startswith(side + "_") and name.split("_", 1)[1] in group:
            return i + 1
    return 0


@dataclass(frozen=True, eq=False)
class RenderedTemplates:
    """Templates of a batch of poses: runs per level, anchor offsets, part pixels.

    ``offset``: (N, 3) pelvis minus anchor floor point (template frame, metres);
    ``part_pixels``: (N, 5) visible pixels of each part at level 3.
    """

    runs: tuple[TemplateRuns, ...]
    offset: NDArray[np.float64]
    part_pixels: NDArray[np.int64]


def project_view(verts: NDArray[np.float32], cam: Camera) -> NDArray[np.float32]:
    """Vertices (..., 3) in the world -> (..., 3) pixel x, pixel y and depth in ``cam``
    (no distortion: the window's views have none), as :func:`rasterize_ids` takes them."""
    pc = verts.astype(np.float64) @ cam.R.T + cam.t
    z = pc[..., 2]
    out = np.empty(verts.shape, np.float32)
    out[..., 0] = cam.K[0, 0] * pc[..., 0] / z + cam.K[0, 2]
    out[..., 1] = cam.K[1, 1] * pc[..., 1] / z + cam.K[1, 2]
    out[..., 2] = z
    return out


def render_templates(skeleton: Skeleton, poses: NDArray[np.float64], geometry: WindowGeometry,
                     levels: tuple[int, ...] = (0, 1, 2), chunk: int = 500,
                     progress: object = None) -> RenderedTemplates:
    """Render ``poses`` (pelvis over the origin) of ``skeleton``'s body mesh as window
    templates at ``levels``; ``progress`` is a tqdm bar advanced per pose."""
    mesh = body_mesh(skeleton)
    dom = mesh.dominant_node()
    part_of_node = np.array([node_part(n) for n in NODE_NAMES], np.uint8)
    face_ids = (part_of_node[dom[mesh.faces[:, 0]]] + 1).astype(np.uint8)
    views = [geometry.template_view(lv) for lv in range(3)]
    n = len(poses)
    masks: dict[int, list[TemplateRuns]] = {lv: [] for lv in levels}
    offset = np.zeros((n, 3))
    part_px = np.zeros((n, len(PART_NAMES)), np.int64)
    for s in range(0, n, chunk):
        q = np.asarray(poses[s : s + chunk], np.float64)
        verts = mesh.pose(skeleton, q)
        w3, h3 = geometry.size(2)
        first = rasterize_ids(project_view(verts, views[2]), mesh.faces, face_ids, w3, h3,
                              cull_backfaces=True)
        anchors = np.zeros((len(q), 3))
        for i in range(len(q)):
            a = anchor_point(first[i])
            g = floor_point(views[2], *a) if a is not None else None
            anchors[i] = g if g is not None else 0.0
            anchors[i, 1] = 0.0
        offset[s : s + len(q)] = q[:, 0:3] - anchors
        shifted = verts - anchors[:, None, :].astype(np.float32)
        for lv in levels:
            w, h = geometry.size(lv)
            ids = rasterize_ids(project_view(shifted, views[lv]), mesh.faces, face_ids, w, h,
                                cull_backfaces=True)
            if lv == 2:
                for p in range(len(PART_NAMES)):
                    part_px[s : s + len(q), p] = np.count_nonzero(ids == p + 1, axis=(1, 2))
            masks[lv].append(encode_runs(ids))
        if progress is not None:
            progress.update(len(q))  # type: ignore[attr-defined]
    runs = tuple(_concat(masks[lv]) for lv in levels)
    return RenderedTemplates(runs, offset, part_px)


def _concat(parts: list[TemplateRuns]) -> TemplateRuns:
    offs = [np.zeros(1, np.int64)]
    base = 0
    for p in parts:
        offs.append(p.offsets[1:] + base)
        base += int(p.offsets[-1])
    return TemplateRuns(parts[0].width, parts[0].height, np.concatenate(offs),
                        np.concatenate([p.row for p in parts]),
                        np.concatenate([p.x0 for p in parts]),
                        np.concatenate([p.x1 for p in parts]))
