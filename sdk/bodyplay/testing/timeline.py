"""A timeline of motions for scripted players: clips, key poses and named gestures.

A :class:`Timeline` is a stack of segments on one time axis. Each segment yields a
skeleton pose vector for any time within it: a mocap clip (played from
``clip_start`` at ``speed``, optionally looped, rooted at the origin), key poses
(held, or interpolated with quaternion slerp), or a named gesture (a short key-pose
sequence or clip from a gesture table). Where segments overlap the one added last
wins; each segment fades in over ``blend`` seconds from whatever was below it and
fades back out after it ends; between segments the last pose is held. Because the
output is a pose vector per time step, the same timeline can drive the pose-level
session directly (:class:`~bodyplay.testing.player.ScriptedPlayer`) or, later, a
synthetic camera rendering the posed body for a real tracker.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.testing.poses import GESTURE_MOTIONS, KEY_POSES, resolve_pose

__all__ = ["Segment", "Timeline", "slerp_poses"]


def slerp_poses(a: NDArray[np.float64], b: NDArray[np.float64], w: float) -> NDArray[np.float64]:
    """Interpolate two pose vectors: lerp the root, slerp every node rotation (w in 0..1)."""
    if w <= 0.0:
        return a.copy()
    if w >= 1.0:
        return b.copy()
    out = np.empty_like(a)
    out[:3] = (1.0 - w) * a[:3] + w * b[:3]
    ra = Rotation.from_rotvec(a[3:].reshape(-1, 3))
    rb = Rotation.from_rotvec(b[3:].reshape(-1, 3))
    rel = (ra.inv() * rb).as_rotvec()
    out[3:] = (ra * Rotation.from_rotvec(rel * w)).as_rotvec().reshape(-1)
    return out


@dataclass(frozen=True, eq=False)
class Segment:
    """One motion on the timeline: ``sample(local_t) -> pose`` for local_t in 0..duration."""

    start: float
    duration: float
    sample: Callable[[float], NDArray[np.float64]]
    blend: float
    label: str

    @property
    def end(self) -> float:
        """When the segment stops."""
        return self.start + self.duration


def _motion_attr(name: str) -> Any:
    import importlib

    import bodyplay.motion as motion

    if hasattr(motion, name):
        return getattr(motion, name)
    for sub in ("clip", "retarget", "bvh"):
        try:
            mod = importlib.import_module(f"bodyplay.motion.{sub}")
        except ImportError:
            continue
        if hasattr(mod, name):
            return getattr(mod, name)
    raise ConfigError(f"bodyplay.motion has no {name}; this bodyplay cannot read motion clips")


class Timeline:
    """A script of motions for one player (see the module docstring).

    Builder methods return the timeline, so scripts chain::

        tl = (Timeline().hold("idle", 1.0).gesture("raise_right_hand")
              .clip("13_29", duration=3.0).gesture("punch_right", start=2.0))

    ``start=None`` appends a segment after the previous one's end (the cursor).
    ``base`` is the pose before the first segment; ``fps`` is the rate clips are
    loaded at (None keeps theirs).
    """

    def __init__(
        self,
        skeleton: Skeleton | None = None,
        *,
        blend: float = 0.2,
        base: Any = "idle",
        key_poses: Mapping[str, Mapping[str, Any]] | None = None,
        gestures: Mapping[str, Sequence[tuple[float, Any]] | str | Any] | None = None,
        fps: float | None = None,
    ) -> None:
        if blend < 0:
            raise ConfigError(f"blend must be >= 0 seconds, got {blend}")
        self.skeleton = skeleton or Skeleton()
        self.blend = float(blend)
        self.key_poses: dict[str, Mapping[str, Any]] = {**KEY_POSES, **(key_poses or {})}
        self.gesture_motions: dict[str, Any] = {**GESTURE_MOTIONS, **(gestures or {})}
        self.base = resolve_pose(base, self.skeleton, self.key_poses)
        self.fps = fps
        self.segments: list[Segment] = []
        self.cursor = 0.0

    # ---- building --------------------------------------------------------------------
    def _add(self, seg_start: float | None, duration: float, sample: Callable[[float], Any],
             blend: float | None, label: str) -> Timeline:
        start = self.cursor if seg_start is None else float(seg_start)
        if not (np.isfinite(start) and start >= 0):
            raise ConfigError(f"{label}: start must be >= 0 seconds, got {seg_start}")
        if not (np.isfinite(duration) and duration >= 0):
            raise ConfigError(f"{label}: duration must be >= 0 seconds, got {duration}")
        b = self.blend if blend is None else float(blend)
        self.segments.append(Segment(start, float(duration), sample, b, label))
        self.cursor = max(self.cursor, start + duration)
        return self

    def wait(self, seconds: float) -> Timeline:
        """Move the cursor on by ``seconds`` (the last pose is held meanwhile)."""
        if seconds < 0:
            raise ConfigError(f"wait needs seconds >= 0, got {seconds}")
        self.cursor += float(seconds)
        return self

    def hold(self, pose: Any, duration: float, *, start: float | None = None,
             blend: float | None = None) -> Timeline:
        """Hold a key pose (name, rotation dict or pose vector) for ``duration`` seconds."""
        q = resolve_pose(pose, self.skeleton, self.key_poses)
        label = pose if isinstance(pose, str) else "pose"
        return self._add(start, duration, lambda _t: q, blend, f"hold {label}")

    def keys(self, keys: Sequence[tuple[float, Any]], *, start: float | None = None,
             interpolate: bool = True, blend: float | None = None,
             label: str = "keys") -> Timeline:
        """Key poses at times relative to ``start``: interpolated (slerp) or stepped."""
        if not keys:
            raise ConfigError(f"{label}: needs at least one key pose")
        times = np.array([float(k[0]) for k in keys])
        if times[0] != 0.0 or np.any(np.diff(times) <= 0):
            raise ConfigError(f"{label}: key times must start at 0 and increase, got {times}")
        poses = [resolve_pose(p, self.skeleton, self.key_poses) for _, p in keys]

        def sample(t: float) -> NDArray[np.float64]:
            i = int(np.searchsorted(times, t, side="right")) - 1
            i = min(max(i, 0), len(poses) - 1)
            if i == len(poses) - 1 or not interpolate:
                return poses[i]
            w = (t - times[i]) / (times[i + 1] - times[i])
            return slerp_poses(poses[i], poses[i + 1], w)

        return self._add(start, float(times[-1]), sample, blend, label)

    def clip(self, clip: Any, *, start: float | None = None, duration: float | None = None,
             clip_start: float = 0.0, speed: float = 1.0, loop: bool = False,
             at: ArrayLike = (0.0, 0.0), rooted: bool = True,
             blend: float | None = None) -> Timeline:
        """Play a mocap clip (a MotionClip, a BVH path or a built-in clip name).

        ``rooted`` moves the clip horizontally so the pelvis of the first pose played
        is at ``at`` (x, z); ``loop`` repeats it until ``duration``.
        """
        if isinstance(clip, str) or hasattr(clip, "__fspath__"):
            clip = _motion_attr("load_clip")(clip, skeleton=self.skeleton, fps=self.fps)
        poses = np.asarray(clip.poses, dtype=np.float64).copy()
        if poses.shape[1] != self.skeleton.pose_dim:
            raise ConfigError("the clip's pose vectors do not fit the timeline's skeleton")
        fps = float(clip.fps)
        if not speed > 0:
            raise ConfigError(f"speed must be positive, got {speed}")
        length = (len(poses) - 1) / fps
        if not 0 <= clip_start <= length:
            raise ConfigError(f"clip_start {clip_start} is outside the clip (0..{length:.3f} s)")
        if rooted:  # the first pose played stands at `at`
            xz = np.asarray(at, dtype=float).reshape(2)
            frames = np.arange(len(poses)) / fps
            poses[:, 0] += xz[0] - np.interp(clip_start, frames, poses[:, 0])
            poses[:, 2] += xz[1] - np.interp(clip_start, frames, poses[:, 2])
        if duration is None:
            if loop:
                raise ConfigError("a looped clip needs a duration")
            duration = (length - clip_start) / speed

        def sample(t: float) -> NDArray[np.float64]:
            u = clip_start + t * speed
            u = u % length if loop and length > 0 else min(u, length)
            f = u * fps
            i = min(int(np.floor(f)), len(poses) - 1)
            if i >= len(poses) - 1:
                return poses[-1]
            return slerp_poses(poses[i], poses[i + 1], f - i)

        name = getattr(clip, "name", "clip")
        return self._add(start, float(duration), sample, blend, f"clip {name}")

    def gesture(self, name: str, *, start: float | None = None,
                blend: float | None = None, speed: float = 1.0,
                at: ArrayLike = (0.0, 0.0)) -> Timeline:
        """Perform a named gesture from the gesture table (key poses or a clip).

        ``at`` (x, z metres) moves it along the floor: a player who stepped aside
        performs the next gesture where they stand.
        """
        motion = self.gesture_motions.get(name)
        if motion is None:
            raise ConfigError(
                f"unknown gesture {name!r}; known: {', '.join(sorted(self.gesture_motions))}"
            )
        if isinstance(motion, str) or hasattr(motion, "poses"):
            return self.clip(motion, start=start, blend=blend, speed=speed, at=at)
        xz = np.asarray(at, dtype=np.float64).reshape(2)
        keys = []
        for t, p in motion:
            q = resolve_pose(p, self.skeleton, self.key_poses).copy()
            q[0] += xz[0]
            q[2] += xz[1]
            keys.append((float(t) / speed, q))
        return self.keys(keys, start=start, blend=blend, label=f"gesture {name}")

    # ---- evaluation ------------------------------------------------------------------
    @property
    def duration(self) -> float:
        """End of the last segment (or the cursor, if later)."""
        return max([self.cursor, *(s.end for s in self.segments)])

    def _eval(self, t: float, n: int) -> tuple[NDArray[np.float64], bool]:
        for i in range(n - 1, -1, -1):
            s = self.segments[i]
            if s.start <= t <= s.end:
                q = np.asarray(s.sample(t - s.start), dtype=np.float64)
                if s.blend > 0 and t < s.start + s.blend:
                    below, _ = self._eval(t, i)
                    q = slerp_poses(below, q, (t - s.start) / s.blend)
                return q, True
            if s.end < t < s.end + s.blend:
                below, active = self._eval(t, i)
                if active:
                    end_q = np.asarray(s.sample(s.duration), dtype=np.float64)
                    return slerp_poses(end_q, below, (t - s.end) / s.blend), True
        # Nothing active: hold the end of the latest segment finished before t.
        done = [s for s in self.segments[:n] if s.end < t]
        if not done:
            return self.base, False
        last = max(done, key=lambda s: s.end)
        return np.asarray(last.sample(last.duration), dtype=np.float64), False

    def pose_at(self, t: float) -> NDArray[np.float64]:
        """The pose vector at time ``t`` seconds."""
        if not np.isfinite(t):
            raise ConfigError(f"time must be finite, got {t}")
        return self._eval(float(t), len(self.segments))[0].copy()

    def poses(self, times: ArrayLike) -> NDArray[np.float64]:
        """(T, pose_dim) pose vectors at the given times."""
        return np.stack([self.pose_at(float(t)) for t in np.asarray(times).reshape(-1)])

    def joints_at(self, t: float) -> NDArray[np.float64]:
        """(17, 3) joint positions at ``t``."""
        return self.skeleton.joint_positions(self.pose_at(t))

    def active(self, t: float) -> list[str]:
        """Labels of the segments running at ``t`` (for test messages)."""
        return [s.label for s in self.segments if s.start <= t <= s.end]

