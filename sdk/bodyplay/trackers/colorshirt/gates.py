"""What a fit must pass to be reported: :func:`plausible` on its own, and
:class:`SpeedGate` against the pose reported before it."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import UPPER_BODY
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["ROOT_HEIGHT", "SpeedGate", "plausible", "within_reach"]

ROOT_HEIGHT = (0.3, 1.4)
"""Metres above the floor where a lone camera's fitted root may be."""


def plausible(skeleton: Skeleton, cameras: Sequence[Camera], q: NDArray[np.float64],
              views: list[CameraView], q_blend: NDArray[np.float64] | None) -> bool:
    """Whether the estimate ``q`` of ``skeleton`` can be reported: in front of every
    camera that saw the shirt (``views``), its chest inside that camera's crop, its
    root within 0.6 m of the database placement ``q_blend`` (when known), and with
    one camera at a person's height (:data:`ROOT_HEIGHT`)."""
    if len(views) == 1 and not ROOT_HEIGHT[0] <= q[1] <= ROOT_HEIGHT[1]:
        return False  # one camera: a root under the floor or overhead is a wrong depth
    chest = skeleton.joint_positions(q)[UPPER_BODY.index("chest")]
    for v in views:
        cam = cameras[v.index]
        z = float(cam.world_to_camera(chest)[2])
        if not 0.3 < z < 12.0:
            return False
        uv = v.window.to_crop(cam.project(chest, distort=False))
        if not (-0.25 * v.window.width <= uv[0] <= 1.25 * v.window.width
                and -0.25 * v.window.height <= uv[1] <= 1.25 * v.window.height):
            return False
    return q_blend is None or float(np.linalg.norm(q[:3] - np.asarray(q_blend)[:3])) < 0.6


def within_reach(reported: tuple[float, NDArray[np.float64]] | None, t: float,
                 root: NDArray[np.float64], max_speed: float) -> bool:
    """Whether ``root`` at time ``t`` lies within ``0.25 m + max_speed * dt`` of the
    root ``reported`` (time, position) at most a second before."""
    if reported is None:
        return True
    t_prev, last = reported
    dt = t - t_prev
    if dt > 1.0:
        return True
    return float(np.linalg.norm(root - last)) <= 0.25 + max_speed * dt


class SpeedGate:
    """The root of each fit against the one reported last (:func:`within_reach`).

    Two good fits in a row (residual at most ``good_residual``) that agree outvote
    the pose reported before them, if their depth is *confirmed* (not one camera
    alone of several).
    """

    def __init__(self, max_speed: float, good_residual: float) -> None:
        self.max_speed = max_speed
        self.good_residual = good_residual
        self.reported: tuple[float, NDArray[np.float64]] | None = None
        """Time and root of the last pose reported (None: none, or forgotten)."""
        self.unreached: tuple[float, NDArray[np.float64]] | None = None
        """Time and root of the last fit the gate rejected."""

    def clear(self) -> None:
        """Forget the last pose reported and the last fit rejected (a new track)."""
        self.reported = self.unreached = None

    def admits(self, t: float, root: NDArray[np.float64], residual: float,
               confirmed: bool = True) -> bool:
        """Whether a fit with ``root`` and ``residual`` at ``t`` may be reported;
        ``confirmed``: whether its depth is (False: one camera of several saw it)."""
        if within_reach(self.reported, t, root, self.max_speed):
            return True
        if not confirmed:
            return False  # a lone camera's depth: no vote, and not kept as a voter
        if (residual <= self.good_residual and self.unreached is not None
                and within_reach(self.unreached, t, root, self.max_speed)):
            self.reported = None  # the pose reported before them was the outlier
            return True
        self.unreached = (t, root.copy())
        return False

    def report(self, t: float, root: NDArray[np.float64]) -> None:
        """The fit with ``root`` at ``t`` was reported."""
        self.reported = (t, root.copy())
        self.unreached = None
