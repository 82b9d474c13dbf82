"""Lit meshes with moderngl: :class:`ShadedRenderer` and the scene it draws.

:class:`ShadedRenderer` draws lit, per-vertex coloured meshes (:class:`RenderMesh`,
lit by up to eight :class:`Light`) over a background photo, as a calibrated
:class:`~bodyplay.capture.camera.Camera` sees them: the returned RGB image (top row
first) lines up exactly with ``Camera.project`` (pinhole part; lens distortion is
not rendered). :meth:`ShadedRenderer.accumulate` sums sub-frame renders in float
for motion blur (:mod:`bodyplay.render.accumulate`), and
:meth:`ShadedRenderer.render_ids` draws flat integer ids, the GPU counterpart of
:mod:`bodyplay.render.idmap`. Contexts and camera matrices come from
:mod:`bodyplay.render.gl`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import moderngl
import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types
from bodyplay.render.accumulate import Accumulation, FloatAccumulator, mesh_window
from bodyplay.render.gl import (
    GLContextError,
    create_context,
    gl_projection,
    gl_view,
    make_current,
)

__all__ = [
    "DEFAULT_LIGHTS",
    "Light",
    "RenderMesh",
    "ShadedRenderer",
    "ShadedRendererOptions",
    "vertex_normals",
]

_MAX_LIGHTS = 8


def _mat_bytes(m: NDArray[np.float64]) -> bytes:
    return np.ascontiguousarray(m.T, dtype=np.float32).tobytes()  # GL is column-major


# ---- scene description ---------------------------------------------------------------


@dataclass(frozen=True)
class Light:
    """A directional light (``direction`` it shines towards) or a point light (``position``).

    ``color`` is linear RGB 0..1 and ``intensity`` scales it. Point lights do not
    fall off with distance (scenes are a few metres across).
    """

    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    direction: tuple[float, float, float] | None = None
    position: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        if (self.direction is None) == (self.position is None):
            raise ConfigError("a Light needs exactly one of direction or position")
        if self.direction is not None and np.linalg.norm(self.direction) < 1e-9:
            raise ConfigError("a Light's direction must be non-zero")
        if len(self.color) != 3 or min(self.color) < 0 or self.intensity < 0:
            raise ConfigError("a Light's color must be 3 non-negative values, intensity >= 0")

    def as_vec4(self) -> tuple[float, float, float, float]:
        """xyz and w = 0 for a direction, w = 1 for a position (the shader's form)."""
        if self.position is not None:
            x, y, z = self.position
            return (float(x), float(y), float(z), 1.0)
        d = np.asarray(self.direction, dtype=float)
        d = d / np.linalg.norm(d)
        return (float(d[0]), float(d[1]), float(d[2]), 0.0)


DEFAULT_LIGHTS: tuple[Light, ...] = (
    Light(color=(1.0, 0.96, 0.9), intensity=0.75, direction=(-0.4, -0.6, -1.0)),
    Light(color=(0.75, 0.85, 1.0), intensity=0.35, direction=(0.8, -0.2, -0.5)),
    Light(color=(1.0, 1.0, 1.0), intensity=0.25, direction=(0.0, -0.3, 1.0)),
)
"""A warm key light from the upper left front, a cool fill and a rim light from behind."""


def vertex_normals(vertices: ArrayLike, faces: ArrayLike) -> NDArray[np.float32]:
    """Smooth per-vertex normals: area-weighted sums of the adjacent face normals."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])  # length = 2 * area
    n = np.zeros_like(v)
    for k in range(3):
        n[:, k] = np.bincount(f.ravel(), weights=np.repeat(fn[:, k], 3), minlength=len(v))
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return (n / np.maximum(length, 1e-12)).astype(np.float32)


class RenderMesh:
    """A mesh to shade: world ``vertices`` (V, 3), ``faces`` (F, 3), RGB ``colors``.

    ``colors`` is (V, 3) float 0..1 per vertex or one (3,) colour for all;
    ``normals`` (V, 3) are computed (smooth, area-weighted) when None. The arrays
    are validated and converted to float32 / int32 once, here. ``closed`` says the
    mesh is watertight and wound counter-clockwise seen from outside: its back
    faces are then culled (the same picture for about half the raster work).
    """

    __slots__ = ("vertices", "faces", "colors", "normals", "closed")

    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        colors: ArrayLike = (0.8, 0.8, 0.8),
        normals: ArrayLike | None = None,
        closed: bool = False,
    ) -> None:
        v = np.ascontiguousarray(vertices, dtype=np.float32)
        f = np.ascontiguousarray(faces, dtype=np.int32)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ConfigError(f"mesh vertices must have shape (V, 3), got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3:
            raise ConfigError(f"mesh faces must have shape (F, 3), got {f.shape}")
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ConfigError(f"mesh faces index vertices outside 0..{len(v) - 1}")
        c = np.asarray(colors, dtype=np.float32)
        if c.shape == (3,):
            c = np.broadcast_to(c, v.shape)
        if c.shape != v.shape:
            raise ConfigError(f"mesh colors must have shape (3,) or {v.shape}, got {c.shape}")
        n = vertex_normals(v, f) if normals is None else normals
        n = np.ascontiguousarray(n, dtype=np.float32)
        if n.shape != v.shape:
            raise ConfigError(f"mesh normals must have shape {v.shape}, got {n.shape}")
        self.vertices: NDArray[np.float32] = v
        self.faces: NDArray[np.int32] = f
        self.colors: NDArray[np.float32] = c
        self.normals: NDArray[np.float32] = n
        self.closed = bool(closed)

    def interleaved(self) -> NDArray[np.float32]:
        """(V, 9) position, normal, colour rows as the vertex buffer holds them."""
        return np.ascontiguousarray(np.hstack([self.vertices, self.normals, self.colors]))


@dataclass(frozen=True)
class ShadedRendererOptions:
    """Image size, multisampling (0 = off), lighting constants and clip depths (metres)."""

    width: int = 640
    height: int = 480
    samples: int = 0
    ambient: float = 0.3
    specular: float = 0.15
    shininess: float = 32.0
    near: float = 0.05
    far: float = 50.0
    background_fit: Literal["fill", "cover"] = "fill"

    def __post_init__(self) -> None:
        check_option_types(self)
        if not (0 < self.width <= 8192 and 0 < self.height <= 8192):
            raise ConfigError(f"render size {self.width}x{self.height} must be 1..8192 a side")
        if self.samples not in (0, 2, 4, 8):
            raise ConfigError(f"msaa samples must be 0, 2, 4 or 8, got {self.samples}")
        if not 0 < self.near < self.far:
            raise ConfigError(f"near {self.near} and far {self.far} must satisfy 0 < near < far")
        if self.ambient < 0 or self.specular < 0 or self.shininess <= 0:
            raise ConfigError("ambient and specular must be >= 0 and shininess > 0")
        if self.background_fit not in ("fill", "cover"):
            raise ConfigError("background_fit must be 'fill' (stretch) or 'cover' (crop)")


# ---- shaders -------------------------------------------------------------------------

_SHADED_VS = """
#version 330
uniform mat4 mvp;
in vec3 in_pos;
in vec3 in_normal;
in vec3 in_color;
out vec3 v_pos;
out vec3 v_normal;
out vec3 v_color;
void main() {
    v_pos = in_pos;
    v_normal = in_normal;
    v_color = in_color;
    gl_Position = mvp * vec4(in_pos, 1.0);
}
"""

_SHADED_FS = f"""
#version 330
#define MAX_LIGHTS {_MAX_LIGHTS}
uniform int n_lights;
uniform vec4 light_vec[MAX_LIGHTS];
uniform vec3 light_rgb[MAX_LIGHTS];
uniform vec3 eye;
uniform float ambient;
uniform float specular;
uniform float shininess;
in vec3 v_pos;
in vec3 v_normal;
in vec3 v_color;
out vec4 f_color;
void main() {{
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing) n = -n;  // two-sided: open meshes (shirts) show their inside
    vec3 view = normalize(eye - v_pos);
    vec3 c = ambient * v_color;
    for (int i = 0; i < n_lights; ++i) {{
        vec3 l = light_vec[i].w > 0.5 ? normalize(light_vec[i].xyz - v_pos)
                                      : -light_vec[i].xyz;
        float d = max(dot(n, l), 0.0);
        float s = d > 0.0 ? pow(max(dot(n, normalize(l + view)), 0.0), shininess) : 0.0;
        c += light_rgb[i] * (d * v_color + specular * s);
    }}
    f_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}}
