"""Choosing the body-size preset at start-up (``ColorShirtOptions(body="auto")``): every
preset is fitted on the first frames with the shirt, and the one whose patch anchors
reproject closest (in shirt sizes) wins. The database stays the reference body's.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shapes import BODY_SHAPES
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.ik import KinematicSolver, PatchAnchors
from bodyplay.trackers.colorshirt.prediction import PoseRenderer, RenderedPose
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["ARM_SCALES", "BodyFit", "BodyModel", "BodySelection", "arm_variants",
           "build_body_models", "reprojection_residual", "with_arm_scale"]

ARM_SCALES: tuple[float, ...] = (0.84, 0.88, 0.92, 0.96, 1.0)
"""Arm lengths tried after the preset is chosen, relative to the preset's."""

_ARM_NODES = ("l_elbow", "r_elbow", "l_wrist", "r_wrist", "l_hand", "r_hand")


@dataclass(eq=False)
class BodyFit:
    """One body's fit of a frame: pose, anchored patches, mean relative residual, and
    its body's renderer and cameras."""

    q: NDArray[np.float64]
    seen: set[int]
    residual: float
    views: list[CameraView]
    renderer: PoseRenderer
    cameras: tuple[Camera, ...]
    _rendered: list[RenderedPose] | None = None

    @property
    def rendered(self) -> list[RenderedPose]:
        """The final pose rendered into each view's crop (on first use)."""
        if self._rendered is None:
            verts = self.renderer.vertices(self.q)
            self._rendered = [self.renderer.render(verts, self.cameras[v.index], v.window)
                              for v in self.views]
        return self._rendered


@dataclass(frozen=True, eq=False)
class BodyModel:
    """Everything of one body preset the per-frame fit needs (built once, cached)."""

    name: str
    skeleton: Skeleton
    renderer: PoseRenderer
    solver: KinematicSolver

    @classmethod
    def build(cls, name: str, cameras: tuple[Camera, ...],
              skeleton: Skeleton | None = None) -> BodyModel:
        """Skeleton, mesh renderer and IK solver of preset ``name`` for ``cameras``."""
        sk = skeleton if skeleton is not None else Skeleton.from_shape(name)
        return cls(name, sk, PoseRenderer(sk), KinematicSolver(sk, cameras))


def build_body_models(cameras: tuple[Camera, ...]) -> dict[str, BodyModel]:
    """A :class:`BodyModel` for every shipped preset."""
    return {n: BodyModel.build(n, cameras) for n in BODY_SHAPES}


def with_arm_scale(skeleton: Skeleton, scale: float) -> Skeleton:
    """``skeleton`` with its upper arms, forearms and hands ``scale`` times as long."""
    off = skeleton.offsets.copy()
    for name in _ARM_NODES:
        off[skeleton.node_index(name)] *= scale
    rows = tuple((float(r[0]), float(r[1]), float(r[2])) for r in off)
    return Skeleton(skeleton.shape, rows)


def arm_variants(body: BodyModel, cameras: tuple[Camera, ...],
                 scales: tuple[float, ...] = ARM_SCALES) -> dict[str, BodyModel]:
    """``body`` with each arm length of ``scales``, shortest first; scale 1 is ``body``
    itself, under its own name, the others are named like ``m_slim*0.88``."""
    out: dict[str, BodyModel] = {}
    for a in sorted(scales):
        if abs(a - 1.0) < 1e-9:
            out[body.name] = body
        else:
            name = f"{body.name}*{a:.2f}"
            out[name] = BodyModel.build(name, cameras, with_arm_scale(body.skeleton, a))
    return out


def reprojection_residual(solver: KinematicSolver, q: NDArray[np.float64],
                          anchors: PatchAnchors, size_px: NDArray[np.float64]) -> float:
    """Mean distance between projected anchors and observed centroids at pose ``q``,
    relative to ``size_px`` (A,), the shirt's size in each anchor's camera."""
    if len(anchors) == 0:
        return float("nan")
    proj = solver.project(q, anchors)[0]
    return float(np.mean(np.linalg.norm(proj - anchors.target, axis=1) / size_px))


@dataclass
class BodySelection:
    """Running mean residual of each candidate preset over the start-up frames.

    ``frames`` frames with a fit decide; ``previous`` holds each candidate's last
    pose. After each fraction ``halvings`` of them the worse half of the ``active``
    candidates drops out (down to two; not those within ``tolerance``). The first
    candidate in ``names`` order within ``tolerance`` of the lowest mean wins. After
    ``patience`` times ``frames`` :meth:`skip`-ped frames, a fallback is chosen.
    """

    names: tuple[str, ...]
    frames: int
    sums: dict[str, float] = field(default_factory=dict)
    counts: dict[str, int] = field(default_factory=dict)
    previous: dict[str, NDArray[np.float64] | None] = field(default_factory=dict)
    seen: int = 0
    chosen: str | None = None
    halvings: tuple[float, ...] = (0.5,)
    active: list[str] = field(default_factory=list)
    tolerance: float = 0.0
    patience: float = 2.0
    skipped: int = 0

    def __post_init__(self) -> None:
        if not self.active:
            self.active = list(self.names)

    def add(self, residuals: dict[str, float]) -> None:
        """Record one frame's residual per candidate (NaN: the candidate failed)."""
        self.seen += 1
        for n in self.names:
            r = residuals.get(n, float("nan"))
            if np.isfinite(r):
                self.sums[n] = self.sums.get(n, 0.0) + r
                self.counts[n] = self.counts.get(n, 0) + 1
        for f in self.halvings:
            if self.seen == max(1, round(f * self.frames)) and len(self.active) > 2:
                ranked = sorted(self.active, key=self.mean)
                kept = ranked[: max(2, (len(ranked) + 1) // 2)]
                near = self.mean(ranked[0]) * (1.0 + self.tolerance)
                self.active = [n for n in ranked if n in kept or self.mean(n) <= near]
        if self.chosen is None and self.seen >= self.frames and self.counts:
            self.chosen = self.best()

    def skip(self, fallback: str) -> None:
        """Record a frame that cannot judge the candidates; once ``patience * frames``
        such frames came before the choice, choose ``fallback``."""
        self.skipped += 1
        if self.chosen is None and self.skipped >= self.patience * self.frames:
            self.chosen = fallback

    def mean(self, name: str) -> float:
        """Mean residual of a candidate so far (inf before it has any)."""
        c = self.counts.get(name, 0)
        return self.sums[name] / c if c else float("inf")

    def best(self) -> str:
        """The candidate in the race with the lowest mean residual among those fitted
        most often."""
        most = max((self.counts.get(n, 0) for n in self.active), default=0)
        pool = [n for n in self.active if self.counts.get(n, 0) >= max(1, most // 2)]
        if not pool:
            return self.active[0] if self.active else self.names[0]
        best = min(self.mean(n) for n in pool)
        return next(n for n in self.names if n in pool
                    and self.mean(n) <= best * (1.0 + self.tolerance))

    def means(self) -> dict[str, float]:
        """Mean residual of every candidate (for the diagnostics)."""
        return {n: self.mean(n) for n in self.names}
