"""One camera's root depth over time: one Kalman filter for the feet and the body's size.

Two cues read the root's depth ``d`` along the camera's axis: the **feet** on the
floor (:mod:`.floor`, ``d + b``, ``b`` the stance's bias) and the **shirt**, the
torso's patch layout fitted at the size it looks (``d / (s (1 + e))``, ``s`` the
player's size relative to the reference body, ``e`` the shirt's own bias).
:class:`RootDepthFilter` combines them in an extended Kalman filter (filterpy) on
``[depth, depth speed, s, b, e]``. A reading beyond ``gate`` variances is left out,
a floor reading further than one std beyond the prediction too (feet leaving the
floor); ``max_rejects`` floor readings left out in a row restart the depth from the
feet. Beyond the paper.

Per frame: :meth:`RootDepthFilter.begin`, :meth:`RootDepthFilter.posterior` for
each candidate fit (nothing committed), :meth:`RootDepthFilter.end` with the
reported fit's reading.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from filterpy.common import Q_discrete_white_noise
from filterpy.kalman import KalmanFilter
from numpy.typing import NDArray

__all__ = ["RootDepthFilter"]

_N = 5
"""State size: depth, depth speed, scale, floor bias, shirt bias."""


@dataclass
class RootDepthFilter:
    """Kalman filter on ``[depth, depth speed, scale, floor bias, shirt bias]`` along
    a lone camera's axis (see the module docstring).

    ``accel``: the root's acceleration std (m/s²); ``floor_std`` (m), ``shirt_std``
    (fraction of the depth): the readings' stds; ``scale_std``, ``floor_bias_std``,
    ``shirt_bias``, ``shirt_bias_std``: the priors of ``s``, ``b`` (m) and ``e``;
    ``gate``: squared innovation, in variances, beyond which a reading is left out;
    ``max_rejects``: floor readings left out in a row that restart the depth from the
    feet (the shirt's readings have no restart: the filter starts from them);
    ``horizon``: seconds without a reading after which the depth lapses (``s``,
    ``b``, ``e`` stay).
    """

    accel: float = 3.0
    floor_std: float = 0.05
    shirt_std: float = 0.08
    scale_std: float = 0.06
    gate: float = 9.0
    max_rejects: int = 15
    horizon: float = 1.0
    floor_bias_std: float = 0.08
    shirt_bias: float = 0.0
    shirt_bias_std: float = 0.05
    camera: int | None = None
    t: float = float("nan")
    """Time of the state."""
    t_read: float = float("nan")
    """Time of the last reading taken in (the depth lapses ``horizon`` after it)."""
    t_floor: float = float("nan")
    """Time of the last floor reading taken in."""
    floor_rejects: int = 0
    """Floor readings left out in a row."""
    kf: KalmanFilter | None = field(default=None, repr=False)
    _floor: float | None = field(default=None, repr=False)
    """This frame's floor reading, folded in with the fit's readings."""
    _body: tuple[NDArray[np.float64], NDArray[np.float64]] | None = field(default=None,
                                                                         repr=False)
    """The player's scale and biases (means, covariance), kept across a lapse."""

    def __post_init__(self) -> None:
        self._body = (np.array([1.0, 0.0, self.shirt_bias]),
                      np.diag([self.scale_std**2, self.floor_bias_std**2,
                               self.shirt_bias_std**2]))

    def _keep_body(self) -> None:
        """Remember the state's scale and biases for a restart of the depth."""
        if self.kf is not None:
            self._body = (self.kf.x[2:].copy(), self.kf.P[2:, 2:].copy())

    # ---- state ---------------------------------------------------------------------
    def _start(self, x: NDArray[np.float64], P: NDArray[np.float64]) -> None:
        kf = KalmanFilter(dim_x=_N, dim_z=1)
        kf.x = np.asarray(x, np.float64).copy()
        kf.P = np.asarray(P, np.float64).copy()
        self.kf = kf
        self.rejects = {"floor": 0, "shirt": 0}

    def _from(self, depth: float, J0: NDArray[np.float64], var: float
              ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The state of a reading alone: ``depth``, whose dependence on (scale,
        floor bias, shirt bias) is ``J0``, and ``var`` its own variance."""
        assert self._body is not None
        m, C = self._body
        x = np.concatenate([[depth, 0.0], m])
        J = np.zeros((_N, _N - 2))
        J[0] = J0
        J[2:] = np.eye(_N - 2)
        P = J @ C @ J.T
        P[0, 0] += var
        P[1, 1] = 1.0
        return x, P

    def _from_floor(self, depth: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The state a floor reading alone gives: ``depth = reading - bias``."""
        assert self._body is not None
        return self._from(depth - float(self._body[0][1]), np.array([0.0, -1.0, 0.0]),
                          self.floor_std**2)

    def _from_shirt(self, reading: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The state the shirt's reading alone gives: ``depth = reading * s (1 + e)``."""
        assert self._body is not None
        s, e = float(self._body[0][0]), float(self._body[0][2])
        depth = reading * s * (1 + e)
        return self._from(depth, np.array([reading * (1 + e), 0.0, reading * s]),
                          (self.shirt_std * depth) ** 2)

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

    # ---- per frame -----------------------------------------------------------------
    def begin(self, index: int | None, t: float, floor: float | None,
              cameras_seeing: int = 1) -> None:
        """A new frame at ``t`` in which ``cameras_seeing`` cameras see the shirt, the
        lone one being ``index``, with the feet's floor reading ``floor`` (depth of
        the root, m; None: no reading), folded in with the fit's readings. Two or
        more cameras see depth themselves: the depth is then forgotten; no camera:
        nothing changes."""
        self._floor = None
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
        kf.F = np.eye(_N)
        kf.F[0, 1] = dt
        Q = np.zeros((_N, _N))
        Q[:2, :2] = Q_discrete_white_noise(dim=2, dt=dt, var=self.accel**2)
        kf.Q = Q
        kf.predict()
        self.t = t
        self._floor = floor

    @staticmethod
    def _update(x: NDArray[np.float64], P: NDArray[np.float64], H: NDArray[np.float64],
                y: float, R: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Kalman update of ``x, P`` by innovation ``y`` of a reading ``H x`` with
        variance ``R`` (Joseph form)."""
        S = float(H @ P @ H) + R
        K = (P @ H) / S
        I_KH = np.eye(_N) - np.outer(K, H)
        return x + K * y, I_KH @ P @ I_KH.T + R * np.outer(K, K)

    def _fold(self, shirt: float | None
              ) -> tuple[NDArray[np.float64], NDArray[np.float64], dict[str, bool]]:
        """The state with this frame's floor and shirt readings folded in (not
        committed), and which of them were taken in."""
        assert self.kf is not None
        x, P = self.kf.x.copy(), self.kf.P.copy()
        took = {"floor": False, "shirt": False, "floor_rejected": False}
        floor = self._floor
        if floor is not None:
            H = np.array([1.0, 0.0, 0.0, 1.0, 0.0])  # the feet read depth + bias
            y = floor - float(x[0] + x[3])
            R = self.floor_std**2
            S = float(H @ P @ H) + R
            # feet leaving the floor read further: beyond one std further, left out
            if y**2 <= (1.0 if y > 0.0 else self.gate) * S:
                x, P = self._update(x, P, H, y, R)
                took["floor"] = True
            else:
                took["floor_rejected"] = True
        if shirt is not None and np.isfinite(shirt) and shirt > 0:
            d, k = float(x[0]), float(x[2] * (1 + x[4]))  # the shirt reads d / k
            H = np.array([1.0 / k, 0.0, -d / (k * x[2]), 0.0, -d / (k * (1 + x[4]))])
            R = (self.shirt_std * shirt) ** 2
            y = shirt - d / k
            if y**2 <= self.gate * (float(H @ P @ H) + R):
                x, P = self._update(x, P, H, y, R)
                took["shirt"] = True
        return x, P, took

    def posterior(self, shirt: float | None) -> tuple[float, float] | None:
        """Depth and its std once this frame's readings are folded in, without
        committing them: the feet's (:meth:`begin`) and the shirt's ``shirt``
        reading (m, for the reference body's size; None: no reading); None when
        nothing is known. A reading the gate leaves out counts as none."""
        if self.kf is None:
            if shirt is None or self.camera is None or not (np.isfinite(shirt) and shirt > 0):
                return None
            x, P = self._from_shirt(shirt)
            return float(x[0]), float(np.sqrt(P[0, 0]))
        x, P, _ = self._fold(shirt)
        return float(x[0]), float(np.sqrt(P[0, 0]))

    def end(self, t: float, shirt: float | None) -> None:
        """Commit the reported fit's readings at ``t`` (see :meth:`posterior`)."""
        if self.camera is None:
            return
        good_shirt = shirt is not None and bool(np.isfinite(shirt)) and shirt > 0
        if self.kf is None:
            if good_shirt:
                assert shirt is not None
                self._start(*self._from_shirt(shirt))
                self.t = self.t_read = t
            return
        x, P, took = self._fold(shirt)
        self.kf.x, self.kf.P = x, P
        if took["floor"] or took["shirt"]:
            self.t_read = t
        if took["floor"]:
            self.t_floor = t
            self.floor_rejects = 0
        elif took["floor_rejected"]:
            self.floor_rejects += 1
            if self.floor_rejects >= self.max_rejects and self._floor is not None:
                self._keep_body()
                self._start(*self._from_floor(self._floor))
                self.t_read = self.t_floor = t
