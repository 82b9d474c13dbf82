"""Pose sampling for the trackers' pose databases.

Both trackers look poses up in a database of rendered poses (80,000 for the colour
shirt, 57,136 for the silhouette tree). :func:`sample_poses` draws such poses from
three sources:

* frames of real motion capture (the built-in CMU clips, or any clips given), turned
  by a random yaw and a small tilt, so the database holds how people really move;
* joint-limit-aware random upper-body configurations (spine, clavicles, shoulders,
  elbows, neck) with a random 3-D orientation: yaw in ``yaw_range`` (the colour
  shirt tracker wants upper bodies roughly facing the camera, +-90 degrees) and a
  small tilt, so arm poses absent from the clips are covered too;
* linear blends between poses already drawn (rotation vectors are blended
  componentwise, which keeps them inside the box limits).

Every returned pose is within ``skeleton.limits``. With ``oversample > 1`` the
candidates are thinned to ``n`` by :func:`uniform_subsample` (greedy farthest-point
on joint positions), the paper's "uniformly sampling a large database".
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.joints import JOINT_INDEX, UPPER_BODY
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.motion.clip import MotionClip, list_builtin_clips, load_clip

__all__ = ["SAMPLING_MODES", "random_upper_body", "sample_poses", "uniform_subsample"]

SAMPLING_MODES = ("mixed", "clips", "upper_body")
"""``mixed``: clip frames + random upper bodies + blends; ``clips``: clip frames +
blends; ``upper_body``: random upper bodies + blends."""

# nodes the random upper-body configurations move, with how much of their range
_UPPER_RANGE = {
    "lumbar": 0.5,
    "thorax": 0.5,
    "neck": 0.4,
    "head": 0.4,
    "l_clavicle": 0.8,
    "r_clavicle": 0.8,
    "l_shoulder": 1.0,
    "r_shoulder": 1.0,
    "l_elbow": 1.0,
    "r_elbow": 1.0,
    "l_wrist": 0.5,
    "r_wrist": 0.5,
}


def _orient(
    skeleton: Skeleton,
    poses: NDArray[np.float64],
    rng: np.random.Generator,
    yaw_range: tuple[float, float],
    max_tilt: float,
) -> NDArray[np.float64]:
    """Apply a random yaw (about +Y) and tilt (about X and Z) to each pose's pelvis."""
    n = poses.shape[0]
    yaw = rng.uniform(yaw_range[0], yaw_range[1], n)
    tilt = rng.uniform(-max_tilt, max_tilt, (n, 2))
    R = Rotation.from_euler("YXZ", np.column_stack([yaw, tilt]))
    out = poses.copy()
    out[:, 3:6] = (R * Rotation.from_rotvec(poses[:, 3:6])).as_rotvec()
    return out


