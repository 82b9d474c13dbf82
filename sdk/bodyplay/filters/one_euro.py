"""The One Euro filter (Casiez, Roussel and Vogel, CHI 2012) over all 17 x 3 coordinates.

A first-order low-pass filter whose cutoff frequency rises with speed: at rest the
cutoff is ``min_cutoff`` (little jitter), when the joint moves fast it rises by
``beta`` Hz per m/s (little lag). The speed is itself low-passed at ``d_cutoff``.
Every step uses the real time since the joint's previous measurement, so dropped or
unevenly spaced frames are handled. All 51 coordinates are filtered at once in numpy.

By default the speed that raises the cutoff is the joint's 3D speed (the same cutoff
for its three coordinates, so the result does not depend on how the world axes are
oriented); ``speed="coordinate"`` filters each coordinate on its own, as in the paper.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
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

__all__ = ["OneEuroOptions", "OneEuroFilter", "one_euro_filter", "smoothing_factor"]


@dataclass(frozen=True)
class OneEuroOptions:
    """Settings of the One Euro filter.

    ``min_cutoff`` (Hz): cutoff at rest; lower removes more jitter but lags slow motion.
    ``beta`` (Hz per m/s): how fast the cutoff rises with speed; higher lags less on
    fast motion. ``d_cutoff`` (Hz): cutoff of the speed estimate. ``speed``: ``joint``
    (3D speed per joint) or ``coordinate`` (each coordinate on its own, as the paper).
    ``reset_after`` (s): a joint lost for longer restarts from its next measurement.
    """

    min_cutoff: float = 1.0
    beta: float = 2.0
    d_cutoff: float = 1.0
    speed: Literal["joint", "coordinate"] = "joint"
    reset_after: float = 0.5

    def __post_init__(self) -> None:
        check_option_types(self)
        _validate(self)


def _validate(o: OneEuroOptions) -> None:
    for name in ("min_cutoff", "d_cutoff", "reset_after"):
        v = getattr(o, name)
        if not isinstance(v, int | float) or not np.isfinite(v) or v <= 0:
            raise ConfigError(f"OneEuroOptions.{name} must be a positive number, got {v!r}")
    if not isinstance(o.beta, int | float) or not np.isfinite(o.beta) or o.beta < 0:
        raise ConfigError(f"OneEuroOptions.beta must be a number >= 0, got {o.beta!r}")
    if o.speed not in ("joint", "coordinate"):
        raise ConfigError(f"OneEuroOptions.speed must be 'joint' or 'coordinate', got {o.speed!r}")


def one_euro_filter(options: OneEuroOptions | None = None, **overrides: Any) -> OneEuroFilter:
    """Build a One Euro filter from options and/or keyword overrides, validating them.

    Unknown keywords or invalid values raise :class:`~bodyplay.errors.ConfigError`,
    e.g. ``one_euro_filter(min_cutoff=0.8, beta=3.0)``.
    """
    base = options if options is not None else OneEuroOptions()
    return OneEuroFilter(with_overrides(base, overrides, "One Euro"))


def smoothing_factor(cutoff: NDArray[np.float64], dt: NDArray[np.float64]) -> NDArray[np.float64]:
    """Exponential smoothing factor of a first-order low-pass at ``cutoff`` Hz over ``dt`` s."""
    r = 2.0 * np.pi * cutoff * dt
    return r / (r + 1.0)


class OneEuroFilter:
    """One Euro smoothing of (17, 3) joints; implements :class:`JointFilter`.

    Lost joints (NaN or state ``lost``) come out as NaN and keep their history, so
    that a joint seen again within ``reset_after`` seconds continues smoothly.
    """

    def __init__(self, options: OneEuroOptions | None = None) -> None:
        self.options = options if options is not None else OneEuroOptions()
        _validate(self.options)
        self.reset()

    def reset(self) -> None:
        """Forget every joint's history."""
        self._x = np.full((NUM_JOINTS, 3), np.nan)
        self._dx = np.zeros((NUM_JOINTS, 3))
        self._seen_t = np.full(NUM_JOINTS, -np.inf)
        self._last_t: float | None = None

    def filter(self, t: float, joints: ArrayLike, state: JointState = None) -> NDArray[np.float64]:
        """Smooth one frame captured at ``t`` seconds; returns a new (17, 3) array."""
        z = as_joints(joints)
        lost = lost_mask(z, state)
        check_timestamp(t, self._last_t)
        self._last_t = float(t)
        o = self.options
        gap = t - self._seen_t  # time since each joint's last measurement
        fresh = ~lost & ~(gap <= o.reset_after)
        run = ~lost & ~fresh
        if np.any(run):
            dt = gap[run][:, None]
            x_prev = self._x[run]
            dx = (z[run] - x_prev) / dt
            dx_hat = self._dx[run] + smoothing_factor(np.asarray(o.d_cutoff), dt) * (
                dx - self._dx[run]
            )
            if o.speed == "joint":
                speed = np.linalg.norm(dx_hat, axis=1, keepdims=True)
            else:
                speed = np.abs(dx_hat)
            a = smoothing_factor(o.min_cutoff + o.beta * speed, dt)
            self._x[run] = x_prev + a * (z[run] - x_prev)
            self._dx[run] = dx_hat
        if np.any(fresh):
            self._x[fresh] = z[fresh]
            self._dx[fresh] = 0.0
        self._seen_t[~lost] = t
        out = self._x.copy()
        out[lost] = np.nan
        return out
