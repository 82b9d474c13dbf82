"""The cloth mirror on the kit: a garment simulated on the tracked body, seen in a mirror.

:class:`ClothMirrorGame` is a :class:`bodyplay.app.Game`. Every new pose steps the
cloth (:class:`bodyplay.cloth.Cloth`) in fixed 1/60 s steps from the previous pose's
time to this one's, the joints interpolated in between (so a 30 fps camera still
moves the body smoothly); joints the tracker reports lost are held where they were.
The scene is the view of a mirror: the view is the calibrated camera that films the
player (for pose input without one: 3.6 m in front of where the player first stood),
and the picture is flipped left-right. The avatar
is drawn as the very capsules the cloth collides with, so what you see is what the
cloth feels. The embedded default input is a synthetic camera filming the actor
doing the CMU 13_29 jumping jacks, tracked.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from bodyplay.app import Game, GameContext, GameOptions, Scene
from bodyplay.cloth import GARMENTS, Cloth, ClothOptions, body_frames, garment
from bodyplay.errors import ConfigError

__all__ = ["ClothMirrorGame", "mirror_timeline", "CLOTH_HZ"]

CLOTH_HZ = 60.0
"""Cloth steps per second of capture time."""

_SKIN = (0.86, 0.70, 0.58)
_HEAD = 0  # index of the head capsule (a sphere) in bodyplay.cloth.CAPSULE_NAMES


def mirror_timeline(seconds: float | None, clip: str = "13_29") -> Any:
    """The virtual player's script: a mocap clip (jumping jacks) looped for ``seconds``."""
    from bodyplay.testing import Timeline

    duration = 20.0 if seconds is None else float(seconds)
    return Timeline().clip(clip, duration=duration, loop=True, at=(0.0, 0.0))