def _center(poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """Remove a clip's travel and heading: pelvis over the origin, facing +Z.

    The pelvis height and its tilt are kept; only the turn about +Y is removed, so
    that the random yaw that follows decides where the body faces.
    """
    out = poses.copy()
    out[:, 0] = 0.0
    out[:, 2] = 0.0
    R = Rotation.from_rotvec(poses[:, 3:6])
    fwd = R.apply([0.0, 0.0, 1.0])
    heading = np.arctan2(fwd[:, 0], fwd[:, 2])
    out[:, 3:6] = (Rotation.from_euler("Y", -heading[:, None]) * R).as_rotvec()
    return out


def random_upper_body(
    skeleton: Skeleton,
    n: int,
    rng: np.random.Generator,
    yaw_range: tuple[float, float] = (-np.pi / 2, np.pi / 2),
    max_tilt: float = 0.15,
) -> NDArray[np.float64]:
    """(n, pose_dim) random upper-body configurations within the joint limits.

    Each rotation component of the spine, neck, clavicles, shoulders, elbows and
    wrists is drawn uniformly in (a share of) its limit box; elbows bend uniformly
    over their whole range. Legs stay straight, the pelvis stands at its rest
    height, turned by a yaw in ``yaw_range`` (radians) and tilted by up to
    ``max_tilt``.
    """
    lo, hi = skeleton.limits
    q = np.tile(skeleton.rest_pose(), (n, 1))
    for name, share in _UPPER_RANGE.items():
        i = 3 + 3 * skeleton.node_index(name)
        a, b = lo[i : i + 3], hi[i : i + 3]
        mid = 0.5 * (a + b)
        half = 0.5 * (b - a) * share
        q[:, i : i + 3] = rng.uniform(mid - half, mid + half, (n, 3))
    return skeleton.clamp(_orient(skeleton, q, rng, yaw_range, max_tilt))


def _clip_frames(
    skeleton: Skeleton,
    clips: Sequence[str | Path | MotionClip],
    fps: float,
) -> NDArray[np.float64]:
    out = []
    for c in clips:
        if isinstance(c, MotionClip):
            clip = c if c.skeleton == skeleton else MotionClip(skeleton, c.poses, c.fps, c.name)
        else:
            clip = load_clip(c, skeleton, fps=fps)
        if clip.fps > fps:
            clip = clip.resample(fps)
        out.append(clip.poses)
    return np.concatenate(out, axis=0)


def uniform_subsample(
    skeleton: Skeleton,
    poses: NDArray[np.float64],
    n: int,
    rng: np.random.Generator,
    upper_body: bool = False,
) -> NDArray[np.intp]:
    """Indices of ``n`` poses spread evenly over pose space (greedy farthest-point).

    The distance between poses is the RMS distance of their joints relative to the
    pelvis (orientation included: renderings differ when the body turns); with
    ``upper_body`` only the first eleven joints count. Cost O(len(poses) * n).
    """
    poses = np.asarray(poses, dtype=np.float64)
    if not 0 < n <= len(poses):
        raise ConfigError(f"cannot select {n} of {len(poses)} poses")
    J = skeleton.joint_positions(poses)
    J = J - J[:, JOINT_INDEX["pelvis"] : JOINT_INDEX["pelvis"] + 1]
    if upper_body:
        J = J[:, : len(UPPER_BODY)]
    X = J.reshape(len(poses), -1).astype(np.float32)
    chosen = np.empty(n, dtype=np.intp)
    chosen[0] = int(rng.integers(len(poses)))
    d = np.sum((X - X[chosen[0]]) ** 2, axis=1)
    for k in range(1, n):
        chosen[k] = int(np.argmax(d))
        np.minimum(d, np.sum((X - X[chosen[k]]) ** 2, axis=1), out=d)
    return chosen


def sample_poses(
    skeleton: Skeleton,
    n: int,
    rng: np.random.Generator,
    clips: Sequence[str | Path | MotionClip] | None = None,
    mode: str = "mixed",
    yaw_range: tuple[float, float] = (-np.pi, np.pi),
    max_tilt: float = 0.15,
    clip_share: float = 0.5,
    blend_share: float = 0.2,
    clip_fps: float = 30.0,
    oversample: float = 1.0,
) -> NDArray[np.float64]:
    """(n, pose_dim) poses for a pose database, all within ``skeleton.limits``.

    ``clips`` are built-in clip names, BVH paths or :class:`MotionClip` objects
    (default: every built-in clip), read at ``clip_fps``. ``mode`` is one of
    :data:`SAMPLING_MODES`; in ``mixed`` mode ``clip_share`` of the non-blended
    poses are clip frames. ``blend_share`` of the poses are blends of two others.
    Orientation: yaw uniform in ``yaw_range`` (radians about +Y; use
    ``(-pi/2, pi/2)`` for a tracker that sees the front only), tilt up to
    ``max_tilt``. Root positions are over the origin. ``oversample > 1`` draws that
    many times ``n`` candidates and keeps ``n`` spread-out ones.
    """
    if mode not in SAMPLING_MODES:
        raise ConfigError(f"unknown sampling mode {mode!r}; choose one of {SAMPLING_MODES}")
    if n < 1:
        raise ConfigError(f"n must be at least 1, got {n}")
    if not yaw_range[0] <= yaw_range[1]:
        raise ConfigError(f"yaw_range must be (low, high) with low <= high, got {yaw_range}")
    for label, v in (("clip_share", clip_share), ("blend_share", blend_share)):
        if not 0.0 <= v <= 1.0:
            raise ConfigError(f"{label} must be within 0..1, got {v}")
    if not (max_tilt >= 0 and clip_fps > 0 and oversample >= 1):
        raise ConfigError("max_tilt must be >= 0, clip_fps > 0 and oversample >= 1")
    total = int(np.ceil(n * oversample))
    n_blend = int(round(total * blend_share)) if total > 1 else 0
    n_base = total - n_blend
    if mode == "clips":
        n_clip = n_base
    elif mode == "upper_body":
        n_clip = 0
    else:
        n_clip = int(round(n_base * clip_share))
    parts = []
    if n_clip:
        names = list(clips) if clips is not None else list(list_builtin_clips())
        if not names:
            raise ConfigError("no motion clips to sample from (no built-in clips installed)")
        frames = _clip_frames(skeleton, names, clip_fps)
        pick = frames[rng.integers(0, len(frames), n_clip)]
        pick = _orient(skeleton, _center(pick), rng, yaw_range, max_tilt)
        parts.append(skeleton.clamp(pick))
    if n_base - n_clip:
        parts.append(random_upper_body(skeleton, n_base - n_clip, rng, yaw_range, max_tilt))
    base = np.concatenate(parts, axis=0)
    if n_blend:
        a = base[rng.integers(0, len(base), n_blend)]
        b = base[rng.integers(0, len(base), n_blend)]
        # blend within the same orientation so the blend does not fold through +-pi
        b[:, 3:6] = a[:, 3:6]
        w = rng.uniform(0.0, 1.0, (n_blend, 1))
        base = np.concatenate([base, skeleton.clamp((1.0 - w) * a + w * b)], axis=0)
    base = base[rng.permutation(len(base))]
    if len(base) > n:
        base = base[uniform_subsample(skeleton, base, n, rng, upper_body=mode == "upper_body")]
    return base
