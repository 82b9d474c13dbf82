"""Patch anchors: a patch seen both in the render and in a camera's classified crop;
its rendered centroid, attached to its bone, is pulled to the observed centroid."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.ik import KinematicSolver, PatchAnchors
from bodyplay.trackers.colorshirt.options import ColorShirtOptions
from bodyplay.trackers.colorshirt.prediction import PoseRenderer, RenderedPose
from bodyplay.trackers.colorshirt.views import WHITE_PATCHES, CameraView

__all__ = ["Observed", "patch_anchors"]

Observed = tuple[NDArray[np.int64], NDArray[np.float64]]
"""One camera's observed patches: pixel count and crop centroid per patch id."""


def patch_anchors(renderer: PoseRenderer, solver: KinematicSolver, cameras: Sequence[Camera],
                  q: NDArray[np.float64], views: Sequence[CameraView],
                  rendered: Sequence[RenderedPose], observed: Sequence[Observed],
                  centroid_std: float, options: ColorShirtOptions) -> PatchAnchors:
    """Anchors for the patches seen both in the render and in the image, all cameras;
    ``centroid_std`` (relative to the shirt's size) grows for partly hidden patches
    and by ``white_std_scale`` for the white ones."""
    o = options
    nodes, locals_, cams, targets, sigmas, pids = [], [], [], [], [], []
    for view, rend, (counts, cents) in zip(views, rendered, observed, strict=True):
        cam = cameras[view.index]
        min_px = max(3, int(o.min_patch_fraction * view.ids.size))
        pats = np.nonzero((rend.stats.count >= min_px) & (counts >= min_px))[0]
        pats = pats[pats > 0]
        if not len(pats):
            continue
        world = renderer.anchor_world(rend, cam, view.window, pats)
        node = renderer.patch_node[pats]
        nodes.append(node)
        locals_.append(solver.attach(q, node, world))
        cams.append(np.full(len(pats), view.index))
        targets.append(view.window.to_image(cents[pats]))
        size_px = view.shirt_scale / view.window.scale
        sig = centroid_std * size_px * np.sqrt(
            np.maximum(1.0, rend.stats.count[pats].max() / (4.0 * counts[pats]))
        )
        sigmas.append(np.where(WHITE_PATCHES[pats], sig * o.white_std_scale, sig))
        pids.append(pats)
    if not nodes:
        return PatchAnchors.empty()
    return PatchAnchors(np.concatenate(nodes), np.concatenate(locals_),
                        np.concatenate(cams).astype(np.int64), np.concatenate(targets),
                        np.concatenate(sigmas), np.concatenate(pids).astype(np.int64))
