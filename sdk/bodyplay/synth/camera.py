"""The synthetic camera: renders the skinned actor in any pose as a webcam would record it.

:class:`SyntheticCamera` puts the actor (MakeHuman body in the color shirt) in front
of one or two placed webcams (:mod:`bodyplay.synth.rig`), lights it with a preset
(:mod:`bodyplay.synth.lighting`), renders it with the GL renderer over a background
photo, integrates sub-frame renders over the exposure time (motion blur) and
passes the result through the sensor model (:mod:`bodyplay.synth.sensor`).

It renders *any* pose stream: a clip (:meth:`SyntheticCamera.from_clip`), a batch
of key poses (:meth:`SyntheticCamera.render`), or poses a game or a virtual player
supplies one step at a time (:meth:`SyntheticCamera.capture`). Each result carries
the truth: the actor skeleton's forward-kinematics joints for the rendered pose,
in world metres. Given a clip, the camera is also a frame source (iterable of
:class:`~bodyplay.capture.frames.FrameSet` with ``cameras`` and ``fps``), so the
Session and the trackers consume it directly, with no files.

Rendering works in linear light: vertex colors and the background are decoded from
sRGB, the colored lights shade them, the sensor adds noise and applies the sRGB
curve with a fixed white balance (so a warm lamp gives an orange picture).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from types import TracebackType
from typing import TYPE_CHECKING, Any, Self

import cv2
import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_NAMES
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import Frame, FrameSet
from bodyplay.errors import ConfigError
from bodyplay.synth.backgrounds import load_background
from bodyplay.synth.lighting import LightingState, lighting_preset
from bodyplay.synth.occluder import PanelMesh, occluder_panel
from bodyplay.synth.options import SyntheticCameraOptions, make_synthetic_camera_options
from bodyplay.synth.rig import Rig, distortion_maps, frame_rig, make_rig_options
from bodyplay.synth.sensor import Sensor, noise_level, srgb_to_linear

if TYPE_CHECKING:
    from bodyplay.body.actor import Actor
    from bodyplay.motion.clip import MotionClip
    from bodyplay.render.accumulate import Accumulation
    from bodyplay.render.shaded import Light, RenderMesh, ShadedRenderer

__all__ = ["SynthFrame", "SyntheticCamera"]

# Motion blur: sub-frames are added until joints move at most this many pixels
# between consecutive sub-frames (bounded by options.max_subframes).
_BLUR_STEP_PX = 3.0
# Fine time grid for clips: poses are resampled at fps * _SUBSTEPS once.
_SUBSTEPS = 8
_RENDER_AMBIENT = 0.06  # the renderer's neutral floor; the colored ambient is a fill light
# Clip frames rendered ahead while a worker thread develops (sensor, lens) earlier ones.
_PIPELINE_DEPTH = 1
_BG_CACHE_SIZE = 8  # lit backgrounds kept (float32 frames; flickering light misses anyway)


@dataclass(frozen=True, eq=False)
class SynthFrame:
    """One synthetic capture instant: the frames of every camera and the truth.

    ``joints`` (17, 3) world metres in JOINT_NAMES order (the actor skeleton's FK
    for ``pose``; NaN, written as null, in the empty-room frames of a lead-in);
    ``t`` seconds since the first frame; ``index`` the frame number.
    """

    frames: FrameSet
    joints: NDArray[np.float64]
    pose: NDArray[np.float64]
    t: float
    index: int

    def truth_record(self) -> dict[str, Any]:
        """The truth.jsonl record of this frame (DESIGN.md)."""
        return {
            "frame": self.index,
            "t": round(self.t, 6),
            "joints": {
                n: ([round(float(x), 5) for x in self.joints[i]]
                    if np.all(np.isfinite(self.joints[i])) else None)
                for i, n in enumerate(JOINT_NAMES)
            },
        }


def _lin_colors(rgb_u8: NDArray[np.uint8]) -> NDArray[np.float32]:
    return srgb_to_linear(rgb_u8.astype(np.float64) / 255.0).astype(np.float32)


@njit(cache=True, nogil=True)
def _vertex_normals(verts, faces, out):  # type: ignore[no-untyped-def]
    """out (n, V, 3) = unit area-weighted smooth normals of posed meshes verts (n, V, 3)."""
    n, nv = verts.shape[0], verts.shape[1]
    acc = np.zeros((nv, 3), np.float64)
    for k in range(n):
        acc[:] = 0.0
        for f in range(faces.shape[0]):
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            e1x = verts[k, b, 0] - verts[k, a, 0]
            e1y = verts[k, b, 1] - verts[k, a, 1]
            e1z = verts[k, b, 2] - verts[k, a, 2]
            e2x = verts[k, c, 0] - verts[k, a, 0]
            e2y = verts[k, c, 1] - verts[k, a, 1]
            e2z = verts[k, c, 2] - verts[k, a, 2]
            nx = e1y * e2z - e1z * e2y
            ny = e1z * e2x - e1x * e2z
            nz = e1x * e2y - e1y * e2x
            for v in (a, b, c):
                acc[v, 0] += nx
                acc[v, 1] += ny
                acc[v, 2] += nz
        for v in range(nv):
            length = math.sqrt(acc[v, 0] ** 2 + acc[v, 1] ** 2 + acc[v, 2] ** 2)
            inv = 1.0 / max(length, 1e-12)
            out[k, v, 0] = acc[v, 0] * inv
            out[k, v, 1] = acc[v, 1] * inv
            out[k, v, 2] = acc[v, 2] * inv


def _is_closed(vertices: NDArray[np.floating], faces: NDArray[np.int32]) -> bool:
    """Whether a mesh is watertight and wound outwards (back faces may be culled)."""
    import trimesh

    tm = trimesh.Trimesh(np.asarray(vertices, np.float64), faces, process=False)
    return bool(tm.is_watertight and tm.is_winding_consistent and tm.volume > 0)


@dataclass(frozen=True, eq=False)
class _Exposure:
    """One camera's rendered exposure, waiting for the sensor (see ``_develop``)."""

    acc: Accumulation
    background: NDArray[np.float32]
    cam_index: int


