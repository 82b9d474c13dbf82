"""How far the player stands when the feet are not seen: the distance from the shape.

The floor point G comes from the silhouette's lowest pixel (feet on the floor). A
player who stands still in a room where the first frame's guess failed (a cup, a
wall of posters: GrabCut takes the furniture with the player, or finds no figure)
shows only what moves, often the arms: its lowest pixel is an elbow, and the ray
through it meets the floor metres behind the player, or never. The still body
under the arms is held back from learning (``BackgroundOptions.hold_below``) and
is "don't care" to the distance, so the templates can still say how far the
player is: at the right distance the arms, head and shoulders that move have the
size and height of a body's; nearer they look too small, farther too large.

:func:`shape_distance` resamples the silhouette into the window at a range of
floor distances along the line of sight under it and scores every leaf of the
tree at each (eq. 11, the level's runs, a few horizontal shifts); the distance of
the best is the answer. The distance is divided by the silhouette's own weight
(sum W) rather than by the window's area: the area normalization favours the
nearest distances, where the silhouette shrinks to a few pixels that any template
covers. One frame's answer is noisy (about 20%), so the tracker takes the median
over several frames (``SilhouetteOptions.shape_frames``). It is biased near: on
the tune captures of ``benchmarks/silhouette_rooms.py`` it read 0.72-1.05 of the
true distance (a template that covers a smaller-looking silhouette whole, its
legs in the "don't care" pixels, costs little); docs/silhouette.md, "Rooms".
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.trackers.silhouette.distance import distance_maps, score_runs_shifted
from bodyplay.trackers.silhouette.hierarchy import BodyTemplates
from bodyplay.trackers.silhouette.window import (
    ObservedWindow,
    WindowGeometry,
    anchor_point,
    sight_direction,
    window_at,
)

__all__ = ["shape_distance", "window_at_distance"]

_SHIFTS = np.array([-2, -1, 0, 1, 2], np.int64)


def window_at_distance(geometry: WindowGeometry, camera: Camera,
                       foreground: NDArray[np.uint8], unknown: NDArray[np.uint8],
                       scale: float, distance: float) -> ObservedWindow | None:
    """The window at the floor point ``distance`` metres away under the silhouette's
    thickest part (None when there is no silhouette or no floor under it)."""
    a = anchor_point(foreground)
    if a is None:
        return None
    direction = sight_direction(camera, (a[0] + 0.5) / scale - 0.5)
    if direction is None:
        return None
    g = camera.center + direction * distance
    g[1] = 0.0
    return window_at(geometry, camera, foreground, unknown, scale, g)


def shape_distance(body: BodyTemplates, geometry: WindowGeometry, camera: Camera,
                   foreground: NDArray[np.uint8], unknown: NDArray[np.uint8], scale: float,
                   near: float, far: float, steps: int = 16, level: int = 2,
                   beta: float = 5.0) -> float | None:
    """The floor distance (m, between ``near`` and ``far``, ``steps`` geometric steps)
    at which ``body``'s templates at tree ``level`` best fit the silhouette, with
    ``unknown`` pixels "don't care"; None without a silhouette or a floor under it."""
    if not np.asarray(foreground).any() or far <= near:
        return None
    n = len(body.runs[level])
    cand = np.repeat(np.arange(n, dtype=np.int64), len(_SHIFTS))
    sx = np.tile(_SHIFTS, n)
    sy = np.zeros_like(sx)
    best, best_d = np.inf, None
    for d in np.geomspace(near, far, steps):
        win = window_at_distance(geometry, camera, foreground, unknown, scale, float(d))
        if win is None:
            return None
        maps = distance_maps(win.foreground[level], win.unknown[level], beta=beta)
        if maps.base <= 0:  # nothing of the silhouette in the window
            continue
        score = float(score_runs_shifted(maps, body.runs[level], cand, sx, sy).min())
        score *= maps.area / maps.base
        if score < best:
            best, best_d = score, float(d)
    return best_d
