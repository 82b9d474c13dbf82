"""Motion clips: pose vectors over time for one skeleton, and the built-in clips.

A :class:`MotionClip` is what retargeting produces and what the synthetic actor,
the pose samplers and ``bodyplay export`` consume: ``poses[t]`` is the pose vector
at time ``t / fps``. Clips resample (spherical interpolation of every rotation,
linear of the root), slice by time and interpolate at any instant.

The CMU clips (free for any use) ship with the package, gzip-compressed, under
``bodyplay/assets/mocap``; ``load_clip("13_29")`` finds them by name.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation, Slerp

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError

__all__ = ["MotionClip", "builtin_clip_path", "list_builtin_clips", "load_clip"]


@dataclass(frozen=True, eq=False)
class MotionClip:
    """Pose vectors ``poses`` (T, pose_dim) of ``skeleton`` sampled at ``fps``.

    ``source_joints`` (T, 17, 3), when the clip came from motion capture, holds the
    source's joints normalized to the skeleton's height (Y up, floor at 0): the
    reference the retargeted poses are measured against.
    """

    skeleton: Skeleton
    poses: NDArray[np.float64]
    fps: float
    name: str = "clip"
    source_joints: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        q = np.asarray(self.poses, dtype=np.float64)
        if q.ndim != 2 or q.shape[1] != self.skeleton.pose_dim or q.shape[0] < 1:
            raise ConfigError(
                f"a MotionClip needs poses of shape (T >= 1, {self.skeleton.pose_dim}), "
                f"got {np.shape(self.poses)}"
            )
        if not np.all(np.isfinite(q)):
            raise ConfigError(f"clip {self.name!r} has NaN or infinite pose values")
        if not (np.isfinite(self.fps) and self.fps > 0):
            raise ConfigError(f"fps must be positive, got {self.fps}")
        if self.source_joints is not None and np.shape(self.source_joints) != (q.shape[0], 17, 3):
            raise ConfigError(
                f"source_joints must have shape ({q.shape[0]}, 17, 3), "
                f"got {np.shape(self.source_joints)}"
            )
        object.__setattr__(self, "poses", q)

    @property
    def num_frames(self) -> int:
        """Number of poses."""
        return int(self.poses.shape[0])

    @property
    def times(self) -> NDArray[np.float64]:
        """(T,) time of each pose in seconds, starting at 0."""
        return np.arange(self.num_frames) / self.fps

    @property
    def duration(self) -> float:
        """Seconds from the first to the last pose."""
        return (self.num_frames - 1) / self.fps

    def __len__(self) -> int:
        return self.num_frames

    def joints(self) -> NDArray[np.float64]:
        """(T, 17, 3) joint positions by forward kinematics."""
        return self.skeleton.joint_positions(self.poses)

    def _interp(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """Poses at times t (clamped to the clip): Slerp rotations, lerp the root."""
        times = self.times
        t = np.clip(t, 0.0, times[-1])
        if self.num_frames == 1:
            return np.repeat(self.poses, len(t), axis=0)
        n = self.skeleton.num_nodes
        out = np.empty((len(t), self.skeleton.pose_dim))
        for c in range(3):
            out[:, c] = np.interp(t, times, self.poses[:, c])
        rv = self.poses[:, 3:].reshape(self.num_frames, n, 3)
        for j in range(n):
            if not np.any(rv[:, j]):
                out[:, 3 + 3 * j : 6 + 3 * j] = 0.0
                continue
            slerp = Slerp(times, Rotation.from_rotvec(rv[:, j]))
            r = slerp(t).as_rotvec()
            out[:, 3 + 3 * j : 6 + 3 * j] = r
        return out

    def at(self, t: float) -> NDArray[np.float64]:
        """The pose at time ``t`` seconds, interpolated (clamped to the clip's span)."""
        if not np.isfinite(t):
            raise ConfigError(f"time must be finite, got {t}")
        return self._interp(np.array([float(t)]))[0]

    def resample(self, fps: float) -> MotionClip:
        """The clip at another frame rate (same duration, up to one frame period)."""
        if not (np.isfinite(fps) and fps > 0):
            raise ConfigError(f"fps must be positive, got {fps}")
        n = int(np.floor(self.duration * fps + 1e-9)) + 1
        t = np.arange(n) / fps
        src = None
        if self.source_joints is not None:
            flat = self.source_joints.reshape(self.num_frames, -1)
            src = np.stack([np.interp(t, self.times, flat[:, c]) for c in range(flat.shape[1])], 1)
            src = src.reshape(n, 17, 3)
        return replace(self, poses=self._interp(t), fps=float(fps), source_joints=src)

    def slice(self, start_s: float, seconds: float | None = None) -> MotionClip:
        """The frames from ``start_s`` for ``seconds`` (to the end when None)."""
        if not np.isfinite(start_s) or start_s < 0 or start_s > self.duration:
            raise ConfigError(f"start {start_s} s is outside the clip (0 .. {self.duration:.3f} s)")
        if seconds is not None and not (np.isfinite(seconds) and seconds > 0):
            raise ConfigError(f"seconds must be positive, got {seconds}")
        a = int(round(start_s * self.fps))
        b = self.num_frames if seconds is None else a + int(round(seconds * self.fps)) + 1
        b = min(b, self.num_frames)
        src = None if self.source_joints is None else self.source_joints[a:b]
        return replace(self, poses=self.poses[a:b], source_joints=src)


# ---- built-in clips ---------------------------------------------------------------


def _assets() -> Path:
    return Path(str(resources.files("bodyplay") / "assets" / "mocap"))


def list_builtin_clips() -> list[str]:
    """Names of the motion clips shipped with bodyplay (e.g. ``"13_29"``)."""
    d = _assets()
    if not d.is_dir():
        return []
    return sorted(p.name[: -len(".bvh.gz")] for p in d.glob("*.bvh.gz"))


def builtin_clip_path(name: str) -> Path:
    """Path of a built-in clip's ``.bvh.gz`` file, with a clear error for unknown names."""
    path = _assets() / f"{name}.bvh.gz"
    if not path.is_file():
        raise ConfigError(
            f"no built-in motion clip {name!r}; built-in clips are "
            f"{', '.join(list_builtin_clips()) or '(none installed)'}"
        )
    return path


def load_clip(
    path: str | Path, skeleton: Skeleton | None = None, fps: float | None = None
) -> MotionClip:
    """Read a BVH file (or a built-in clip by name) and retarget it onto ``skeleton``.

    ``fps`` resamples the result; by default it keeps the source frame rate.
    """
    from bodyplay.motion.bvh import read_bvh
    from bodyplay.motion.retarget import retarget

    p = Path(path)
    if not p.exists() and isinstance(path, str) and "/" not in path and "." not in p.name:
        p = builtin_clip_path(path)
    if fps is not None and not (np.isfinite(fps) and fps > 0):
        raise ConfigError(f"fps must be positive, got {fps}")
    bvh = read_bvh(p)
    # retarget only the frames a lower output rate needs (every step-th), then resample
    step = max(1, int(np.floor(bvh.fps / fps + 1e-6))) if fps is not None else 1
    clip = retarget(bvh, skeleton or Skeleton(), frames=slice(None, None, step))
    return clip if fps is None or abs(clip.fps - fps) < 1e-9 else clip.resample(fps)