"""

_BG_VS = """
#version 330
uniform vec4 uv_rect;  // u0, v0, u1, v1 of the image shown
out vec2 v_uv;
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    vec2 f = 0.5 * (p + 1.0);  // 0..1 left to right, bottom to top
    // texture row 0 is the image's top row
    v_uv = vec2(mix(uv_rect.x, uv_rect.z, f.x), mix(uv_rect.w, uv_rect.y, f.y));
    gl_Position = vec4(p, 0.0, 1.0);
}
"""

_BG_FS = """
#version 330
uniform sampler2D image;
in vec2 v_uv;
out vec4 f_color;
void main() { f_color = vec4(texture(image, v_uv).rgb, 1.0); }
"""

_IDS_VS = """
#version 330
uniform mat4 mvp;
in vec3 in_pos;
in uint in_id;
flat out uint v_id;
void main() {
    v_id = in_id;
    gl_Position = mvp * vec4(in_pos, 1.0);
}
"""

_IDS_FS = """
#version 330
flat in uint v_id;
out uint f_id;
void main() { f_id = v_id; }
"""


# ---- renderer ------------------------------------------------------------------------


class _Slot:
    """GL buffers of one mesh, kept between frames and grown when a mesh needs more."""

    def __init__(self, ctx: moderngl.Context, program: moderngl.Program) -> None:
        self.vbo = ctx.buffer(reserve=4096, dynamic=True)
        self.ibo = ctx.buffer(reserve=4096, dynamic=True)
        self.vao = ctx.vertex_array(
            program,
            [(self.vbo, "3f 3f 3f", "in_pos", "in_normal", "in_color")],
            index_buffer=self.ibo,
            index_element_size=4,
        )
        self.count = 0

    def upload(self, mesh: RenderMesh) -> None:
        data = mesh.interleaved()
        for buf, arr in ((self.vbo, data), (self.ibo, mesh.faces)):
            if arr.nbytes > buf.size:
                buf.orphan(int(arr.nbytes * 1.25) + 16)
            buf.write(arr.tobytes())
        self.count = mesh.faces.size

    def release(self) -> None:
        self.vao.release()
        self.vbo.release()
        self.ibo.release()


class ShadedRenderer:
    """Renders lit meshes (and flat id maps) as a calibrated camera sees them.

    Create once and call :meth:`render` every frame: framebuffers, programs, vertex
    buffers and the background texture are reused. Pass ``ctx`` to draw with an
    existing context (e.g. a pygame window's, from ``create_context(False)``); by
    default the renderer creates its own headless EGL context and releases it in
    :meth:`release` (also called on leaving a ``with`` block).
    """

    def __init__(
        self, options: ShadedRendererOptions | None = None, ctx: moderngl.Context | None = None
    ) -> None:
        self.options = options or ShadedRendererOptions()
        self._owns_ctx = ctx is None
        self.ctx = create_context(headless=True) if ctx is None else ctx
        o = self.options
        size = (o.width, o.height)
        if o.samples > self.ctx.max_samples:
            raise ConfigError(
                f"msaa samples {o.samples} exceeds this GL driver's {self.ctx.max_samples}"
            )
        ctx_ = self.ctx
        self._shaded = ctx_.program(vertex_shader=_SHADED_VS, fragment_shader=_SHADED_FS)
        self._bg = ctx_.program(vertex_shader=_BG_VS, fragment_shader=_BG_FS)
        self._ids = ctx_.program(vertex_shader=_IDS_VS, fragment_shader=_IDS_FS)
        self._bg_vao = ctx_.vertex_array(self._bg, [])
        self._bg_tex: moderngl.Texture | None = None
        self._color = ctx_.renderbuffer(size, 3)
        self._depth = ctx_.depth_renderbuffer(size)
        self._fbo = ctx_.framebuffer([self._color], self._depth)
        self._ms_fbo: moderngl.Framebuffer | None = None
        self._ms_bufs: list[Any] = []
        if o.samples:
            mc = ctx_.renderbuffer(size, 3, samples=o.samples)
            md = ctx_.depth_renderbuffer(size, samples=o.samples)
            self._ms_bufs = [mc, md]
            self._ms_fbo = ctx_.framebuffer([mc], md)
        self._id_tex = ctx_.texture(size, 1, dtype="u1")
        self._id_depth = ctx_.depth_renderbuffer(size)
        self._id_fbo = ctx_.framebuffer([self._id_tex], self._id_depth)
        self._id_vbo = ctx_.buffer(reserve=4096, dynamic=True)
        self._id_ibo = ctx_.buffer(reserve=4096, dynamic=True)
        self._id_vao = ctx_.vertex_array(
            self._ids, [(self._id_vbo, "3f", "in_pos"), (self._id_ibo, "1u", "in_id")]
        )
        self._slots: list[_Slot] = []
        self._rgb = bytearray(o.width * o.height * 3)
        self._acc: FloatAccumulator | None = None  # accumulate()'s targets, made on first use
        self._released = False

    # ---- helpers ---------------------------------------------------------------------
    def _camera(self, camera: Camera) -> Camera:
        o = self.options
        if (camera.width, camera.height) == (o.width, o.height):
            return camera
        return camera.with_size(o.width, o.height)

    def _mvp(self, camera: Camera) -> bytes:
        o = self.options
        return _mat_bytes(gl_projection(camera, o.near, o.far) @ gl_view(camera))

    def _set(self, program: moderngl.Program, name: str, value: Any) -> None:
        if name in program:  # the GLSL compiler drops unused uniforms
            program[name].value = value  # type: ignore[union-attr]

    def _draw_background(self, background: ArrayLike) -> None:
        img = np.ascontiguousarray(background)
        if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] != 3:
            raise ConfigError(
                f"background must be an (H, W, 3) uint8 RGB image, got {img.dtype} {img.shape}"
            )
        h, w = img.shape[:2]
        if self._bg_tex is None or self._bg_tex.size != (w, h):
            if self._bg_tex is not None:
                self._bg_tex.release()
            self._bg_tex = self.ctx.texture((w, h), 3, dtype="f1")
            self._bg_tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
            self._bg_tex.repeat_x = False
            self._bg_tex.repeat_y = False
        self._bg_tex.write(img.tobytes(), alignment=1)
        u0, v0, u1, v1 = 0.0, 0.0, 1.0, 1.0
        if self.options.background_fit == "cover":
            o = self.options
            ai, at = w / h, o.width / o.height
            if ai > at:
                k = at / ai
                u0, u1 = 0.5 - k / 2, 0.5 + k / 2
            else:
                k = ai / at
                v0, v1 = 0.5 - k / 2, 0.5 + k / 2
        self._set(self._bg, "uv_rect", (u0, v0, u1, v1))
        self._bg_tex.use(0)
        self._set(self._bg, "image", 0)
        self.ctx.disable(moderngl.DEPTH_TEST)
        self._bg_vao.render(moderngl.TRIANGLES, vertices=3)

    def _setup_shading(self, cam: Camera, lights: Sequence[Light]) -> None:
        if len(lights) > _MAX_LIGHTS:
            raise ConfigError(f"at most {_MAX_LIGHTS} lights, got {len(lights)}")
        o = self.options
        p = self._shaded
        p["mvp"].write(self._mvp(cam))  # type: ignore[union-attr]
        vecs = np.zeros((_MAX_LIGHTS, 4), np.float32)
        rgbs = np.zeros((_MAX_LIGHTS, 3), np.float32)
        for i, light in enumerate(lights):
            vecs[i] = light.as_vec4()
            rgbs[i] = np.asarray(light.color, np.float32) * light.intensity
        if "light_vec" in p:
            p["light_vec"].write(vecs.tobytes())  # type: ignore[union-attr]
            p["light_rgb"].write(rgbs.tobytes())  # type: ignore[union-attr]
        self._set(p, "n_lights", len(lights))
        self._set(p, "eye", tuple(float(x) for x in cam.center))
        self._set(p, "ambient", o.ambient)
        self._set(p, "specular", o.specular)
        self._set(p, "shininess", o.shininess)

    def _draw_meshes(self, meshes: Sequence[RenderMesh]) -> None:
        while len(self._slots) < len(meshes):
            self._slots.append(_Slot(self.ctx, self._shaded))
        for slot, mesh in zip(self._slots, meshes, strict=False):
            slot.upload(mesh)
            if mesh.closed:
                self.ctx.front_face = "ccw"
                self.ctx.cull_face = "back"
                self.ctx.enable(moderngl.CULL_FACE)
            slot.vao.render(moderngl.TRIANGLES, vertices=slot.count)
            self.ctx.disable(moderngl.CULL_FACE)

    # ---- public API ------------------------------------------------------------------
    def render(
        self,
        meshes: Sequence[RenderMesh] | RenderMesh,
        camera: Camera,
        background: ArrayLike | None = None,
        lights: Sequence[Light] = DEFAULT_LIGHTS,
    ) -> NDArray[np.uint8]:
        """Shade ``meshes`` seen by ``camera`` over ``background``: (H, W, 3) RGB uint8.

        ``camera`` is resampled to the options' size if it differs; the background
        image (any size, RGB uint8) is stretched (``fill``) or cropped (``cover``) to
        the frame; black when None. Up to 8 lights.
        """
        self._check_alive()
        if self._owns_ctx:
            make_current(self.ctx)
        if isinstance(meshes, RenderMesh):
            meshes = [meshes]
        if len(lights) > _MAX_LIGHTS:
            raise ConfigError(f"at most {_MAX_LIGHTS} lights, got {len(lights)}")
        cam = self._camera(camera)
        o = self.options
        ctx = self.ctx
        target = self._ms_fbo if self._ms_fbo is not None else self._fbo
        target.use()
        target.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        if background is not None:
            self._draw_background(background)
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.depth_func = "<"
        self._setup_shading(cam, lights)
        self._draw_meshes(meshes)
        if self._ms_fbo is not None:
            ctx.copy_framebuffer(self._fbo, self._ms_fbo)
        self._fbo.read_into(self._rgb, components=3, alignment=1)
        img = np.frombuffer(self._rgb, dtype=np.uint8).reshape(o.height, o.width, 3)
        return np.ascontiguousarray(img[::-1])

    def accumulate(
        self,
        sub_frames: Sequence[Sequence[RenderMesh] | RenderMesh],
        camera: Camera,
        lights: Sequence[Light] = DEFAULT_LIGHTS,
    ) -> Accumulation:
        """Shade each sub-frame's meshes (no background) and sum them in float on the GPU.

        For motion blur: one read-back per exposure, of the window the meshes cover
        only, with no 8-bit rounding; ``Accumulation.composite`` adds the background
        once. Same shading and conventions as :meth:`render`.
        """
        self._check_alive()
        if self._owns_ctx:
            make_current(self.ctx)
        subs = [[m] if isinstance(m, RenderMesh) else list(m) for m in sub_frames]
        if not subs:
            raise ConfigError("accumulate needs at least one sub-frame")
        cam = self._camera(camera)
        o = self.options
        verts = [m.vertices for sub in subs for m in sub]
        window = mesh_window(np.concatenate(verts) if verts else np.zeros((0, 3)), cam, o.near)
        if window[2] <= window[0]:
            empty = np.zeros((0, 0, 4), np.float32)
            return Accumulation(empty, 0, 0, len(subs), o.width, o.height)
        if self._acc is None:  # float targets, made on first use
            self._acc = FloatAccumulator(self.ctx, o.width, o.height, o.samples)
        self._setup_shading(cam, lights)
        return self._acc.run(subs, self._draw_meshes, window)

    def render_ids(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        face_ids: ArrayLike,
        camera: Camera,
    ) -> NDArray[np.uint8]:
        """Flat id map (H, W) uint8 of one posed mesh: no lighting, no MSAA, 0 = background.

        Same conventions as :func:`bodyplay.render.idmap.render_idmaps`, so the two
        can be compared (GL clips triangles at the near plane where the numba
        rasterizer skips them, and clips at the far plane where it does not).
        """
        self._check_alive()
        if self._owns_ctx:
            make_current(self.ctx)
        v = np.asarray(vertices, dtype=np.float32)
        f = np.asarray(faces, dtype=np.int64)
        ids = np.asarray(face_ids)
        if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3:
            raise ConfigError("render_ids takes vertices (V, 3) and faces (F, 3)")
        if ids.shape != (len(f),) or (ids.size and (ids.min() < 0 or ids.max() > 255)):
            raise ConfigError(f"face_ids must be ({len(f)},) values in 0..255")
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ConfigError(f"faces index vertices outside 0..{len(v) - 1}")
        cam = self._camera(camera)
        o = self.options
        # un-indexed: each corner carries its face's id (flat, no provoking-vertex issues)
        pos = np.ascontiguousarray(v[f.ravel()])
        corner_ids = np.repeat(ids.astype(np.uint32), 3)
        for buf, arr in ((self._id_vbo, pos), (self._id_ibo, corner_ids)):
            if arr.nbytes > buf.size:
                buf.orphan(int(arr.nbytes * 1.25) + 16)
            buf.write(arr.tobytes())
        ctx = self.ctx
        self._id_fbo.use()
        self._id_fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.depth_func = "<"
        self._ids["mvp"].write(self._mvp(cam))  # type: ignore[union-attr]
        self._id_vao.render(moderngl.TRIANGLES, vertices=len(pos))
        data = self._id_fbo.read(components=1, dtype="u1", alignment=1)
        img = np.frombuffer(data, dtype=np.uint8).reshape(o.height, o.width)
        return np.ascontiguousarray(img[::-1])

    def _check_alive(self) -> None:
        if self._released:
            raise GLContextError("this ShadedRenderer was released; create a new one")

    def release(self) -> None:
        """Free every GL object (and the context if the renderer created it)."""
        if self._released:
            return
        self._released = True
        for slot in self._slots:
            slot.release()
        self._slots.clear()
        objs: list[Any] = [
            self._id_vao, self._id_vbo, self._id_ibo, self._id_fbo, self._id_tex,
            self._id_depth, self._bg_vao, self._fbo, self._color, self._depth,
            self._shaded, self._bg, self._ids,
        ]
        if self._ms_fbo is not None:
            objs += [self._ms_fbo, *self._ms_bufs]
        if self._bg_tex is not None:
            objs.append(self._bg_tex)
        for obj in objs:
            obj.release()
        if self._acc is not None:
            self._acc.release()
            self._acc = None
        if self._owns_ctx:
            self.ctx.release()

    def __enter__(self) -> ShadedRenderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()
