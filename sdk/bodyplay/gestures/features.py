"""Body-relative joint features that gesture definitions test, and the running calibration.

Gestures must work for a child and for a tall adult, near the camera or far, so every
length is divided by the person's *torso length* (pelvis to neck, about 0.5 m for a
1.75 m adult) and every speed is in torso lengths per second. Heights of the pelvis
are compared with the *standing* pelvis height, learned while the person stands
upright (both knees straighter than 160 degrees, both ankles near the floor).

Directions are the person's own: ``up`` is world +Y, ``left`` the horizontal
direction from the right hip to the left hip averaged over the calibration time
constant (so that a stance change or a lunge that turns the hips does not turn
"left" with them), ``forward`` = left x up (where the person faces). Features of
joints that are missing (NaN) are NaN, and a condition on
a NaN feature is false.

The catalogue (``FEATURES``) maps each feature name to its argument kinds; see
docs/gestures.md for the meaning and unit of each.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.optiontypes import check_option_types

__all__ = ["FEATURES", "FeatureSpec", "BodyCalibration", "FeatureFrame", "CalibrationOptions"]

_P, _N = JOINT_INDEX["pelvis"], JOINT_INDEX["neck"]
_LH, _RH = JOINT_INDEX["l_hip"], JOINT_INDEX["r_hip"]
_LS, _RS = JOINT_INDEX["l_shoulder"], JOINT_INDEX["r_shoulder"]
_LK, _RK = JOINT_INDEX["l_knee"], JOINT_INDEX["r_knee"]
_LA, _RA = JOINT_INDEX["l_ankle"], JOINT_INDEX["r_ankle"]
_LEGS = [JOINT_INDEX[n] for n in ("l_hip", "l_knee", "l_ankle", "r_hip", "r_knee", "r_ankle")]


@dataclass(frozen=True)
class CalibrationOptions:
    """How the running body calibration adapts.

    ``time_constant`` (s): smoothing of the torso length and standing pelvis height.
    ``straight_knee`` (deg): knee angle above which a leg counts as straight.
    ``floor_margin`` (torso lengths): how close to the floor level both ankles must
    be for the person to count as standing. ``floor_rise`` (m/s): how fast the floor
    estimate (a leaky minimum of ankle heights) may rise. ``velocity_window`` (s):
    span over which joint velocities are measured (longer is less noisy).
    ``shift_window`` (s): span over which ``shift_*`` displacements are measured.
    ``upright_band`` (fraction of the standing pelvis height): with the legs unseen,
    frames whose pelvis is this close to the standing height count as standing.
    """

    time_constant: float = 2.0
    straight_knee: float = 160.0
    floor_margin: float = 0.1
    floor_rise: float = 0.02
    velocity_window: float = 0.1
    shift_window: float = 0.5
    upright_band: float = 0.1

    def __post_init__(self) -> None:
        check_option_types(self)


class BodyCalibration:
    """Running estimates of torso length, floor level and standing pelvis height.

    Updated every frame from the joints; all values start unknown (NaN) and are set
    by the first frame that shows them.
    """

    def __init__(self, options: CalibrationOptions | None = None) -> None:
        self.options = options if options is not None else CalibrationOptions()
        self.torso = float("nan")
        self.ankle_floor = float("nan")
        self.standing_pelvis = float("nan")
        self.left = np.full(3, np.nan)
        self._last_t: float | None = None

    def update(self, t: float, joints: NDArray[np.float64]) -> None:
        """Fold one frame into the estimates (joints (17, 3), NaN where missing)."""
        o = self.options
        dt = 0.0 if self._last_t is None else max(t - self._last_t, 0.0)
        self._last_t = t
        a = 1.0 if dt == 0.0 else 1.0 - np.exp(-dt / o.time_constant)
        torso = float(np.linalg.norm(joints[_N] - joints[_P]))
        if np.isfinite(torso) and torso > 0:
            self.torso = torso if not np.isfinite(self.torso) else self.torso + a * (
                torso - self.torso
            )
        left = _left_axis(joints)
        if np.all(np.isfinite(left)):
            if not np.all(np.isfinite(self.left)):
                self.left = left
            else:
                m = self.left + a * (left - self.left)
                self.left = m / max(float(np.linalg.norm(m)), 1e-9)
        ank = float(np.fmin(joints[_LA, 1], joints[_RA, 1]))
        if np.isfinite(ank):
            rise = o.floor_rise * dt
            self.ankle_floor = (
                ank if not np.isfinite(self.ankle_floor) else min(self.ankle_floor + rise, ank)
            )
        pel = float(joints[_P, 1])
        if not np.isfinite(pel):
            return
        if not np.isfinite(self.standing_pelvis):
            self.standing_pelvis = pel
            return
        if self._upright(joints):
            self.standing_pelvis += a * (pel - self.standing_pelvis)

    @property
    def floor(self) -> float:
        """The floor level: the ankles' leaky minimum, or the world floor (Y = 0) for a
        source that never shows the legs (an upper-body tracker in a calibrated room)."""
        return self.ankle_floor if np.isfinite(self.ankle_floor) else 0.0

    def _upright(self, j: NDArray[np.float64]) -> bool:
        o = self.options
        if not np.all(np.isfinite(j[[_LK, _RK, _LA, _RA]])):
            # Legs unseen: standing means the pelvis is within upright_band of the
            # standing height (a crouch drops it by 25% or more, so never counts).
            s = self.standing_pelvis - self.floor
            return bool(j[_P, 1] > self.standing_pelvis - o.upright_band * s)
        knees = (_angle(j[_LH], j[_LK], j[_LA]), _angle(j[_RH], j[_RK], j[_RA]))
        if not all(np.isfinite(k) and k > o.straight_knee for k in knees):
            return False
        margin = o.floor_margin * self.torso
        return bool(max(j[_LA, 1], j[_RA, 1]) < self.ankle_floor + margin)


def _left_axis(j: NDArray[np.float64]) -> NDArray[np.float64]:
    """Horizontal unit vector from the right to the left hip (shoulders if no hips)."""
    left = j[_LH] - j[_RH]
    if not np.all(np.isfinite(left)):
        left = j[_LS] - j[_RS]
    left = np.array([left[0], 0.0, left[2]])
    n = float(np.linalg.norm(left))
    return left / n if n > 0 else np.full(3, np.nan)


def _angle(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]) -> float:
    u, v = a - b, c - b
    nu, nv = float(np.linalg.norm(u)), float(np.linalg.norm(v))
    if not (nu > 0 and nv > 0):
        return float("nan")
    return float(np.degrees(np.arccos(np.clip(np.dot(u, v) / (nu * nv), -1.0, 1.0))))


class FeatureFrame:
    """The features of one frame: evaluates (and caches) ``FEATURES`` by name and args."""

    def __init__(
        self,
        joints: NDArray[np.float64],
        velocity: NDArray[np.float64],
        calib: BodyCalibration,
        shift: NDArray[np.float64] | None = None,
    ) -> None:
        self.joints = joints
        self.velocity = velocity
        self.shift = shift if shift is not None else np.full_like(joints, np.nan)
        self.calib = calib
        self._cache: dict[tuple[str, tuple[str, ...]], float] = {}
        self.left = calib.left
        self.legs_unseen = bool(np.all(np.isnan(joints[_LEGS])))
        """No leg joint (hips, knees, ankles) is known in this frame."""
        self.up = np.array([0.0, 1.0, 0.0])
        self.forward = np.cross(self.left, self.up)

    def value(self, name: str, args: tuple[str, ...]) -> float:
        """Value of feature ``name`` with joint arguments ``args`` (NaN if unknown)."""
        key = (name, args)
        if key not in self._cache:
            self._cache[key] = float(FEATURES[name].compute(self, [JOINT_INDEX[a] for a in args]))
        return self._cache[key]


@dataclass(frozen=True)
class FeatureSpec:
    """A feature: how many joint arguments it takes, its unit, what it measures."""

    arity: int
    unit: str
    doc: str
    compute: Callable[[FeatureFrame, list[int]], float]


def _height(f: FeatureFrame, a: list[int]) -> float:
    return float((f.joints[a[0], 1] - f.calib.floor) / f.calib.torso)


def _above(f: FeatureFrame, a: list[int]) -> float:
    return float((f.joints[a[0], 1] - f.joints[a[1], 1]) / f.calib.torso)


def _distance(f: FeatureFrame, a: list[int]) -> float:
    return float(np.linalg.norm(f.joints[a[0]] - f.joints[a[1]]) / f.calib.torso)


def _lateral(f: FeatureFrame, a: list[int]) -> float:
    return float(np.dot(f.joints[a[0]] - f.joints[a[1]], f.left) / f.calib.torso)


def _ahead(f: FeatureFrame, a: list[int]) -> float:
    return float(np.dot(f.joints[a[0]] - f.joints[a[1]], f.forward) / f.calib.torso)


def _angle_f(f: FeatureFrame, a: list[int]) -> float:
    return _angle(f.joints[a[0]], f.joints[a[1]], f.joints[a[2]])


def _elevation(f: FeatureFrame, a: list[int]) -> float:
    d = f.joints[a[1]] - f.joints[a[0]]
    n = float(np.linalg.norm(d))
    if not n > 0:
        return float("nan")
    return float(np.degrees(np.arccos(np.clip(-d[1] / n, -1.0, 1.0))))


def _pelvis_drop(f: FeatureFrame, a: list[int]) -> float:
    s = f.calib.standing_pelvis - f.calib.floor
    if not s > 0:  # no height learned yet (or a degenerate pose): no drop to measure
        return float("nan")
    return float((f.calib.standing_pelvis - f.joints[_P, 1]) / s)


def _pelvis_rise(f: FeatureFrame, a: list[int]) -> float:
    return float((f.joints[_P, 1] - f.calib.standing_pelvis) / f.calib.torso)


def _feet_lift(f: FeatureFrame, a: list[int]) -> float:
    low = min(f.joints[_LA, 1], f.joints[_RA, 1])  # NaN propagates
    return float((low - f.calib.ankle_floor) / f.calib.torso)


def _speed(f: FeatureFrame, a: list[int]) -> float:
    return float(np.linalg.norm(f.velocity[a[0]]) / f.calib.torso)


def _vel(axis: str) -> Callable[[FeatureFrame, list[int]], float]:
    def compute(f: FeatureFrame, a: list[int]) -> float:
        return float(np.dot(f.velocity[a[0]], getattr(f, axis)) / f.calib.torso)

    return compute


def _shift(axis: str) -> Callable[[FeatureFrame, list[int]], float]:
    def compute(f: FeatureFrame, a: list[int]) -> float:
        return float(np.dot(f.shift[a[0]], getattr(f, axis)) / f.calib.torso)

    return compute


FEATURES: dict[str, FeatureSpec] = {
    "height": FeatureSpec(1, "torso", "height of a joint above the floor level", _height),
    "above": FeatureSpec(2, "torso", "how far joint a is above joint b (negative: below)", _above),
    "distance": FeatureSpec(2, "torso", "distance between two joints", _distance),
    "lateral": FeatureSpec(2, "torso", "offset of a from b towards the person's left", _lateral),
    "ahead": FeatureSpec(2, "torso", "offset of a from b in the facing direction", _ahead),
    "angle": FeatureSpec(3, "deg", "angle at b between b->a and b->c (elbow, knee)", _angle_f),
    "elevation": FeatureSpec(
        2, "deg", "angle of a->b from straight down (0 hanging, 90 level, 180 up)", _elevation
    ),
    "pelvis_drop": FeatureSpec(
        0, "fraction", "pelvis lowering as a fraction of the standing pelvis height", _pelvis_drop
    ),
    "pelvis_rise": FeatureSpec(
        0, "torso", "pelvis height above the standing pelvis height", _pelvis_rise
    ),
    "feet_lift": FeatureSpec(
        0, "torso", "height of the lower ankle above the floor level", _feet_lift
    ),
    "speed": FeatureSpec(1, "torso/s", "speed of a joint", _speed),
    "vel_up": FeatureSpec(1, "torso/s", "upward velocity of a joint", _vel("up")),
    "vel_left": FeatureSpec(1, "torso/s", "velocity towards the person's left", _vel("left")),
    "vel_forward": FeatureSpec(1, "torso/s", "velocity in the facing direction", _vel("forward")),
    "shift_left": FeatureSpec(
        1, "torso", "displacement towards the person's left over the shift window", _shift("left")
    ),
    "shift_forward": FeatureSpec(
        1, "torso", "displacement in the facing direction over the shift window", _shift("forward")
    ),
    "shift_up": FeatureSpec(1, "torso", "upward displacement over the shift window", _shift("up")),
}
"""Every feature a gesture condition may use, by name."""


class VelocityTracker:
    """Joint velocities (or displacements) over a short window of past frames."""

    def __init__(self, window: float) -> None:
        self.window = window
        self._hist: deque[tuple[float, NDArray[np.float64]]] = deque()

    def update(self, t: float, joints: NDArray[np.float64]) -> NDArray[np.float64]:
        """Add a frame; return (17, 3) velocities in m/s (NaN until two frames are seen)."""
        self._hist.append((t, joints))
        while len(self._hist) > 2 and t - self._hist[1][0] >= self.window:
            self._hist.popleft()
        t0, j0 = self._hist[0]
        if t - t0 <= 0:
            return np.full_like(joints, np.nan)
        return (joints - j0) / (t - t0)

    def displacement(self, t: float, joints: NDArray[np.float64]) -> NDArray[np.float64]:
        """Add a frame; return (17, 3) displacements in m since ``window`` seconds ago."""
        self._hist.append((t, joints))
        while len(self._hist) > 2 and t - self._hist[1][0] >= self.window:
            self._hist.popleft()
        return joints - self._hist[0][1]

    def reset(self) -> None:
        """Forget the history."""
        self._hist.clear()
