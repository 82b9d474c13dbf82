"""The body's width measured from the silhouette (an addition to the paper).

The paper's body-size models, like this tracker's presets (``xs`` to ``xl``), tie
the body's thickness to its height: a preset is chosen by stature
(:mod:`.bodychoice`), and the player's torso and limbs are as thick as that
preset's. People of one height differ in build, and clothes add to it: on the real
footage of Pose2Sim the rendered body of the chosen preset was 3 to 6 pixels
narrower, row by row, than the person's silhouette (MediaPipe's mask: 3 to 7 cm
across the torso), and on the synthetic captures the actor was wider than the
tracker's mesh too (docs/silhouette-history.md, section 14).

The body's *girth* (the thickness of torso and limbs about their bones; the
skeleton, its joints and bone lengths do not change) is measured on the reported
pose, frame by frame, with the tracker's own distance: the body mesh of the chosen
preset at each of a few girth factors (0.9 to ``width_max``) in the reported pose
is rendered in the window and scored by eq. 10-11 (the sum of A = D(S) - W over its
pixels; the distance is linear in the template mask), and the cheapest factor is
that frame's reading. The width is a property of the player, not of a frame: the
median of the track's first ``width_frames`` readings is kept for the track, and
reported as the body shape (``extras["shape"]``, a
:class:`~bodyplay.body.shapes.BodyShape`) that a game or a figure renders the
reported pose with. The joints do not change.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.mesh import body_mesh
from bodyplay.body.shapes import BodyShape, body_shape
from bodyplay.body.skeleton import Skeleton
from bodyplay.body.skinning import SkinnedMesh
from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError
from bodyplay.render.idmap import project_vertices, rasterize_ids

__all__ = ["WidthFit", "girth_factors", "widened"]

_STEP = 0.1  # between the girth factors tried
_LOWEST = 0.9  # the thinnest factor tried


def girth_factors(width_max: float) -> NDArray[np.float64]:
    """The girth factors a frame is read at: 0.9 to ``width_max`` in steps of 0.1
    (1.0 always among them)."""
    if width_max < 1.0:
        raise ConfigError(f"width_max must be at least 1 (the preset's own girth), got {width_max}")
    n = int(np.floor((width_max - _LOWEST) / _STEP + 1e-9)) + 1
    return np.round(_LOWEST + _STEP * np.arange(n), 6)


def widened(shape: BodyShape, factor: float) -> BodyShape:
    """``shape`` with its torso and limbs ``factor`` times as thick (girth and chest;
    height and breadth, hence the skeleton's joints, unchanged)."""
    return dataclasses.replace(shape, girth=shape.girth * factor, chest=shape.chest * factor)


class WidthFit:
    """The girth of the player measured on the reported poses of one track.

    ``frames``: readings kept (their median is the width); ``width_max``: the widest
    factor tried. :meth:`add` reads a frame, :attr:`factor` is the width so far
    (1.0 before any reading, relative to the preset's own girth) and
    :meth:`shape` the body shape to report for a preset. The readings are relative
    to the preset in use at each frame, so they carry over while the body preset is
    being chosen (neighbouring presets differ in girth by 4 to 6%).
    """

    def __init__(self, frames: int, width_max: float) -> None:
        if frames < 1:
            raise ConfigError(f"a width fit needs at least one frame, got {frames}")
        self.frames = frames
        self.factors = girth_factors(width_max)
        self._meshes: dict[str, list[tuple[Skeleton, SkinnedMesh]]] = {}  # built on use
        self.readings: list[float] = []
        self.factor = 1.0

    @property
    def done(self) -> bool:
        """Whether all ``frames`` readings are in (the width is fixed for the track)."""
        return len(self.readings) >= self.frames

    def shape(self, body: str) -> BodyShape:
        """The preset ``body`` at the measured width."""
        return widened(body_shape(body), self.factor)

    def costs(self, body: str, pose: NDArray[np.float64], view: Camera,
              cost: NDArray[np.float32]) -> NDArray[np.float64]:
        """eq. 11's sum of A = D(S) - W (``cost``, one window level, the size of the
        view ``view``) over the pixels of preset ``body``'s mesh in ``pose`` (world),
        per girth factor."""
        meshes = self._meshes.get(body)
        if meshes is None:
            meshes = []
            for f in self.factors:
                sk = Skeleton.from_shape(widened(body_shape(body), float(f)))
                meshes.append((sk, body_mesh(sk)))
            self._meshes[body] = meshes
        h, w = cost.shape
        out = np.empty(len(self.factors))
        q = np.asarray(pose, np.float64)[None]
        for k, (sk, mesh) in enumerate(meshes):
            ids = rasterize_ids(project_vertices(mesh.pose(sk, q)[0], view), mesh.faces,
                                None, w, h)
            out[k] = float(cost[ids > 0].sum(dtype=np.float64))
        return out

    def add(self, body: str, pose: NDArray[np.float64], view: Camera,
            cost: NDArray[np.float32]) -> None:
        """Read one frame (preset ``body`` in the reported ``pose``, world; the window's
        ``view`` and its A map ``cost``): the cheapest factor joins the readings, and
        the width is their median. Nothing once :attr:`done`."""
        if self.done:
            return
        c = self.costs(body, pose, view, cost)
        self.readings.append(float(self.factors[int(np.argmin(c))]))
        self.factor = float(np.median(self.readings))
