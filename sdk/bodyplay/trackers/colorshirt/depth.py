"""One camera's root depth over time: one Kalman filter for the feet and the body's size.

One camera cannot tell a small person near from a tall one far. Two cues tell the
root's depth along the camera's axis:

* the **feet on the floor** (:mod:`.floor`): where the lowest pixels of the
  person meet the floor, raised to the root's height; about 5 cm when the feet
  stand on the floor, metres off when they leave it (a foot 18 cm up reads about
  50 cm too far at 3 m), absent without a background plate;
* the **body's known lengths**: the torso's patch anchors fitted to the image
  without any depth prior (:meth:`.ik.KinematicSolver.solve_global`) put the
  root at the depth where the skeleton's metric lengths project as large as the
  shirt looks. It is always there, noisy (a lean towards the camera reads as
  distance) and biased by the ratio of the player's size to the model's: an 8%
  larger player reads 8% too near.

:class:`RootDepthFilter` combines both in one extended Kalman filter (filterpy)
on ``[depth, depth speed, body scale, floor bias]``: the scale ``s`` is the
player's size over the reference body's, so the shirt reads ``depth / s``; it
starts at 1 with ``scale_std`` and is learned whenever the feet are seen, so
that the shirt alone holds the depth when the feet leave the floor or vanish.
The feet read ``depth + b``: where the lowest pixel of a foot lies relative to
the pelvis depends on the stance (toes towards the camera, a bow that moves the
pelvis back), a bias per player and motion of about ``floor_bias_std`` (5 cm
on the tune half) that no number of readings averages away, so the reported
uncertainty never falls below it. Each reading has a stated standard deviation
(``floor_std`` metres; ``shirt_std`` as a fraction of the depth) and is left out
when its innovation exceeds ``gate`` variances (the feet in the air, a wrong
fit of the shirt). Without a floor reading ever, the depth is the shirt's with
the scale's uncertainty: a missing floor cue costs about ``scale_std`` of the
depth (6%: 18 cm at 3 m), which the reported standard deviation says. Beyond
the paper. Feet leave the floor upwards only, which reads them further: a floor
reading further than predicted by more than one standard deviation of the
innovation is left out (with the symmetric gate alone, a hop's rising feet
passed it a little at a time and dragged the depth 16 cm too far; on the
tune half's hop clip 30 cm). A player who really walks away is followed
through the shirt's readings, or after ``max_rejects`` readings in a row.

Per frame: :meth:`RootDepthFilter.begin` (predict, floor reading),
:meth:`RootDepthFilter.posterior` for each candidate fit (the shirt reading
folded in, nothing committed: the IK's prior on the root's depth), and
:meth:`RootDepthFilter.end` with the reported fit's shirt reading.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from filterpy.common import Q_discrete_white_noise
from filterpy.kalman import KalmanFilter
from numpy.typing import NDArray

__all__ = ["RootDepthFilter"]


@dataclass
class RootDepthFilter:
    """Extended Kalman filter on ``[depth, depth speed, body scale]`` along a lone
    camera's axis (see the module docstring).

    ``accel``: std of the root's acceleration along the axis (m/s², white noise);
    ``floor_std``: std of a floor reading (m); ``shirt_std``: std of the shirt's
    reading as a fraction of the depth; ``scale_std``: the prior std of the
    player's size relative to the reference body; ``floor_bias_std``: the prior std
    of the floor readings' common bias (m); ``gate``: squared innovation, in
    variances, beyond which a reading is left out; after ``max_rejects`` rejected
    readings of a kind in a row the depth restarts from the reading (it, not the
    prediction, was right); ``horizon``: seconds without a reading after which the
    depth lapses (the learned scale stays).
    """

    accel: float = 3.0
    floor_std: float = 0.05
    shirt_std: float = 0.08
    scale_std: float = 0.06
    gate: float = 9.0
    max_rejects: int = 15
    horizon: float = 1.0
    camera: int | None = None
    t: float = float("nan")
    """Time of the state."""
    t_read: float = float("nan")
    """Time of the last reading taken in (the depth lapses ``horizon`` after it)."""
    t_floor: float = float("nan")
    """Time of the last floor reading taken in."""
    rejected: bool = False
    """Whether this frame's floor reading was left out."""
    rejects: dict[str, int] = field(default_factory=lambda: {"floor": 0, "shirt": 0})
    kf: KalmanFilter | None = field(default=None, repr=False)
    floor_bias_std: float = 0.05
    _body: tuple[NDArray[np.float64], NDArray[np.float64]] | None = field(default=None,
                                                                         repr=False)
    """The player's scale and floor bias (means, covariance), kept across a lapse."""

    def __post_init__(self) -> None:
        self._body = (np.array([1.0, 0.0]), np.diag([self.scale_std**2, self.floor_bias_std**2]))

    def _keep_body(self) -> None:
        """Remember the state's scale and floor bias for a restart of the depth."""
        if self.kf is not None:
            self._body = (self.kf.x[2:].copy(), self.kf.P[2:, 2:].copy())

    # ---- state ---------------------------------------------------------------------
    def _start(self, x: NDArray[np.float64], P: NDArray[np.float64]) -> None:
        kf = KalmanFilter(dim_x=4, dim_z=1)
        kf.x = np.asarray(x, np.float64).copy()
        kf.P = np.asarray(P, np.float64).copy()
        self.kf = kf
        self.rejects = {"floor": 0, "shirt": 0}

    def _from_floor(self, depth: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The state a floor reading alone gives: ``depth = reading - bias``."""
        assert self._body is not None
        m, C = self._body
        x = np.array([depth - m[1], 0.0, m[0], m[1]])
        J = np.array([[0.0, -1.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])  # d(x)/d(s, b)
        P = J @ C @ J.T
        P[0, 0] += self.floor_std**2
        P[1, 1] = 1.0
        return x, P

    def _from_shirt(self, reading: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The state the shirt's reading alone gives: ``depth = reading * scale``."""
        assert self._body is not None
        m, C = self._body
        x = np.array([reading * m[0], 0.0, m[0], m[1]])
        J = np.array([[reading, 0.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
        P = J @ C @ J.T
        P[0, 0] += (self.shirt_std * reading) ** 2
        P[1, 1] = 1.0
        return x, P

    def feet_known(self) -> bool:
        """Whether the depth rests on the feet: a floor reading taken in within the
        last ``horizon`` seconds of the state."""
        return self.kf is not None and self.t - self.t_floor <= self.horizon

    def std(self) -> float | None:
        """The depth's current standard deviation (m), None without a state."""
        return None if self.kf is None else float(np.sqrt(self.kf.P[0, 0]))

    def depth(self) -> float | None:
        """The depth's current estimate (m along the camera's axis), None without one."""
        return None if self.kf is None else float(self.kf.x[0])

    def scale(self) -> tuple[float, float]:
        """The player's size relative to the reference body, and its std."""
        if self.kf is not None:
            return float(self.kf.x[2]), float(np.sqrt(self.kf.P[2, 2]))
        assert self._body is not None
        return float(self._body[0][0]), float(np.sqrt(self._body[1][0, 0]))

    # ---- per frame -----------------------------------------------------------------
    def begin(self, index: int | None, t: float, floor: float | None,
              cameras_seeing: int = 1) -> None:
        """A new frame at ``t`` in which ``cameras_seeing`` cameras see the shirt, the
        lone one being ``index``, with the feet's floor reading ``floor`` (depth of
        the root, m; None: no reading). Two or more cameras see depth themselves: the
        depth is then forgotten; no camera: nothing changes."""
        self.rejected = False
        if cameras_seeing == 0:
            return
        if cameras_seeing > 1 or index is None:
            self.camera, self.kf = None, None
            return
        if self.camera != index or self.kf is None or not t - self.t_read <= self.horizon:
            if self.camera == index:
                self._keep_body()
            self.camera, self.kf = index, None
            if floor is not None:
                self._start(*self._from_floor(floor))
                self.t = self.t_read = self.t_floor = t
            return
        kf = self.kf
        dt = max(t - self.t, 1e-3)
        kf.F = np.eye(4)
        kf.F[0, 1] = dt
        Q = np.zeros((4, 4))
        Q[:2, :2] = Q_discrete_white_noise(dim=2, dt=dt, var=self.accel**2)
        kf.Q = Q
        kf.predict()
        self.t = t
        if floor is not None:
            H = np.array([[1.0, 0.0, 0.0, 1.0]])  # the feet read depth + bias
            y = floor - float(kf.x[0] + kf.x[3])
            R = self.floor_std**2
            S = float((H @ kf.P @ H.T)[0, 0]) + R
            # feet leaving the floor read further: beyond one std further, left out
            if y**2 <= (1.0 if y > 0.0 else self.gate) * S:
                self.rejects["floor"] = 0
                kf.update(np.array([floor]), R=np.array([[R]]), H=H)
                self.t_read = self.t_floor = t
            else:
                self.rejects["floor"] += 1
                self.rejected = True
                if self.rejects["floor"] >= self.max_rejects:
                    self._keep_body()
                    self._start(*self._from_floor(floor))
                    self.t_read = self.t_floor = t

    def _shirt_update(self, x: NDArray[np.float64], P: NDArray[np.float64],
                      reading: float) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """``x, P`` updated by the shirt's reading (EKF: it reads ``depth / scale``);
        None when the gate leaves it out."""
        d, s = float(x[0]), float(x[2])
        H = np.array([[1.0 / s, 0.0, -d / s**2, 0.0]])
        R = (self.shirt_std * reading) ** 2
        S = float((H @ P @ H.T)[0, 0]) + R
        y = reading - d / s
        if y**2 > self.gate * S:
            return None
        K = (P @ H.T) / S
        x = x + K[:, 0] * y
        I_KH = np.eye(4) - K @ H
        return x, I_KH @ P @ I_KH.T + R * (K @ K.T)

    def posterior(self, shirt: float | None) -> tuple[float, float] | None:
        """Depth and its std once the shirt's ``shirt`` reading (m, for the reference
        body's size; None: no reading) is folded in, without committing it; None when
        nothing is known. A reading the gate leaves out counts as none."""
        if self.kf is None:
            if shirt is None or self.camera is None:
                return None
            x, P = self._from_shirt(shirt)
            return float(x[0]), float(np.sqrt(P[0, 0]))
        x, P = self.kf.x, self.kf.P
        if shirt is not None and np.isfinite(shirt) and shirt > 0:
            up = self._shirt_update(x, P, shirt)
            if up is not None:
                x, P = up
        return float(x[0]), float(np.sqrt(P[0, 0]))

    def end(self, t: float, shirt: float | None) -> None:
        """Commit the reported fit's shirt reading at ``t`` (see :meth:`posterior`)."""
        if self.camera is None or shirt is None or not (np.isfinite(shirt) and shirt > 0):
            return
        if self.kf is None:
            self._start(*self._from_shirt(shirt))
            self.t = self.t_read = t
            return
        up = self._shirt_update(self.kf.x, self.kf.P, shirt)
        if up is None:
            self.rejects["shirt"] += 1
            if self.rejects["shirt"] >= self.max_rejects:  # the shirt was right
                self._keep_body()
                self._start(*self._from_shirt(shirt))
                self.t = self.t_read = t
            return
        self.rejects["shirt"] = 0
        self.kf.x, self.kf.P = up
        self.t_read = t
