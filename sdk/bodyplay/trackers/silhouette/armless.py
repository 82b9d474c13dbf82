"""The leaf's body without its arms: the torso, head and legs the per-arm refinement
scores arms against (an addition to the paper).

The per-arm refinement (:mod:`.armfit`) scores each candidate arm on the silhouette
the body does not already explain. The leaf's template less the capsules of its
arms is not that body: a leaf whose arm hangs in front of the torso leaves a hole
over torso silhouette when the arm is cut out, and its own arm, filling the hole
again, is credited with the torso it hid, so a raised arm the silhouette shows
loses to it (docs/silhouette-history.md, sections 16 and 17). Here the leaf's pose
is rendered again from the tracker's body mesh with the arms' faces left out
(those whose first vertex is skinned mostly to a shoulder, elbow, wrist or hand:
the upper arm onwards; the clavicles' faces, the top of the shoulders, stay with
the torso), from the very view, anchor and rasterizer the tree's templates were
rendered with (:mod:`.templates`). Where the torso lies behind the arm it is the
torso's, whatever the arm does; only what the torso, head and legs do not cover is
the arms' to win or lose.

One render of one mesh at 320x240 a frame (a few ms of CPU).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.mesh import body_mesh
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.render.idmap import rasterize_ids
from bodyplay.trackers.silhouette.templates import project_view
from bodyplay.trackers.silhouette.window import WindowGeometry

__all__ = ["ARM_NODES", "ArmlessBody"]

ARM_NODES: tuple[str, ...] = tuple(f"{s}_{n}" for s in "lr"
                                   for n in ("shoulder", "elbow", "wrist", "hand"))
"""Skeleton nodes whose faces are the arms' (the clavicles' stay with the torso)."""


class ArmlessBody:
    """Renders one body preset's poses without their arms as window masks at one
    level, exactly as its templates were rendered with them."""

    def __init__(self, skeleton: Skeleton, geometry: WindowGeometry, level: int = 2) -> None:
        self.skeleton = skeleton
        self.mesh = body_mesh(skeleton)
        dom = self.mesh.dominant_node()[self.mesh.faces[:, 0]]
        arm = np.isin(dom, [NODE_NAMES.index(n) for n in ARM_NODES])
        self.faces = np.ascontiguousarray(self.mesh.faces[~arm])
        self.view = geometry.template_view(level)
        self.size = geometry.size(level)

    def mask(self, pose: NDArray[np.float64], anchor: NDArray[np.float64]) -> NDArray[np.uint8]:
        """The body of ``pose`` without its arms, standing with ``anchor`` (its floor
        point under the torso, what the templates subtract) at the template origin:
        (height, width) uint8, 1 on the body."""
        verts = self.mesh.pose(self.skeleton, np.asarray(pose, np.float64)[None])[0]
        verts = verts - np.asarray(anchor, np.float32)
        w, h = self.size
        ids = rasterize_ids(project_view(verts, self.view), self.faces, None, w, h,
                            cull_backfaces=True)
        return (ids > 0).astype(np.uint8)