class ClothMirrorGame(Game):
    """The avatar in a simulated garment (``robe``, ``cape`` or ``skirt``), mirrored."""

    name = "cloth_mirror"
    title = "bodyplay cloth mirror"
    filters = ("one_euro",)

    def __init__(self, garment_name: str = "robe", wind: float = 0.0,
                 cloth_options: ClothOptions | None = None, clip: str = "13_29") -> None:
        if garment_name not in GARMENTS:
            raise ConfigError(f"unknown garment {garment_name!r}; choose one of "
                              f"{', '.join(GARMENTS)}")
        if not (np.isfinite(wind) and 0.0 <= wind <= 30.0):
            raise ConfigError(f"wind must be 0..30 m/s, got {wind}")
        self.garment_name = garment_name
        base = cloth_options or ClothOptions()
        opts = base.__dict__ | {"wind": (0.0, 0.0, float(wind))} if wind else base.__dict__
        self.cloth_options = ClothOptions(**opts)
        self.clip = clip
        self.cloth: Cloth | None = None
        self._last_t: float | None = None
        self._last_joints: NDArray[np.float64] | None = None
        self._stats: dict[str, list[float]] = {}
        self._teleports = 0
        self._lost_steps = 0
        self._view: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None

    # ---- the kit's hooks -------------------------------------------------------------
    def virtual_player(self, options: GameOptions) -> Any:
        """The actor doing jumping jacks, filmed by the synthetic camera(s)."""
        from bodyplay.virtual import TimelineController, VirtualPlayerSource

        controller = TimelineController(mirror_timeline(options.seconds, self.clip))
        return VirtualPlayerSource(controller, cameras=options.cameras, fps=options.video_fps,
                                   size=(options.width, options.height), seed=options.seed,
                                   seconds=options.seconds)

    def setup(self, ctx: GameContext) -> None:
        """A fresh garment on nobody yet (it dresses the first pose)."""
        opts = self.cloth_options
        if getattr(getattr(ctx, "session", None), "cameras", ()):
            # tracked input: limbs the tracker sinks into the torso are moved out
            opts = ClothOptions(**(opts.__dict__ | {"separate_limbs": True}))
        self.cloth = Cloth(garment(self.garment_name), opts)
        self._last_t = None
        self._last_joints = None
        self._stats = {k: [] for k in ("step_ms", "max_strain", "mean_strain",
                                       "max_penetration", "kinetic_energy")}
        self._teleports = 0
        self._lost_steps = 0
        self._view = None

    def restart(self, ctx: GameContext) -> None:
        """Take the garment off and put it on again."""
        self.setup(ctx)

    def update(self, ctx: GameContext, dt: float) -> None:
        """Step the cloth up to the latest pose's time (fixed 1/60 s steps)."""
        pose = ctx.pose
        if self.cloth is None or pose is None:
            return
        if self._last_t is not None and pose.t <= self._last_t:
            return
        joints = np.array(pose.joints, dtype=np.float64)
        joints[np.array([s == "lost" for s in pose.state], dtype=bool)] = np.nan
        if self._last_t is None or self._last_joints is None:
            self._step(1.0 / CLOTH_HZ, joints)
        else:
            n = max(1, int(round((pose.t - self._last_t) * CLOTH_HZ)))
            n = min(n, 30)  # after a long gap the cloth catches up in at most 0.5 s
            prev = self._last_joints
            for k in range(1, n + 1):
                a = k / n
                mix = prev + (joints - prev) * a
                # a joint known on one side only takes that side's value
                mix = np.where(np.isnan(prev), joints, np.where(np.isnan(joints), prev, mix))
                self._step(1.0 / CLOTH_HZ, mix if k < n else joints)
        self._last_t = pose.t
        self._last_joints = joints

    def _step(self, dt: float, joints: NDArray[np.float64]) -> None:
        assert self.cloth is not None
        r = self.cloth.step(dt, joints)
        if not r.dressed:
            return
        s = self._stats
        s["step_ms"].append(1000.0 * r.seconds)
        s["max_strain"].append(r.max_strain)
        s["mean_strain"].append(r.mean_strain)
        s["max_penetration"].append(r.max_penetration)
        s["kinetic_energy"].append(r.kinetic_energy)
        self._teleports += int(r.teleported)
        self._lost_steps += int(r.lost)

    def draw(self, ctx: GameContext, scene: Scene) -> None:
        """The mirror: the body's capsules and the garment, seen from the camera, flipped."""
        cams = getattr(ctx.session, "cameras", ()) if hasattr(ctx, "session") else ()
        if cams:  # a mirror shows the player from where the camera stands
            scene.camera = cams[0].with_size(ctx.options.width, ctx.options.height)
        else:
            eye, target = self._mirror_view()
            scene.look(eye=eye, target=target, hfov_deg=50.0)
        scene.mirror = True
        scene.sky = (0.16, 0.17, 0.2)
        scene.floor()
        cloth = self.cloth
        caps = None if cloth is None else cloth.capsules()
        if cloth is None or caps is None:
            super().draw(ctx, scene)
            scene.text("waiting for the player...", (12, 30))
            return
        for c in range(len(caps.radius)):
            if c == _HEAD:
                scene.sphere(caps.a[c], float(caps.radius[c]), _SKIN)
            else:
                scene.capsule(caps.a[c], caps.b[c], float(caps.radius[c]), _SKIN)
        scene.mesh(cloth.positions, cloth.faces, cloth.garment.color, two_sided=True)
        body = cloth.body_joints
        if body is not None:
            scene.shadow((float(body[0, 0]), 0.0, float(body[0, 2])), 0.45)
        s = self._stats
        if s["step_ms"]:
            scene.text(f"{self.garment_name}  {cloth.num_particles} particles  "
                       f"cloth {s['step_ms'][-1]:.1f} ms", (12, 26), size=0.6)
            scene.text(f"stretch {100 * s['mean_strain'][-1]:.1f}%  "
                       f"inside body {1000 * s['max_penetration'][-1]:.1f} mm", (12, 50),
                       size=0.6)

    def _mirror_view(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """Eye and target of the mirror: 3.6 m in front of where the player first stood,
        facing the way the player first faced (fixed for the run)."""
        if self._view is None:
            if self.cloth is None or self.cloth.body_joints is None:
                return (0.0, 1.25, 3.6), (0.0, 0.95, 0.0)
            j = self.cloth.body_joints
            _, rots = body_frames(j)
            fwd = rots[0][:, 2].copy()
            fwd[1] = 0.0
            n = float(np.linalg.norm(fwd))
            fwd = fwd / n if n > 1e-6 else np.array([0.0, 0.0, 1.0])
            p = j[0]
            eye = (float(p[0] + 3.6 * fwd[0]), 1.25, float(p[2] + 3.6 * fwd[2]))
            self._view = (eye, (float(p[0]), 0.95, float(p[2])))
        return self._view

    def summary(self, ctx: GameContext) -> dict[str, Any]:
        """Cloth figures: step time, constraint error, penetration, energy."""
        s = {k: np.asarray(v, dtype=np.float64) for k, v in self._stats.items()}
        n = len(s["step_ms"])
        cloth = self.cloth

        def stats(a: NDArray[np.float64], scale: float = 1.0) -> dict[str, float]:
            if len(a) == 0:
                return {}
            return {"median": round(float(np.median(a)) * scale, 4),
                    "p95": round(float(np.percentile(a, 95)) * scale, 4),
                    "max": round(float(a.max()) * scale, 4)}

        return {
            "garment": self.garment_name,
            "particles": 0 if cloth is None else cloth.num_particles,
            "constraints": [] if cloth is None else list(cloth.num_constraints),
            "cloth_steps": n,
            "cloth_hz": CLOTH_HZ,
            "cloth_step_ms": stats(s["step_ms"]),
            "constraint_error": {"max_strain": stats(s["max_strain"]),
                                 "mean_strain": stats(s["mean_strain"])},
            "penetration_mm": {**stats(s["max_penetration"], 1000.0),
                               "steps_over_10mm": int(np.sum(s["max_penetration"] > 0.01))},
            "kinetic_energy_j": stats(s["kinetic_energy"]),
            "teleports": self._teleports,
            "lost_steps": self._lost_steps,
        }
