"""One camera's root depth over time: a Kalman filter of the feet and the shirt's size.

One camera cannot tell a small person near from a tall one far. Two cues tell the
root's depth along the camera's axis: the feet on the floor (:mod:`.floor`, 5 cm
when they stand on it, but metres off when they leave it: a foot 18 cm up reads
about 50 cm too far at 3 m) and the shirt's size in the image with the chosen
body's known lengths (biased by as much as the body's size is off).
:class:`RootDepthFilter` follows the depth over time with a constant-velocity
model (filterpy): a player walking towards the camera is followed, a floor
reading that disagrees with the prediction by more than ``gate`` standard
deviations (the feet in the air, a misread foot) is left out, and frames without
a reading hold the depth with a growing uncertainty. Its prediction, updated by
the frame's floor reading, is the IK's prior on the root's depth (the IK adds
the shirt), and the fitted depth carries on to the next frame; the standard
deviation is reported per frame. Without any floor reading there is no state,
and the depth is the shirt's. Beyond the paper.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from filterpy.common import Q_discrete_white_noise
from filterpy.kalman import KalmanFilter

from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.ik import RootPrior

__all__ = ["RootDepthFilter"]


@dataclass
class RootDepthFilter:
    """Kalman filter on ``[depth, depth speed]`` along a lone camera's axis.

    ``accel``: std of the root's acceleration along the axis (m/s², white noise);
    ``floor_std``: std of a floor reading (m); ``gate``: squared innovation, in variances, beyond
    which a floor reading is left out; after ``max_rejects`` rejected readings in a
    row the filter restarts from the reading (it, not the prediction, was right);
    ``horizon``: seconds without a report after which the state lapses.
    Per frame: :meth:`begin` (predict, floor update, the prior) and, when a pose is
    reported, :meth:`end` (the fitted depth carries on).
    """

    accel: float = 3.0
    floor_std: float = 0.05
    gate: float = 9.0
    max_rejects: int = 15
    horizon: float = 1.0
    camera: int | None = None
    t: float = float("nan")
    rejects: int = 0
    rejected: bool = False
    """Whether this frame's floor reading was left out."""
    kf: KalmanFilter | None = field(default=None, repr=False)

    def _start(self, depth: float, std: float) -> None:
        kf = KalmanFilter(dim_x=2, dim_z=1)
        kf.x = np.array([depth, 0.0])
        kf.P = np.diag([std**2, 1.0])
        kf.H = np.array([[1.0, 0.0]])
        self.kf = kf
        self.rejects = 0

    def std(self) -> float | None:
        """The depth's current standard deviation (m), None without a state."""
        return None if self.kf is None else float(np.sqrt(self.kf.P[0, 0]))

    def depth(self) -> float | None:
        """The depth's current estimate (m along the camera's axis), None without one."""
        return None if self.kf is None else float(self.kf.x[0])

    def begin(self, cameras: Sequence[Camera], index: int | None, t: float,
              floor: float | None) -> RootPrior | None:
        """A new frame at ``t`` that camera ``index`` alone sees (None: two or more
        cameras, which see depth themselves; the filter then stops), with the feet's
        floor reading ``floor`` (depth of the root, m; None: no reading). Returns the
        root-depth prior for the fit (None: nothing known yet)."""
        self.rejected = False
        if index is None:
            self.camera, self.kf = None, None
            return None
        if self.camera != index or self.kf is None or not t - self.t <= self.horizon:
            self.camera, self.kf = index, None
            if floor is not None:
                self._start(floor, self.floor_std)
        else:
            dt = max(t - self.t, 1e-3)
            self.kf.F = np.array([[1.0, dt], [0.0, 1.0]])
            self.kf.Q = Q_discrete_white_noise(dim=2, dt=dt, var=self.accel**2)
            self.kf.predict()
            if floor is not None:
                S = float(self.kf.P[0, 0]) + self.floor_std**2
                if (floor - float(self.kf.x[0])) ** 2 > self.gate * S:
                    self.rejected = True
                    self.rejects += 1
                    if self.rejects >= self.max_rejects:
                        self._start(floor, self.floor_std)
                else:
                    self.rejects = 0
                    self.kf.update(np.array([floor]), R=np.array([[self.floor_std**2]]))
        self.t = t
        if self.kf is None:
            return None
        return RootPrior.camera_depth(cameras[index], float(self.kf.x[0]),
                                      float(np.sqrt(self.kf.P[0, 0])))

    def end(self, fitted: float | None) -> None:
        """The reported pose's root depth ``fitted`` (m along the filter's camera)
        becomes the state's depth; the uncertainty stays the one the floor readings
        and the motion model gave. The fit also used the shirt's size, whose error
        is a bias of the body's size rather than noise: counted as a measurement
        every frame it made the filter sure of a depth 30-50 cm off (validation
        clips, one camera)."""
        if self.kf is None or fitted is None or not np.isfinite(fitted):
            return
        self.kf.x[0] = fitted
