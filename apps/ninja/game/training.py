"""The ninja's motions as a training clip for the silhouette tracker's hierarchy.

The paper built its game's pose hierarchy from the game's own motions (400,000
poses of three subjects performing the five motions, thinned to about 30,000).
:func:`ninja_training_clip` does the same with what we have: the five motions of
the gesture tables, each performed at three speeds with a side step either way,
written once as a BVH file; :func:`silhouette_options` adds it to the vendored CMU
clips the silhouette tracker's hierarchy is built from (its cache key includes the
clip's content, so the hierarchy is built once).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from bodyplay.body.skeleton import Skeleton
from bodyplay.testing import Timeline

__all__ = ["ninja_training_clip", "silhouette_options"]

_ORDER = ("transfigure", "crouch", "step_left", "hit", "step_right", "double_hit",
          "step_right", "crouch", "step_left", "hit", "double_hit")


def ninja_training_clip(folder: Path | None = None, fps: float = 30.0) -> Path:
    """Write (once) and return the BVH of the five motions at speeds 0.8, 1 and 1.25."""
    from bodyplay.motion.bvh import write_bvh

    folder = folder or Path.home() / ".cache" / "bodyplay"
    path = folder / "ninja_motions.bvh"
    if path.exists():
        return path
    folder.mkdir(parents=True, exist_ok=True)
    sk = Skeleton()
    tl = Timeline(sk, blend=0.15).hold("idle", 0.5)
    x = 0.0
    for speed in (0.8, 1.0, 1.25):
        for g in _ORDER:
            tl.gesture(g, start=tl.cursor + 0.3, speed=speed, at=(x, 0.0))
            x += 0.5 if g == "step_left" else -0.5 if g == "step_right" else 0.0
    times = np.arange(0.0, tl.duration, 1.0 / fps)
    return write_bvh(path, sk, tl.poses(times), fps)


def silhouette_options(folder: Path | None = None) -> Any:
    """Silhouette tracker options whose hierarchy also holds the ninja's motions."""
    from bodyplay.motion import list_builtin_clips
    from bodyplay.trackers.silhouette.options import HierarchyOptions, SilhouetteOptions

    clips = tuple(list_builtin_clips()) + (str(ninja_training_clip(folder)),)
    return SilhouetteOptions(hierarchy=HierarchyOptions(clips=clips))
