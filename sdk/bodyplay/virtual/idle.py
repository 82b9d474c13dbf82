"""Real mocap idle motion, looped seamlessly: the base every virtual player stands in.

:class:`IdleMotion` takes a calm stretch of a vendored CMU clip (by default the
first 0.8 s of trial 131_03, where the subject stands with the arms down, swaying
slightly, before setting off), turns it to face +Z at a chosen spot on the
floor, and plays it back and forth for ever. A plain loop would jump where the end
meets the start; playing it forwards then backwards never jumps, and the
turnarounds are eased (the playback speed follows ``clip(A cos phase, -1, 1)``, so
it is 1 most of the time and reverses smoothly over about a third of a second):
poses and their velocities are continuous everywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.rotations import matrix_to_rotvec, rotvec_to_matrix
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError

__all__ = ["IdleMotion", "DEFAULT_IDLE"]

DEFAULT_IDLE: tuple[str, float, float] = ("131_03", 0.0, 0.8)
"""(clip, start s, end s) of the default idle: CMU 131_03 before the subject sets off."""

# Turnaround sharpness: playback speed is clip(A cos(phase), -1, 1).
_EASE_A = 3.0
_TABLE = 2048


@dataclass(frozen=True, eq=False)
class _Warp:
    """Back-and-forth time warp: loop time -> clip time in [0, length]."""

    length: float
    period: float
    table: NDArray[np.float64]  # F(phase) / F(pi/2) on [-pi/2, pi/2], 0..1

    def __call__(self, t: float) -> float:
        phase = (2.0 * math.pi * t / self.period) % (2.0 * math.pi)  # 0..2pi
        # forward on [-pi/2, pi/2], backward on [pi/2, 3pi/2]
        phi = phase - 0.5 * math.pi  # -pi/2 .. 3pi/2
        if phi > 0.5 * math.pi:
            phi = math.pi - phi  # mirror: back down
        x = (phi + 0.5 * math.pi) / math.pi * (_TABLE - 1)
        return self.length * float(np.interp(x, np.arange(_TABLE), self.table))


def _make_warp(length: float) -> _Warp:
    phi = np.linspace(-0.5 * math.pi, 0.5 * math.pi, _TABLE)
    v = np.minimum(1.0, _EASE_A * np.cos(phi))
    f = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(phi))])
    integral = float(f[-1])
    # half a period covers the clip once: (P / 2pi) * integral = length
    period = 2.0 * math.pi * length / integral
    return _Warp(length, period, f / integral)


def _yaw_matrix(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


class IdleMotion:
    """A calm mocap segment played back and forth, facing +Z, centred on ``at`` (x, z).

    ``clip`` is a built-in clip name, a BVH path or a
    :class:`~bodyplay.motion.MotionClip` of ``skeleton``; ``start``/``end`` bound the
    calm stretch in the clip's seconds. ``facing`` turns the actor about the vertical
    (radians; 0 faces +Z). :meth:`pose_at` is a pure function of time.
    """

    def __init__(
        self,
        skeleton: Skeleton | None = None,
        *,
        clip: object = DEFAULT_IDLE[0],
        start: float = DEFAULT_IDLE[1],
        end: float = DEFAULT_IDLE[2],
        at: ArrayLike = (0.0, 0.0),
        facing: float = 0.0,
        fps: float = 60.0,
    ) -> None:
        from bodyplay.motion.clip import MotionClip, load_clip

        self.skeleton = skeleton or Skeleton()
        if not (math.isfinite(start) and math.isfinite(end) and end - start >= 0.2):
            raise ConfigError(f"the idle segment {start}..{end} s must last at least 0.2 s")
        if isinstance(clip, MotionClip):
            mc = clip if clip.skeleton == self.skeleton else None
            if mc is None:
                raise ConfigError("the idle clip was retargeted onto another skeleton")
            mc = mc.resample(fps)
        elif isinstance(clip, str) or hasattr(clip, "__fspath__"):
            mc = load_clip(clip, skeleton=self.skeleton, fps=fps)  # type: ignore[arg-type]
        else:
            raise ConfigError(f"idle clip must be a clip name, a BVH path or a MotionClip, "
                              f"got {type(clip).__name__}")
        if end > mc.duration + 1e-6:
            raise ConfigError(f"the idle segment ends at {end} s, after the clip "
                              f"({mc.duration:.2f} s)")
        seg = mc.slice(start, end - start)
        poses = seg.poses.copy()
        self.fps = float(seg.fps)
        xz = np.asarray(at, dtype=np.float64).reshape(2)
        self.at = xz
        self.facing = float(facing)
        self.poses = self._normalize(poses, xz, float(facing))
        self.source = (getattr(mc, "name", "clip"), float(start), float(end))
        self._warp = _make_warp((len(self.poses) - 1) / self.fps)

    def _normalize(
        self, poses: NDArray[np.float64], at: NDArray[np.float64], facing: float
    ) -> NDArray[np.float64]:
        """Turn the segment to face ``facing`` and centre its mean pelvis on ``at``."""
        j = self.skeleton.joint_positions(poses)
        across = (j[:, JOINT_INDEX["l_hip"]] - j[:, JOINT_INDEX["r_hip"]]).mean(0)
        across += (j[:, JOINT_INDEX["l_shoulder"]] - j[:, JOINT_INDEX["r_shoulder"]]).mean(0)
        # facing direction = up x across (person's left is +X when facing +Z)
        fwd = np.cross(across, [0.0, 1.0, 0.0])
        yaw_now = math.atan2(fwd[0], fwd[2])
        turn = _yaw_matrix(facing - yaw_now)
        out = poses.copy()
        centre = poses[:, [0, 2]].mean(0)
        rel = poses[:, :3].copy()
        rel[:, 0] -= centre[0]
        rel[:, 2] -= centre[1]
        rel = rel @ turn.T
        out[:, 0] = rel[:, 0] + at[0]
        out[:, 1] = rel[:, 1]
        out[:, 2] = rel[:, 2] + at[1]
        out[:, 3:6] = matrix_to_rotvec(turn[None] @ rotvec_to_matrix(poses[:, 3:6]))
        return out

    @property
    def period(self) -> float:
        """Seconds of one back-and-forth cycle."""
        return self._warp.period

    def clip_time(self, t: float) -> float:
        """Seconds into the segment that loop time ``t`` shows."""
        return self._warp(t)

    def pose_at(self, t: float) -> NDArray[np.float64]:
        """The idle pose vector at time ``t`` seconds (any real t; periodic)."""
        if not math.isfinite(t):
            raise ConfigError(f"time must be finite, got {t}")
        from bodyplay.testing.timeline import slerp_poses

        f = self._warp(float(t)) * self.fps
        i = min(int(math.floor(f)), len(self.poses) - 2)
        return slerp_poses(self.poses[i], self.poses[i + 1], f - i)

    def poses_at(self, times: ArrayLike) -> NDArray[np.float64]:
        """(T, pose_dim) idle poses at ``times``."""
        return np.stack([self.pose_at(float(t)) for t in np.asarray(times).reshape(-1)])
