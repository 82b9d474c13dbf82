"""The single-camera silhouette tracker (papers/single-camera-silhouette-mocap.txt).

Build one with :func:`create_silhouette_tracker`; it implements
:class:`bodyplay.trackers.base.Tracker`. Modules: :mod:`.background` (per-pixel
Gaussian background model that learns with the player in view), :mod:`.window`
(the floor point and the matching window), :mod:`.distance` (normalized
core-weighted XOR distance), :mod:`.poses` (training poses, the 5-degree rule),
:mod:`.templates` (rendering), :mod:`.hierarchy` (Algorithm 1, the cached tree),
:mod:`.treefilter` (tree-based Bayesian filter), :mod:`.tracker` (the pipeline).
See docs/silhouette.md.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.background import BackgroundModel, Silhouette
from bodyplay.trackers.silhouette.hierarchy import ShapeTree, load_or_build_tree
from bodyplay.trackers.silhouette.options import (
    BackgroundOptions,
    HierarchyOptions,
    SilhouetteOptions,
)
from bodyplay.trackers.silhouette.tracker import SilhouetteTracker

__all__ = [
    "BackgroundModel",
    "BackgroundOptions",
    "HierarchyOptions",
    "ShapeTree",
    "Silhouette",
    "SilhouetteOptions",
    "SilhouetteTracker",
    "create_silhouette_tracker",
    "load_or_build_tree",
]


def create_silhouette_tracker(
    options: SilhouetteOptions | None = None,
    cameras: Sequence[Camera] = (),
    tree: ShapeTree | None = None,
    progress: bool | None = None,
) -> SilhouetteTracker:
    """Validate the options and the camera and build a ready tracker.

    Of several cameras the first is used (and the first frame of every frame set).
    The shape hierarchy is loaded from the cache unless ``tree`` is given. On first
    use it is built (about two minutes from the vendored clips): a WARNING on the
    ``bodyplay.silhouette`` logger says so and where it is cached, and a tqdm bar
    shows the progress on stderr (``progress``; by default when stderr is a terminal).
    """
    opts = options or SilhouetteOptions()
    cams = tuple(cameras)
    if not cams:
        raise ConfigError("the silhouette tracker needs one calibrated camera, got none")
    cams = cams[:1]  # one camera (the paper's setup): the first of a rig
    if tree is None:
        cache = Path(opts.cache) if opts.cache else None
        tree = load_or_build_tree(opts.hierarchy, cache, progress=progress)
    if opts.body != "auto" and opts.body not in tree.bodies:
        raise ConfigError(f"body {opts.body!r} has no templates in the hierarchy; choose "
                          f"'auto' or one of {', '.join(tree.bodies)}")
    return SilhouetteTracker(opts, cams, tree)
