"""The body preset of the silhouette tracker, chosen while it tracks.

Until the choice, a tree filter runs per preset (the tracker owns them). Each frame,
every preset's MAP leaf gives two readings: its distance to the silhouette (eq. 11),
and, with ``body_cue="stature"``, how far the head top of its template lies from the
observed one (:func:`.stature.stature_reading`, corrected by the mesh's shortfall
against the preset's stature). The presets whose median head-top offset is within
``stature_tolerance`` metres of the best are candidates, and the one of smallest mean
distance among them is the body: the distance alone favoured the large presets and
differs by a few percent between them. docs/silhouette.md, "Body size".
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.mesh import body_mesh
from bodyplay.body.shapes import body_shape
from bodyplay.body.skeleton import Skeleton
from bodyplay.trackers.silhouette.hierarchy import ShapeTree
from bodyplay.trackers.silhouette.options import SilhouetteOptions
from bodyplay.trackers.silhouette.stature import stature_reading
from bodyplay.trackers.silhouette.window import WindowGeometry

__all__ = ["BodyChoice"]


class BodyChoice:
    """The readings of every preset in ``names`` and the preset chosen (``chosen``:
    given when the body is fixed, else None until the readings choose it)."""

    def __init__(self, names: list[str], tree: ShapeTree, geometry: WindowGeometry,
                 options: SilhouetteOptions, chosen: str | None = None) -> None:
        self.tree = tree
        self.geometry = geometry
        self.options = options
        self.chosen = chosen
        self.scores: dict[str, list[float]] = {b: [] for b in names}
        self.tops: dict[str, list[float]] = {b: [] for b in names}
        self._short: dict[str, float] = {}

    def clear(self) -> None:
        """Drop the readings so far (the player moved for the first time: until then
        the silhouette was only the first frame's colour guess)."""
        for b in self.scores:
            self.scores[b].clear()
            self.tops[b].clear()

    @property
    def frames(self) -> int:
        """Frames read since the last :meth:`clear`."""
        return len(next(iter(self.scores.values())))

    def add(self, body: str, distance: float, observed: NDArray[np.uint8], leaf: int,
            shift: tuple[int, int]) -> None:
        """One frame's readings of ``body``: its MAP leaf ``leaf``'s distance, and where
        the leaf's level-3 template, moved by ``shift``, puts the head top against the
        ``observed`` window silhouette."""
        self.scores[body].append(distance)
        o = self.options
        if o.body_cue == "stature":
            mask = self.tree.bodies[body].runs[2].masks(np.array([leaf]))[0]
            wide = o.shoulder_width / self.geometry.mpp(2)
            read = stature_reading(observed, mask, shift, wide, o.head_gap)
            if read is not None:  # the mesh's shortfall: its head top is short
                self.tops[body].append(read[0] - (self._shortfall(body) if read[1] else 0.0))

    def _shortfall(self, body: str) -> float:
        """How far (level-3 window pixels) the top of the body's template mesh, standing,
        lies below the preset's stature: the head top is compared with the player's
        stature, which the presets are named by, not with the mesh's."""
        if body not in self._short:
            top = float(body_mesh(Skeleton.from_shape(body)).rest_vertices[:, 1].max())
            self._short[body] = (body_shape(body).height - top) / self.geometry.mpp(2)
        return self._short[body]

    def best(self) -> str:
        """The chosen preset, or the one leading: of those whose head tops match the
        observed head top (median over the frames so far) within
        ``stature_tolerance`` metres of the best match, the one of smallest mean
        distance; with ``body_cue="distance"`` the smallest mean distance alone."""
        if self.chosen is not None:
            return self.chosen

        def dist(b: str) -> float:
            return float(np.mean(self.scores[b] or [np.inf]))

        if self.options.body_cue == "stature" and all(len(v) for v in self.tops.values()):
            off = {b: abs(float(np.median(v))) * self.geometry.mpp(2)
                   for b, v in self.tops.items()}
            least = min(off.values())
            near = [b for b in off if off[b] <= least + self.options.stature_tolerance]
            return min(near, key=dist)
        return min(self.scores, key=dist)
