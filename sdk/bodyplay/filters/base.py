"""What every joint filter provides, and the helpers they share.

A joint filter smooths the (17, 3) joint positions a tracker reports frame by frame.
It is driven by explicit capture timestamps (frames need not be evenly spaced) and
told which joints the tracker lost, so that it can predict or hold them instead of
smoothing NaNs. The session calls ``filter(t, joints, state)`` once per frame and
``reset()`` when the person is lost or a new one appears.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import fields, replace
from typing import TYPE_CHECKING, Any, Protocol, TypeVar, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import NUM_JOINTS
from bodyplay.errors import ConfigError, TimestampError

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

__all__ = [
    "JointFilter",
    "JointState",
    "as_joints",
    "lost_mask",
    "check_timestamp",
    "with_overrides",
]

_Options = TypeVar("_Options", bound="DataclassInstance")

JointState = Sequence[str] | None
"""Per-joint tracker state (``tracked``, ``inferred`` or ``lost``), or None when unknown."""


@runtime_checkable
class JointFilter(Protocol):
    """A stateful smoother of joint positions, driven by capture timestamps.

    ``filter`` takes the frame time ``t`` (seconds, strictly increasing), the
    measured joints (17, 3) in world metres (NaN where lost) and the optional
    per-joint state, and returns the smoothed (17, 3) joints (NaN for a joint the
    filter cannot estimate). ``reset`` forgets all history.
    """

    def filter(self, t: float, joints: ArrayLike, state: JointState = None) -> NDArray[np.float64]:
        """Smooth one frame; see the class docstring."""
        ...

    def reset(self) -> None:
        """Forget every joint's history, as if no frame had been seen."""
        ...


def as_joints(joints: ArrayLike) -> NDArray[np.float64]:
    """Check and convert a frame's joints to a float (17, 3) array (a copy)."""
    arr = np.array(joints, dtype=np.float64)
    if arr.shape != (NUM_JOINTS, 3):
        raise ConfigError(f"joints must have shape ({NUM_JOINTS}, 3), got {arr.shape}")
    return arr


def lost_mask(joints: NDArray[np.float64], state: JointState) -> NDArray[np.bool_]:
    """(17,) True for joints that carry no measurement: any NaN, or state ``lost``."""
    lost = ~np.all(np.isfinite(joints), axis=1)
    if state is not None:
        if len(state) != NUM_JOINTS:
            raise ConfigError(f"state must name {NUM_JOINTS} joint states, got {len(state)}")
        lost |= np.fromiter((s == "lost" for s in state), dtype=bool, count=NUM_JOINTS)
    return lost


def check_timestamp(t: float, last_t: float | None) -> float:
    """Return ``t - last_t`` (0 for the first frame); reject time that does not advance."""
    if not np.isfinite(t):
        raise TimestampError(f"frame time must be a finite number of seconds, got {t}")
    if last_t is None:
        return 0.0
    if t <= last_t:
        raise TimestampError(
            f"frame time {t:.6f} s is not after the previous frame's {last_t:.6f} s; "
            "pass strictly increasing capture times (or reset() the filter)"
        )
    return float(t - last_t)


def with_overrides(base: _Options, overrides: Mapping[str, Any], what: str) -> _Options:
    """``base`` (a frozen options dataclass) with keyword ``overrides`` replaced.

    The filter factories take options as keywords; a misspelt name must be an error
    naming the known ones (``what`` names the filter in it), not silently ignored.
    """
    known = {f.name for f in fields(base)}
    unknown = sorted(set(overrides) - known)
    if unknown:
        raise ConfigError(
            f"unknown {what} option(s) {', '.join(unknown)}; known: {', '.join(sorted(known))}"
        )
    return replace(base, **overrides)
