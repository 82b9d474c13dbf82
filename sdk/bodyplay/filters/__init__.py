"""Joint smoothing filters: One Euro and Kalman (constant velocity / acceleration).

Every filter implements :class:`JointFilter`: ``filter(t, joints, state)`` per frame,
``reset()`` when the person changes. Build one by name with :func:`make_filter`
(``"one_euro"``, ``"kalman_cv"``, ``"kalman_ca"``) or with its own factory.
"""

from __future__ import annotations

from typing import Any

from bodyplay.errors import ConfigError
from bodyplay.filters.base import JointFilter, JointState, check_timestamp, lost_mask
from bodyplay.filters.kalman import KalmanJointFilter, KalmanOptions, kalman_filter
from bodyplay.filters.one_euro import OneEuroFilter, OneEuroOptions, one_euro_filter

__all__ = [
    "FILTER_KINDS",
    "JointFilter",
    "JointState",
    "KalmanJointFilter",
    "KalmanOptions",
    "OneEuroFilter",
    "OneEuroOptions",
    "check_timestamp",
    "kalman_filter",
    "lost_mask",
    "make_filter",
    "one_euro_filter",
]

FILTER_KINDS: tuple[str, ...] = ("one_euro", "kalman_cv", "kalman_ca")
"""Names :func:`make_filter` accepts."""


def make_filter(kind: str, **options: Any) -> JointFilter:
    """Build a joint filter by name with keyword options, e.g. ``make_filter("kalman_ca")``.

    Raises :class:`~bodyplay.errors.ConfigError` for an unknown kind or option.
    """
    if kind == "one_euro":
        return one_euro_filter(**options)
    if kind in ("kalman_cv", "kalman_ca"):
        if "model" in options:
            raise ConfigError(f"filter kind {kind!r} already sets the model; drop 'model'")
        return kalman_filter(model=kind[-2:], **options)
    raise ConfigError(f"unknown filter kind {kind!r}; choose one of {', '.join(FILTER_KINDS)}")
