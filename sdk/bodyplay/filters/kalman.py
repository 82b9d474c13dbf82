"""Kalman smoothing of joints with constant-velocity or constant-acceleration motion.

Each joint coordinate follows a kinematic model: ``cv`` (position, velocity; white-noise
acceleration) or ``ca`` (position, velocity, acceleration; white-noise jerk). The
process noise is filterpy's :func:`~filterpy.common.Q_discrete_white_noise` for the
frame's real ``dt``, so uneven frame spacing is modelled. The measurement is the
joint position with isotropic noise ``measurement_std``.

Lost joints (NaN or state ``lost``) are predicted but not updated; after
``max_predict`` seconds without a measurement they come out as NaN and restart from
their next measurement. A measurement further than ``gate`` standard deviations
(Mahalanobis) from the prediction is treated as an outlier and skipped, unless
``max_rejections`` come in a row (then the person really moved: re-initialize).

Two back-ends compute the same thing (the tests check they agree):
``filterpy`` keeps one :class:`filterpy.kalman.KalmanFilter` per joint (x, y, z
blocks in one 6- or 9-dimensional state); ``numpy`` (default) batches the same
equations (predict, Joseph-form update) over all joints in a few array operations.
It exists because filterpy's per-call overhead makes 17 filters cost about 1.1 ms a
frame, four times the numpy version (see docs/smoothing.md). Because the three
axes of a joint share F, Q, H and an isotropic R, their covariances stay identical,
so the numpy back-end keeps one n x n covariance per joint.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from filterpy.common import Q_discrete_white_noise
from filterpy.kalman import KalmanFilter
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import NUM_JOINTS
from bodyplay.errors import ConfigError
from bodyplay.filters.base import (
    JointState,
    as_joints,
    check_timestamp,
    lost_mask,
    with_overrides,
)
from bodyplay.optiontypes import check_option_types

__all__ = ["KalmanOptions", "KalmanJointFilter", "kalman_filter"]


@dataclass(frozen=True)
class KalmanOptions:
    """Settings of the Kalman joint smoother.

    ``model``: ``cv`` (constant velocity) or ``ca`` (constant acceleration).
    ``measurement_std`` (m): tracker noise per coordinate.
    ``accel_std`` (m/s^2, cv): std of the white-noise acceleration.
    ``jerk_std`` (m/s^3, ca): std of the white-noise jerk; the per-frame variance
    given to Q_discrete_white_noise is ``(jerk_std * dt)**2``.
    ``init_velocity_std`` (m/s), ``init_accel_std`` (m/s^2): prior spread at (re)start.
    ``gate`` (sigmas, or None for no gating): outlier rejection threshold.
    ``max_rejections``: consecutive rejected measurements that force a re-start.
    ``max_predict`` (s): how long a lost joint is predicted before it becomes NaN.
    ``backend``: ``numpy`` (batched, default) or ``filterpy`` (one KalmanFilter per joint).
    """

    model: Literal["cv", "ca"] = "cv"
    measurement_std: float = 0.03
    accel_std: float = 10.0
    jerk_std: float = 100.0
    init_velocity_std: float = 1.0
    init_accel_std: float = 10.0
    gate: float | None = 5.0
    max_rejections: int = 3
    max_predict: float = 0.3
    backend: Literal["numpy", "filterpy"] = "numpy"

    def __post_init__(self) -> None:
        check_option_types(self)
        _validate(self)


def _validate(o: KalmanOptions) -> None:
    if o.model not in ("cv", "ca"):
        raise ConfigError(f"KalmanOptions.model must be 'cv' or 'ca', got {o.model!r}")
    if o.backend not in ("numpy", "filterpy"):
        raise ConfigError(
            f"KalmanOptions.backend must be 'numpy' or 'filterpy', got {o.backend!r}"
        )
    for name in (
        "measurement_std",
        "accel_std",
        "jerk_std",
        "init_velocity_std",
        "init_accel_std",
        "max_predict",
    ):
        v = getattr(o, name)
        if not isinstance(v, int | float) or not np.isfinite(v) or v <= 0:
            raise ConfigError(f"KalmanOptions.{name} must be a positive number, got {v!r}")
    if o.gate is not None and (not isinstance(o.gate, int | float) or not o.gate > 0):
        raise ConfigError(f"KalmanOptions.gate must be a positive number or None, got {o.gate!r}")
    if not isinstance(o.max_rejections, int) or o.max_rejections < 1:
        raise ConfigError(
            f"KalmanOptions.max_rejections must be an integer >= 1, got {o.max_rejections!r}"
        )


def kalman_filter(options: KalmanOptions | None = None, **overrides: Any) -> KalmanJointFilter:
    """Build a Kalman joint smoother from options and/or keyword overrides, validating them.

    e.g. ``kalman_filter(model="ca", measurement_std=0.02)``; unknown keywords or
    invalid values raise :class:`~bodyplay.errors.ConfigError`.
    """
    base = options if options is not None else KalmanOptions()
    return KalmanJointFilter(with_overrides(base, overrides, "Kalman"))


def _transition(order: int, dt: float) -> NDArray[np.float64]:
    """Kinematic state transition for ``order`` derivatives (2: cv, 3: ca) over dt."""
    F = np.eye(order)
    F[0, 1] = dt
    if order == 3:
        F[0, 2] = 0.5 * dt * dt
        F[1, 2] = dt
    return F


class KalmanJointFilter:
    """Kalman smoothing of (17, 3) joints; implements :class:`JointFilter`.

    Lost joints are predicted for up to ``max_predict`` seconds (their output is the
    prediction), then NaN. :meth:`velocities` gives the estimated joint velocities.
    """

    def __init__(self, options: KalmanOptions | None = None) -> None:
        self.options = options if options is not None else KalmanOptions()
        _validate(self.options)
        self._n = 2 if self.options.model == "cv" else 3
        self._r = self.options.measurement_std**2
        p0 = [self._r, self.options.init_velocity_std**2, self.options.init_accel_std**2]
        self._P0 = np.diag(p0[: self._n])
        self.reset()

    # ---- public -------------------------------------------------------------------
    def reset(self) -> None:
        """Forget every joint's state."""
        n = self._n
        self._X = np.zeros((NUM_JOINTS, 3, n))
        self._P = np.repeat(self._P0[None], NUM_JOINTS, axis=0)
        self._active = np.zeros(NUM_JOINTS, dtype=bool)
        self._seen_t = np.full(NUM_JOINTS, -np.inf)
        self._rejections = np.zeros(NUM_JOINTS, dtype=int)
        self._last_t: float | None = None
        self._kfs: list[KalmanFilter] | None = None
        if self.options.backend == "filterpy":
            self._kfs = [self._make_kf() for _ in range(NUM_JOINTS)]

    def filter(self, t: float, joints: ArrayLike, state: JointState = None) -> NDArray[np.float64]:
        """Predict to ``t``, update with the measured joints; returns a new (17, 3) array."""
        z = as_joints(joints)
        lost = lost_mask(z, state)
        dt = check_timestamp(t, self._last_t)
        self._last_t = float(t)
        o = self.options
        # Joints unseen for too long stop being predicted and restart when seen.
        self._active &= (t - self._seen_t) <= o.max_predict
        run = self._active.copy()
        if dt > 0 and np.any(run):
            self._predict(dt, run)
        meas = run & ~lost
        if np.any(meas):
            ok = meas.copy()
            if o.gate is not None:
                d2 = self._mahalanobis2(z)
                bad = meas & (d2 > o.gate**2)
                self._rejections[bad] += 1
                restart = bad & (self._rejections >= o.max_rejections)
                ok = meas & ~bad
                self._start(z, restart, t)
            if np.any(ok):
                self._update(z, ok)
                self._rejections[ok] = 0
                self._seen_t[ok] = t
        self._start(z, ~lost & ~run, t)
        out = self._X[:, :, 0].copy()
        out[~self._active] = np.nan
        return out

    def velocities(self) -> NDArray[np.float64]:
        """(17, 3) estimated velocities in m/s after the last frame (NaN when inactive)."""
        self._sync_from_filterpy()
        v = self._X[:, :, 1].copy()
        v[~self._active] = np.nan
        return v

    # ---- internals ----------------------------------------------------------------
    def _process_var(self, dt: float) -> float:
        o = self.options
        return o.accel_std**2 if self._n == 2 else (o.jerk_std * dt) ** 2

    def _make_kf(self) -> KalmanFilter:
        n = self._n
        kf = KalmanFilter(dim_x=3 * n, dim_z=3)
        kf.H = np.zeros((3, 3 * n))
        for a in range(3):
            kf.H[a, a * n] = 1.0
        kf.R = np.eye(3) * self._r
        return kf

    def _start(self, z: NDArray[np.float64], mask: NDArray[np.bool_], t: float) -> None:
        if not np.any(mask):
            return
        self._X[mask] = 0.0
        self._X[mask, :, 0] = z[mask]
        self._P[mask] = self._P0
        self._active[mask] = True
        self._seen_t[mask] = t
        self._rejections[mask] = 0
        if self._kfs is not None:
            for j in np.flatnonzero(mask):
                kf = self._kfs[j]
                kf.x = self._X[j].reshape(-1, 1).copy()
                kf.P = np.kron(np.eye(3), self._P0)

    def _predict(self, dt: float, run: NDArray[np.bool_]) -> None:
        F = _transition(self._n, dt)
        Q = Q_discrete_white_noise(self._n, dt=dt, var=self._process_var(dt))
        if self._kfs is not None:
            F3 = np.kron(np.eye(3), F)
            Q3 = Q_discrete_white_noise(self._n, dt=dt, var=self._process_var(dt), block_size=3)
            for j in np.flatnonzero(run):
                kf = self._kfs[j]
                kf.predict(F=F3, Q=Q3)
            self._sync_from_filterpy(run)
            return
        self._X[run] = np.einsum("ij,kaj->kai", F, self._X[run])
        self._P[run] = F @ self._P[run] @ F.T + Q

    def _mahalanobis2(self, z: NDArray[np.float64]) -> NDArray[np.float64]:
        # S = H P H' + R is r + P[0, 0] times the 3x3 identity for every joint.
        y = z - self._X[:, :, 0]
        s = self._P[:, 0, 0] + self._r
        with np.errstate(invalid="ignore"):
            return np.where(np.isfinite(y).all(axis=1), np.sum(y * y, axis=1) / s, np.inf)

    def _update(self, z: NDArray[np.float64], ok: NDArray[np.bool_]) -> None:
        if self._kfs is not None:
            for j in np.flatnonzero(ok):
                self._kfs[j].update(z[j])
            self._sync_from_filterpy(ok)
            return
        P = self._P[ok]
        s = P[:, 0, 0] + self._r
        K = P[:, :, 0] / s[:, None]  # (m, n): gain, the same for each axis
        y = z[ok] - self._X[ok, :, 0]  # (m, 3)
        self._X[ok] += y[:, :, None] * K[:, None, :]
        # Joseph form, as filterpy: (I - K H) P (I - K H)' + K R K'
        A = np.repeat(np.eye(self._n)[None], len(K), axis=0)
        A[:, :, 0] -= K
        self._P[ok] = A @ P @ A.transpose(0, 2, 1) + self._r * K[:, :, None] * K[:, None, :]

    def _sync_from_filterpy(self, mask: NDArray[np.bool_] | None = None) -> None:
        if self._kfs is None:
            return
        n = self._n
        idx = range(NUM_JOINTS) if mask is None else np.flatnonzero(mask)
        for j in idx:
            kf = self._kfs[j]
            self._X[j] = kf.x.reshape(3, n)
            self._P[j] = kf.P[:n, :n]