class SyntheticCamera:
    """Renders the actor as one or two webcams see it; a frame source when given a clip.

    ``clip`` (optional) is the motion the camera frames its rig for and plays when
    iterated; ``frame_joints`` (T, 17, 3) frames the rig for other motion (live use);
    without either the rig frames a standing actor with room to move about. ``actor``
    and ``renderer`` may be shared between cameras; by default they are created
    (the renderer lazily, at the first frame) and released by :meth:`close`.
    """

    def __init__(
        self,
        options: SyntheticCameraOptions | None = None,
        clip: MotionClip | None = None,
        *,
        frame_joints: ArrayLike | None = None,
        actor: Actor | None = None,
        renderer: ShadedRenderer | None = None,
        duration: float | None = None,
    ) -> None:
        self.options = options or make_synthetic_camera_options()
        o = self.options
        if actor is None:
            from bodyplay.body.actor import load_actor

            actor = load_actor(shape=o.body)
        self.actor = actor
        self.skeleton = actor.skeleton
        if clip is not None and clip.skeleton != self.skeleton:
            clip = _retarget_clip(clip, self.skeleton)
        self.clip = clip
        self.fps = float(o.fps)
        self.duration = duration if duration is not None else (
            clip.duration if clip is not None else None
        )
        if frame_joints is None:
            frame_joints = clip.joints() if clip is not None else _play_area_joints(self.skeleton)
        rig_opts = make_rig_options(
            o.cameras, o.width, o.height, o.hfov_deg, o.distance, o.baseline, o.k1, o.seed
        )
        self.rig: Rig = frame_rig(frame_joints, rig_opts)
        self.cameras: tuple[Camera, ...] = self.rig.cameras
        self._pinhole = tuple(
            Camera(c.name, c.width, c.height, c.K, c.R, c.t) for c in self.cameras
        )
        self._maps = [distortion_maps(c) for c in self.cameras]
        self._preset = lighting_preset(o.lighting)
        self._sensor = Sensor(noise_level(o.noise), self._preset.gain)
        mesh = actor.mesh
        self._faces = np.ascontiguousarray(mesh.faces, dtype=np.int32)
        self._colors = _lin_colors(mesh.vertex_rgb)
        self._closed_mesh = _is_closed(mesh.rest_vertices, self._faces)
        bg = [load_background(o.background, o.width, o.height, i) for i in range(o.cameras)]
        self._bg_linear = [srgb_to_linear(b / 255.0).astype(np.float32) for b in bg]
        self._bg_cache: dict[tuple[int, float, float, float], NDArray[np.float32]] = {}
        self._renderer = renderer
        self._owns_renderer = renderer is None
        self._panels: dict[int, tuple[PanelMesh, ...]] = {}
        self._last: tuple[float, NDArray[np.float64]] | None = None
        self._next_index = 0
        self._closed = False

    # ---- plumbing --------------------------------------------------------------------
    def _gl(self) -> ShadedRenderer:
        if self._renderer is None:
            from bodyplay.render.shaded import ShadedRenderer, ShadedRendererOptions

            o = self.options
            self._renderer = ShadedRenderer(
                ShadedRendererOptions(
                    width=o.width, height=o.height, samples=o.msaa, ambient=_RENDER_AMBIENT,
                    specular=0.08,
                )
            )
        return self._renderer

    def close(self) -> None:
        """Release the renderer if this camera created it; further frames raise."""
        if self._owns_renderer and self._renderer is not None:
            self._renderer.release()
        self._renderer = None
        self._closed = True

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    # ---- scene -----------------------------------------------------------------------
    def _world(self, d: tuple[float, float, float]) -> NDArray[np.float64]:
        """Actor-facing frame direction (x camera right, y up, z towards camera) to world."""
        r = self.rig
        return np.asarray(d[0] * r.right + d[1] * np.array([0.0, 1.0, 0.0]) + d[2] * r.forward)

    def _lights(self, state: LightingState, cam: Camera) -> list[Light]:
        from bodyplay.render.shaded import Light

        out = []
        for spec in state.lights:
            towards = -self._world(spec.direction)
            out.append(Light(color=spec.color, intensity=spec.intensity, direction=_vec3(towards)))
        # The room's colored ambient light: a soft fill from behind the camera.
        amb = np.asarray(state.ambient, dtype=np.float64)
        level = float(amb.max())
        if level > 0:
            towards = self.rig.target - cam.center
            towards = towards / np.linalg.norm(towards) + np.array([0.0, -0.3, 0.0])
            out.append(
                Light(color=_vec3(amb / level), intensity=level, direction=_vec3(towards))
            )
        return out

    def _background(self, cam_index: int, state: LightingState) -> NDArray[np.float32]:
        """The background lit by the room's light, linear float32 (read-only, cached)."""
        ill = state.room_illuminant()
        ref = lighting_preset("steady").state(0.0, None).room_illuminant()
        gain = ill / float(ref.mean())
        key = (cam_index, round(float(gain[0]), 3), round(float(gain[1]), 3),
               round(float(gain[2]), 3))
        cached = self._bg_cache.get(key)
        if cached is None:
            cached = self._bg_linear[cam_index] * gain.astype(np.float32)
            cached.flags.writeable = False
            if len(self._bg_cache) >= _BG_CACHE_SIZE:
                self._bg_cache.clear()
            self._bg_cache[key] = cached
        return cached

    def _occluders(self, t: float) -> tuple[PanelMesh, ...]:
        active = [i for i, occ in enumerate(self.options.occlusions) if occ.active(t)]
        if not active:
            return ()
        if 0 not in self._panels:
            self._panels[0] = (occluder_panel(self.cameras[0].center, self.rig.target),)
        return self._panels[0]

    def _normals(self, verts: NDArray[np.float32]) -> NDArray[np.float32]:
        """(n, V, 3) smooth vertex normals of posed meshes (area-weighted; a numba kernel)."""
        v = np.ascontiguousarray(verts, dtype=np.float32)
        out = np.empty_like(v)
        _vertex_normals(v, self._faces, out)
        return out

    def _render_meshes(
        self, verts: NDArray[np.float32] | None, normals: NDArray[np.float32] | None, t: float
    ) -> list[RenderMesh]:
        from bodyplay.render.shaded import RenderMesh

        meshes = []
        if verts is not None:
            meshes.append(RenderMesh(verts, self._faces, self._colors, normals,
                                     closed=self._closed_mesh))
        for p in self._occluders(t):
            meshes.append(RenderMesh(p.vertices, p.faces, _lin_colors(
                np.round(p.colors * 255).astype(np.uint8)), p.normals))
        return meshes

    # ---- rendering core ----------------------------------------------------------------
    def _subframe_count(self, a: NDArray[np.float64], b: NDArray[np.float64]) -> int:
        """Sub-frames needed so joints move <= _BLUR_STEP_PX between them (camera 0)."""
        if self.options.max_subframes <= 1:
            return 1
        j = self.skeleton.joint_positions(np.stack([a, b]))
        uv = self._pinhole[0].project(j)
        d = float(np.nanmax(np.linalg.norm(uv[1] - uv[0], axis=-1)))
        if not math.isfinite(d):
            return 1
        return int(min(self.options.max_subframes, max(1, math.ceil(d / _BLUR_STEP_PX))))

    def _expose(
        self, t: float, sub_poses: NDArray[np.float64] | None
    ) -> list[_Exposure]:
        """Render sub-frame poses (n, D) of every camera, summed on the GPU (GL thread).

        ``None`` renders the empty room (occluders and background, no actor).
        """
        if self._closed:
            raise ConfigError("this SyntheticCamera was closed; create a new one")
        gl = self._gl()
        state = self._preset.state(t, self.duration)
        if sub_poses is None:
            meshes_per_sub = [self._render_meshes(None, None, t)]
        else:
            verts = self.actor.mesh.pose(self.skeleton, sub_poses)
            normals = self._normals(verts)
            meshes_per_sub = [self._render_meshes(v, n, t)
                              for v, n in zip(verts, normals, strict=True)]
        out = []
        for ci, cam in enumerate(self._pinhole):
            acc = gl.accumulate(meshes_per_sub, cam, lights=self._lights(state, cam))
            out.append(_Exposure(acc, self._background(ci, state), ci))
        return out

    def _develop(
        self, t: float, index: int, pose: NDArray[np.float64], exposures: list[_Exposure]
    ) -> SynthFrame:
        """Background, lens and sensor of rendered exposures; truth from ``pose``.

        No GL: runs in a worker thread while the next frame renders. The noise
        comes from a generator seeded by (seed, frame, camera), so the frames do not
        depend on the thread timing.
        """
        frames = []
        for ex in exposures:
            ci = ex.cam_index
            linear = ex.acc.composite(ex.background)  # the shutter's average, linear light
            maps = self._maps[ci]
            if maps is not None:
                warped = cv2.remap(
                    linear, maps[0], maps[1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT
                )
                linear = np.asarray(warped, dtype=np.float32)
            rng = np.random.default_rng([self.options.seed, index, ci])
            image = self._sensor.develop(linear, rng)
            frames.append(Frame(image, t, index, self.cameras[ci].name))
        if np.all(np.isfinite(pose)):
            joints = self.skeleton.joint_positions(pose)
        else:  # the empty room: nobody to have a truth of
            joints = np.full((len(JOINT_NAMES), 3), np.nan)
        return SynthFrame(FrameSet(tuple(frames), t, index), joints, pose, t, index)

    def _shoot(
        self, t: float, index: int, pose: NDArray[np.float64], sub_poses: NDArray[np.float64]
    ) -> SynthFrame:
        """Render sub-frame poses (n, D), average, develop; truth from ``pose``."""
        return self._develop(t, index, pose, self._expose(t, sub_poses))

    # ---- public API --------------------------------------------------------------------
    def capture(self, t: float, pose: ArrayLike, index: int | None = None) -> SynthFrame:
        """Render one frame of live play: ``pose`` (pose_dim,) held at time ``t`` seconds.

        The shutter closes at ``t``; motion blur interpolates from the previous
        :meth:`capture`'s pose over the exposure (none on the first frame). Times must
        increase. ``index`` defaults to one more than the previous frame's.
        """
        q = np.asarray(pose, dtype=np.float64)
        if q.shape != (self.skeleton.pose_dim,) or not np.all(np.isfinite(q)):
            raise ConfigError(
                f"capture takes one finite pose vector of {self.skeleton.pose_dim} values, "
                f"got shape {q.shape}"
            )
        if not math.isfinite(t):
            raise ConfigError(f"capture time must be finite, got {t}")
        idx = self._next_index if index is None else int(index)
        sub = q[None]
        if self._last is not None:
            t0, q0 = self._last
            if t <= t0:
                raise ConfigError(f"capture time {t} s is not after the previous one ({t0} s)")
            exposure = min(self._preset.exposure / self.fps, t - t0)
            n = self._subframe_count(_lerp(q0, q, 1.0 - exposure / (t - t0)), q)
            if n > 1:
                w = 1.0 - exposure / (t - t0) * (1.0 - (np.arange(n) + 0.5) / n)
                sub = np.stack([_lerp(q0, q, float(x)) for x in w])
        self._last = (float(t), q)
        self._next_index = idx + 1
        return self._shoot(float(t), idx, q, sub)

    def capture_empty(self, t: float, index: int | None = None) -> SynthFrame:
        """Render one frame of the empty room at ``t`` (no actor; truth joints NaN).

        For live sources that start before the player steps in; it does not count
        as a pose for the next :meth:`capture`'s motion blur.
        """
        if not math.isfinite(t):
            raise ConfigError(f"capture time must be finite, got {t}")
        idx = self._next_index if index is None else int(index)
        self._next_index = idx + 1
        empty = np.full(self.skeleton.pose_dim, np.nan)
        return self._develop(float(t), idx, empty, self._expose(float(t), None))

    def render(
        self, poses: ArrayLike, times: Sequence[float] | None = None
    ) -> list[SynthFrame]:
        """Render key poses (N, pose_dim) (or one pose) as sharp stills at ``times``.

        ``times`` default to ``i / fps``. No motion blur: key poses are unrelated.
        """
        q = np.asarray(poses, dtype=np.float64)
        if q.ndim == 1:
            q = q[None]
        if q.ndim != 2 or q.shape[1] != self.skeleton.pose_dim:
            raise ConfigError(
                f"render takes poses of shape (N, {self.skeleton.pose_dim}), got {q.shape}"
            )
        ts = [i / self.fps for i in range(len(q))] if times is None else [float(x) for x in times]
        if len(ts) != len(q):
            raise ConfigError(f"render got {len(q)} poses but {len(ts)} times")
        return [self._shoot(t, i, q[i], q[i : i + 1]) for i, t in enumerate(ts)]

    def from_clip(
        self,
        clip: MotionClip | None = None,
        start: float = 0.0,
        seconds: float | None = None,
        frames: int | None = None,
        lead_in: float = 0.0,
    ) -> Iterator[SynthFrame]:
        """Render a clip (default: the camera's) from ``start`` s for ``seconds`` or ``frames``.

        Frames are at ``i / fps`` (t counts from ``start``); each integrates the
        clip's motion over the preset's exposure, centred on the frame time, which is
        also the time of the truth joints. ``lead_in`` seconds of the empty room
        (background, lights and occluders, no actor; truth joints null) come first,
        as when a game asks the player to step out of view while it learns the
        background; the clip's frames follow them in numbering and time.
        """
        if not (math.isfinite(lead_in) and 0.0 <= lead_in <= 60.0):
            raise ConfigError(f"lead_in {lead_in} must be within 0..60 seconds")
        n_lead = int(round(lead_in * self.fps))
        src = clip if clip is not None else self.clip
        if src is None:
            raise ConfigError("from_clip needs a clip: pass one here or to SyntheticCamera")
        if src.skeleton != self.skeleton:
            src = _retarget_clip(src, self.skeleton)
        if frames is not None and frames < 1:
            raise ConfigError(f"frames must be at least 1, got {frames}")
        length = seconds if seconds is not None else (
            None if frames is None else (frames - 1) / self.fps + 1.0 / src.fps
        )
        part = src.slice(start, length)
        fine = part.resample(self.fps * _SUBSTEPS)
        n = (fine.num_frames - 1) // _SUBSTEPS + 1
        if frames is not None:
            n = min(n, frames)
        half = self._preset.exposure * _SUBSTEPS / 2.0
        last = fine.num_frames - 1
        # GL renders frame i + 1 here while a worker develops frame i (sensor noise,
        # JPEG: numpy and OpenCV release the GIL) and the caller encodes it.
        pending: deque[Future[SynthFrame]] = deque()
        with ThreadPoolExecutor(max_workers=1, thread_name_prefix="synth-develop") as pool:
            try:
                empty = np.full(self.skeleton.pose_dim, np.nan)
                for i in range(n_lead):
                    t = i / self.fps
                    pending.append(pool.submit(self._develop, t, i, empty, self._expose(t, None)))
                    if len(pending) > _PIPELINE_DEPTH:
                        yield pending.popleft().result()
                for i in range(n):
                    c = i * _SUBSTEPS
                    pose = fine.poses[c]
                    a = fine.poses[max(0, int(round(c - half)))]
                    b = fine.poses[min(last, int(round(c + half)))]
                    k = self._subframe_count(a, b)
                    if k > 1:
                        # sub-frame times spread over the exposure, centred on the frame time
                        offs = (np.arange(k) + 0.5) / k * 2.0 * half - half
                        idx = np.clip(np.round(c + offs).astype(int), 0, last)
                        sub = fine.poses[idx]
                    else:
                        sub = pose[None]
                    t = (n_lead + i) / self.fps
                    exposures = self._expose(t, sub)
                    pending.append(pool.submit(self._develop, t, n_lead + i, pose, exposures))
                    if len(pending) > _PIPELINE_DEPTH:
                        yield pending.popleft().result()
                while pending:
                    yield pending.popleft().result()
            finally:
                for fut in pending:
                    fut.cancel()

    def __iter__(self) -> Iterator[FrameSet]:
        """Frame sets of the camera's clip (the frame-source protocol)."""
        for sf in self.from_clip():
            yield sf.frames

    def silhouettes(self, pose: ArrayLike) -> list[NDArray[np.bool_]]:
        """Per camera, the (H, W) mask of pixels the actor covers in ``pose`` (no lens).

        Rendered as a flat id map, for tests and for checking framing.
        """
        q = np.asarray(pose, dtype=np.float64)
        verts = self.actor.mesh.pose(self.skeleton, q)
        ids = np.ones(len(self._faces), dtype=np.uint8)
        return [
            self._gl().render_ids(verts, self._faces, ids, cam) > 0 for cam in self._pinhole
        ]


def _vec3(v: ArrayLike) -> tuple[float, float, float]:
    a = np.asarray(v, dtype=np.float64).ravel()
    return (float(a[0]), float(a[1]), float(a[2]))


def _lerp(a: NDArray[np.float64], b: NDArray[np.float64], w: float) -> NDArray[np.float64]:
    """Linear blend of two nearby pose vectors (fine for the few ms of an exposure)."""
    return np.asarray(a + (b - a) * w)


def _retarget_clip(clip: MotionClip, skeleton: Any) -> MotionClip:
    """The clip's pose vectors on another skeleton of the same node layout."""
    from dataclasses import replace

    if clip.skeleton.pose_dim != skeleton.pose_dim:
        raise ConfigError("the clip's skeleton has a different pose layout than the actor's")
    return replace(clip, skeleton=skeleton)


def _play_area_joints(skeleton: Any) -> NDArray[np.float64]:
    """Joints that bound a standing player's reach: arms up and out, a step each way."""
    poses = []
    for dx in (-0.5, 0.5):
        for arm in (0.0, 1.2):
            q = skeleton.pose(
                root=(dx, skeleton.pelvis_height, 0.0),
                rotations={"l_shoulder": (0.0, 0.0, arm), "r_shoulder": (0.0, 0.0, -arm)},
            )
            poses.append(q)
    return np.asarray(skeleton.joint_positions(np.stack(poses)))
