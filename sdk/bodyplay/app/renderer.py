"""Drawing a :class:`~bodyplay.app.scene.Scene` with moderngl: :class:`SceneRenderer`.

Spheres, boxes and capsules are instances of three unit meshes, one instanced draw
call per kind; free meshes (cloth) are uploaded per frame; the floor is one quad
checkered in its fragment shader; blob shadows are soft alpha discs just above the
floor; the HUD (text and insets such as the camera picture) is drawn with OpenCV
onto the read-back picture. Shading is two-sided Blinn-Phong with
the same lights as :class:`~bodyplay.render.shaded.ShadedRenderer`, and the view
matrices come from :mod:`bodyplay.render.gl` (a Scene camera is a calibrated
:class:`~bodyplay.capture.camera.Camera`).

The renderer draws into its own framebuffer; :meth:`SceneRenderer.render` reads it
back as an RGB image with the HUD (headless: the video frame) and
:meth:`SceneRenderer.present` shows such an image on the window's screen.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import cv2
import moderngl
import numpy as np
import trimesh
from numpy.typing import NDArray

from bodyplay.app.scene import Scene, TextItem
from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError
from bodyplay.render.gl import (
    GLContextError,
    create_context,
    gl_projection,
    gl_view,
    make_current,
)
from bodyplay.render.shaded import DEFAULT_LIGHTS, Light, vertex_normals

__all__ = ["SceneRenderer", "draw_hud"]

_MAX_LIGHTS = 8

_LIT_VS = """
#version 330
uniform mat4 vp;
in vec3 in_pos;
in vec3 in_normal;
in vec3 in_vcolor;
in vec4 in_m0;
in vec4 in_m1;
in vec4 in_m2;
in vec4 in_m3;
in vec3 in_icolor;
out vec3 v_pos;
out vec3 v_normal;
out vec3 v_color;
void main() {
    mat4 m = mat4(in_m0, in_m1, in_m2, in_m3);
    vec4 w = m * vec4(in_pos, 1.0);
    v_pos = w.xyz;
    // columns are rotation * scale: the inverse transpose is R S^-1 = M S^-2
    vec3 s2 = vec3(dot(in_m0.xyz, in_m0.xyz), dot(in_m1.xyz, in_m1.xyz),
                   dot(in_m2.xyz, in_m2.xyz));
    v_normal = mat3(m) * (in_normal / max(s2, vec3(1e-12)));
    v_color = in_vcolor * in_icolor;
    gl_Position = vp * w;
}
"""

_LIT_FS = f"""
#version 330
#define MAX_LIGHTS {_MAX_LIGHTS}
uniform int n_lights;
uniform vec4 light_vec[MAX_LIGHTS];
uniform vec3 light_rgb[MAX_LIGHTS];
uniform vec3 eye;
uniform float ambient;
uniform float specular;
in vec3 v_pos;
in vec3 v_normal;
in vec3 v_color;
out vec4 f_color;
void main() {{
    vec3 n = normalize(v_normal);
    vec3 view = normalize(eye - v_pos);
    if (dot(n, view) < 0.0) n = -n;  // two-sided: cloth and open meshes show both faces
    vec3 c = ambient * v_color;
    for (int i = 0; i < n_lights; ++i) {{
        vec3 l = light_vec[i].w > 0.5 ? normalize(light_vec[i].xyz - v_pos)
                                      : -light_vec[i].xyz;
        float d = max(dot(n, l), 0.0);
        float s = d > 0.0 ? pow(max(dot(n, normalize(l + view)), 0.0), 24.0) : 0.0;
        c += light_rgb[i] * (d * v_color + specular * s);
    }}
    f_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}}
"""

_FLOOR_VS = """
#version 330
uniform mat4 vp;
uniform float half_size;
in vec2 in_xz;
out vec2 v_xz;
void main() {
    v_xz = in_xz * half_size;
    gl_Position = vp * vec4(v_xz.x, 0.0, v_xz.y, 1.0);
}
"""

_FLOOR_FS = """
#version 330
uniform vec3 color1;
uniform vec3 color2;
uniform float tile;
uniform float light;
in vec2 v_xz;
out vec4 f_color;
void main() {
    vec2 k = floor(v_xz / tile);
    float odd = mod(k.x + k.y, 2.0);
    f_color = vec4(mix(color1, color2, odd) * light, 1.0);
}
"""

_SHADOW_VS = """
#version 330
uniform mat4 vp;
in vec2 in_corner;
in vec4 in_shadow;  // x, z, radius, strength
out vec2 v_uv;
out float v_strength;
void main() {
    v_uv = in_corner;
    v_strength = in_shadow.w;
    vec2 xz = in_shadow.xy + in_corner * in_shadow.z;
    gl_Position = vp * vec4(xz.x, 0.004, xz.y, 1.0);
}
"""

_SHADOW_FS = """
#version 330
in vec2 v_uv;
in float v_strength;
out vec4 f_color;
void main() {
    float r = length(v_uv);
    if (r > 1.0) discard;
    f_color = vec4(0.0, 0.0, 0.0, v_strength * (1.0 - smoothstep(0.35, 1.0, r)));
}
"""

_LINE_VS = """
#version 330
uniform mat4 vp;
in vec3 in_pos;
in vec3 in_color;
out vec3 v_color;
void main() {
    v_color = in_color;
    gl_Position = vp * vec4(in_pos, 1.0);
}
"""

_LINE_FS = """
#version 330
in vec3 v_color;
out vec4 f_color;
void main() { f_color = vec4(v_color, 1.0); }
"""

_OVERLAY_VS = """
#version 330
out vec2 v_uv;
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    v_uv = vec2(0.5 * (p.x + 1.0), 1.0 - 0.5 * (p.y + 1.0));
    gl_Position = vec4(p, 0.0, 1.0);
}
"""

_OVERLAY_FS = """
#version 330
uniform sampler2D image;
in vec2 v_uv;
out vec4 f_color;
void main() { f_color = vec4(texture(image, v_uv).rgb, 1.0); }
"""


def _unit_sphere(subdivisions: int = 2) -> tuple[
    NDArray[np.float32], NDArray[np.float32], NDArray[np.int32]
]:
    m = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    v = np.asarray(m.vertices, np.float32)
    return v, v.copy(), np.asarray(m.faces, np.int32)


def _unit_box() -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.int32]]:
    verts: list[NDArray[np.float64]] = []
    norms: list[NDArray[np.float64]] = []
    faces: list[list[int]] = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = 1.0
            w = np.cross(n, u)
            base = len(verts)
            for du, dw in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                verts.append(0.5 * n + 0.5 * du * u + 0.5 * dw * w)
                norms.append(n)
            faces += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    return (np.asarray(verts, np.float32), np.asarray(norms, np.float32),
            np.asarray(faces, np.int32))


def _unit_cylinder(segments: int = 16) -> tuple[
    NDArray[np.float32], NDArray[np.float32], NDArray[np.int32]
]:
    """Open cylinder of radius 1 along Y from -0.5 to 0.5 (capsule ends are spheres)."""
    a = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    ring = np.stack([np.cos(a), np.zeros_like(a), np.sin(a)], 1)
    v = np.concatenate([ring + [0, -0.5, 0], ring + [0, 0.5, 0]]).astype(np.float32)
    n = np.concatenate([ring, ring]).astype(np.float32)
    i = np.arange(segments)
    j = (i + 1) % segments
    f = np.concatenate(
        [np.stack([i, j + segments, j], 1), np.stack([i, i + segments, j + segments], 1)]
    )
    return v, n, f.astype(np.int32)


def _basis_models(a: NDArray[np.float64], b: NDArray[np.float64],
                  r: NDArray[np.float64]) -> NDArray[np.float32]:
    """(N, 16) column-major models mapping the unit cylinder onto segments a-b, radius r."""
    d = b - a
    length = np.linalg.norm(d, axis=1)
    y = d / np.maximum(length, 1e-9)[:, None]
    y[length < 1e-9] = (0.0, 1.0, 0.0)
    ref = np.where(np.abs(y[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    x = np.cross(y, ref)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    z = np.cross(x, y)
    m = np.zeros((len(a), 4, 4))
    m[:, :3, 0] = x * r[:, None]
    m[:, :3, 1] = y * length[:, None]
    m[:, :3, 2] = z * r[:, None]
    m[:, :3, 3] = 0.5 * (a + b)
    m[:, 3, 3] = 1.0
    return np.ascontiguousarray(m.transpose(0, 2, 1).reshape(-1, 16), np.float32)


def _scale_models(c: NDArray[np.float64], s: NDArray[np.float64],
                  yaw: NDArray[np.float64] | None = None) -> NDArray[np.float32]:
    """(N, 16) column-major models: translate(c) * rotY(yaw) * scale(s)."""
    n = len(c)
    m = np.zeros((n, 4, 4))
    cy = np.ones(n) if yaw is None else np.cos(yaw)
    sy = np.zeros(n) if yaw is None else np.sin(yaw)
    m[:, 0, 0], m[:, 0, 2] = cy * s[:, 0], sy * s[:, 2]
    m[:, 1, 1] = s[:, 1]
    m[:, 2, 0], m[:, 2, 2] = -sy * s[:, 0], cy * s[:, 2]
    m[:, :3, 3] = c
    m[:, 3, 3] = 1.0
    return np.ascontiguousarray(m.transpose(0, 2, 1).reshape(-1, 16), np.float32)


class _Instanced:
    """A unit mesh drawn as many instances (model matrix + color each)."""

    def __init__(self, ctx: moderngl.Context, prog: moderngl.Program,
                 mesh: tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.int32]]) -> None:
        v, n, f = mesh
        data = np.hstack([v, n, np.ones_like(v)]).astype(np.float32)
        self.vbo = ctx.buffer(data.tobytes())
        self.ibo = ctx.buffer(f.astype(np.int32).tobytes())
        self.inst = ctx.buffer(reserve=64 * 76, dynamic=True)
        self.vao = ctx.vertex_array(
            prog,
            [(self.vbo, "3f 3f 3f", "in_pos", "in_normal", "in_vcolor"),
             (self.inst, "4f 4f 4f 4f 3f/i", "in_m0", "in_m1", "in_m2", "in_m3", "in_icolor")],
            index_buffer=self.ibo, index_element_size=4,
        )
        self.count = int(f.size)

    def draw(self, models: NDArray[np.float32], colors: NDArray[np.float32]) -> None:
        n = len(models)
        if n == 0:
            return
        data = np.ascontiguousarray(np.hstack([models, colors]), np.float32)
        if data.nbytes > self.inst.size:
            self.inst.orphan(int(data.nbytes * 1.5))
        self.inst.write(data.tobytes())
        self.vao.render(moderngl.TRIANGLES, vertices=self.count, instances=n)

    def release(self) -> None:
        for o in (self.vao, self.vbo, self.ibo, self.inst):
            o.release()


_FONT = cv2.FONT_HERSHEY_DUPLEX


def draw_hud(image: NDArray[np.uint8], scene: Scene) -> None:
    """Draw the scene's insets and text onto an (H, W, 3) RGB ``image`` (OpenCV, in
    place): the HUD goes on the read-back picture, which costs far less than
    blending a full-screen overlay texture on a software GL."""
    h, w = image.shape[:2]
    for ins in scene.insets:
        x, y, iw, ih = ins.rect
        x0, y0, x1, y1 = max(x, 0), max(y, 0), min(x + iw, w), min(y + ih, h)
        if x1 <= x0 or y1 <= y0:
            continue
        img: NDArray[np.uint8] = ins.image
        if img.shape[:2] != (ih, iw):
            img = np.asarray(cv2.resize(img, (iw, ih), interpolation=cv2.INTER_AREA), np.uint8)
        image[y0:y1, x0:x1] = img[y0 - y:y1 - y, x0 - x:x1 - x]
        if ins.border is not None:
            c = tuple(int(255 * v) for v in ins.border)
            cv2.rectangle(image, (x0, y0), (x1 - 1, y1 - 1), c, 2)
    for item in scene.texts:
        _put_text(image, item)


def _put_text(image: NDArray[np.uint8], item: TextItem) -> None:
    scale = 0.62 * item.size
    thick = max(1, int(round(1.6 * item.size)))
    (tw, _), _ = cv2.getTextSize(item.text, _FONT, scale, thick)
    x, y = item.pos
    if item.anchor == "center":
        x -= tw / 2.0
    elif item.anchor == "right":
        x -= tw
    org = (int(round(x)), int(round(y)))
    if item.outline:  # a drop shadow keeps the text readable on sky and grass
        off = max(1, thick)
        cv2.putText(image, item.text, (org[0] + off, org[1] + off), _FONT, scale,
                    (0, 0, 0), thick, cv2.LINE_AA)
    c = tuple(int(255 * v) for v in item.color)
    cv2.putText(image, item.text, org, _FONT, scale, c, thick, cv2.LINE_AA)


class SceneRenderer:
    """Renders :class:`Scene` draw lists at ``width`` x ``height``.

    ``ctx`` is the GL context to use (a pygame window's from
    ``create_context(headless=False)``); by default a headless EGL context is
    created and released with the renderer. ``samples`` multisamples (0, 2, 4).
    """

    def __init__(self, width: int = 640, height: int = 480, *, ctx: moderngl.Context | None = None,
                 samples: int = 0, lights: Sequence[Light] = DEFAULT_LIGHTS,
                 ambient: float = 0.35, specular: float = 0.2) -> None:
        if not (16 <= width <= 8192 and 16 <= height <= 8192):
            raise ConfigError(f"render size {width}x{height} must be 16..8192 a side")
        if samples not in (0, 2, 4, 8):
            raise ConfigError(f"samples must be 0, 2, 4 or 8, got {samples}")
        if len(lights) > _MAX_LIGHTS:
            raise ConfigError(f"at most {_MAX_LIGHTS} lights, got {len(lights)}")
        self.width, self.height = int(width), int(height)
        self._owns_ctx = ctx is None
        self.ctx = create_context(headless=True) if ctx is None else ctx
        c = self.ctx
        samples = min(samples, c.max_samples)
        self._lit = c.program(vertex_shader=_LIT_VS, fragment_shader=_LIT_FS)
        self._floor = c.program(vertex_shader=_FLOOR_VS, fragment_shader=_FLOOR_FS)
        self._shadow = c.program(vertex_shader=_SHADOW_VS, fragment_shader=_SHADOW_FS)
        self._overlay = c.program(vertex_shader=_OVERLAY_VS, fragment_shader=_OVERLAY_FS)
        self._line = c.program(vertex_shader=_LINE_VS, fragment_shader=_LINE_FS)
        self._line_vbo = c.buffer(reserve=64 * 24, dynamic=True)
        self._line_vao = c.vertex_array(self._line,
                                        [(self._line_vbo, "3f 3f", "in_pos", "in_color")])
        self._sphere = _Instanced(c, self._lit, _unit_sphere())
        self._box = _Instanced(c, self._lit, _unit_box())
        self._cyl = _Instanced(c, self._lit, _unit_cylinder())
        self._cap = _Instanced(c, self._lit, _unit_sphere(1))  # capsule ends: 80 triangles
        quad = np.array([[-1, -1], [1, -1], [1, 1], [-1, -1], [1, 1], [-1, 1]], np.float32)
        self._quad = c.buffer(quad.tobytes())
        self._floor_vao = c.vertex_array(self._floor, [(self._quad, "2f", "in_xz")])
        self._shadow_inst = c.buffer(reserve=16 * 64, dynamic=True)
        self._shadow_vao = c.vertex_array(
            self._shadow,
            [(self._quad, "2f", "in_corner"), (self._shadow_inst, "4f/i", "in_shadow")],
        )
        self._mesh_vbo = c.buffer(reserve=4096, dynamic=True)
        self._mesh_ibo = c.buffer(reserve=4096, dynamic=True)
        self._mesh_inst = c.buffer(
            np.hstack([np.eye(4, dtype=np.float32).reshape(1, 16), np.ones((1, 3), np.float32)])
            .tobytes()
        )
        self._mesh_vao = c.vertex_array(
            self._lit,
            [(self._mesh_vbo, "3f 3f 3f", "in_pos", "in_normal", "in_vcolor"),
             (self._mesh_inst, "4f 4f 4f 4f 3f/i", "in_m0", "in_m1", "in_m2", "in_m3",
              "in_icolor")],
            index_buffer=self._mesh_ibo, index_element_size=4,
        )
        self._overlay_vao = c.vertex_array(self._overlay, [])
        self._screen_tex = c.texture((self.width, self.height), 3)
        self._screen_tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
        size = (self.width, self.height)
        self._color = c.renderbuffer(size, 3)
        self._depth = c.depth_renderbuffer(size)
        self._fbo = c.framebuffer([self._color], self._depth)
        self._ms: list[Any] = []
        self._ms_fbo: moderngl.Framebuffer | None = None
        if samples:
            mc = c.renderbuffer(size, 3, samples=samples)
            md = c.depth_renderbuffer(size, samples=samples)
            self._ms = [mc, md]
            self._ms_fbo = c.framebuffer([mc], md)
        self._rgb = bytearray(self.width * self.height * 3)
        vecs = np.zeros((_MAX_LIGHTS, 4), np.float32)
        rgbs = np.zeros((_MAX_LIGHTS, 3), np.float32)
        for i, light in enumerate(lights):
            vecs[i] = light.as_vec4()
            rgbs[i] = np.asarray(light.color, np.float32) * light.intensity
        self._lit["light_vec"].write(vecs.tobytes())  # type: ignore[union-attr]
        self._lit["light_rgb"].write(rgbs.tobytes())  # type: ignore[union-attr]
        self._lit["n_lights"].value = len(lights)  # type: ignore[union-attr]
        self._lit["ambient"].value = ambient  # type: ignore[union-attr]
        self._lit["specular"].value = specular  # type: ignore[union-attr]
        # floor brightness: ambient + the lights' diffuse on an upward normal
        up = sum(max(0.0, -float(v[1])) * float(np.mean(r))
                 for v, r in zip(vecs, rgbs, strict=True))
        self._floor_light = min(1.0, ambient + up)
        self._released = False

    # ---- frame ---------------------------------------------------------------------
    def _default_camera(self) -> Camera:
        scene = Scene(self.width, self.height)
        return scene.look((0.0, 1.6, 4.0), (0.0, 1.0, 0.0))

    def _vp(self, scene: Scene) -> tuple[bytes, Camera]:
        cam = scene.camera or self._default_camera()
        if (cam.width, cam.height) != (self.width, self.height):
            cam = cam.with_size(self.width, self.height)
        P = gl_projection(cam, 0.05, 100.0)
        if scene.mirror:
            P = np.diag([-1.0, 1.0, 1.0, 1.0]) @ P
        vp = P @ gl_view(cam)
        return np.ascontiguousarray(vp.T, np.float32).tobytes(), cam

    def draw(self, scene: Scene) -> None:
        """Draw ``scene`` into the renderer's framebuffer (no read-back)."""
        if self._released:
            raise GLContextError("this SceneRenderer was released; create a new one")
        c = self.ctx
        make_current(c)  # another context (a synthetic camera's) may be current
        target = self._ms_fbo if self._ms_fbo is not None else self._fbo
        target.use()
        target.clear(*scene.sky, 1.0, depth=1.0)
        vp, cam = self._vp(scene)
        c.disable(moderngl.CULL_FACE | moderngl.BLEND)
        c.enable(moderngl.DEPTH_TEST)
        c.front_face = "cw" if scene.mirror else "ccw"
        if scene.floor_spec is not None:
            c1, c2, size, tile = scene.floor_spec
            f = self._floor
            f["vp"].write(vp)  # type: ignore[union-attr]
            f["half_size"].value = size / 2.0  # type: ignore[union-attr]
            f["color1"].value = c1  # type: ignore[union-attr]
            f["color2"].value = c2  # type: ignore[union-attr]
            f["tile"].value = tile  # type: ignore[union-attr]
            f["light"].value = self._floor_light  # type: ignore[union-attr]
            self._floor_vao.render(moderngl.TRIANGLES, vertices=6)
        lit = self._lit
        lit["vp"].write(vp)  # type: ignore[union-attr]
        lit["eye"].value = tuple(float(x) for x in cam.center)  # type: ignore[union-attr]
        sph = list(scene.spheres)
        if scene.capsules:
            cap = np.asarray(scene.capsules, np.float64)
            a, b, r = cap[:, 0:3], cap[:, 3:6], cap[:, 6]
            self._cyl.draw(_basis_models(a, b, r), cap[:, 7:10].astype(np.float32))
            big = r >= 0.012  # thin rods (nets, lines) need no round ends
            ends = np.concatenate([a[big], b[big]])
            rr = np.repeat(np.concatenate([r[big], r[big]])[:, None], 3, 1)
            col = cap[big, 7:10]
            self._cap.draw(_scale_models(ends, rr), np.concatenate([col, col]).astype(np.float32))
        if sph:
            s = np.asarray(sph, np.float64)
            self._sphere.draw(_scale_models(s[:, :3], np.repeat(s[:, 3:4], 3, 1)),
                              s[:, 4:7].astype(np.float32))
        if scene.boxes:
            bx = np.asarray(scene.boxes, np.float64)
            self._box.draw(_scale_models(bx[:, :3], bx[:, 3:6], bx[:, 6]),
                           bx[:, 7:10].astype(np.float32))
        for m in scene.meshes:
            self._draw_mesh(m.vertices, m.faces, m.colors, m.two_sided)
        if scene.lines:
            ln = np.asarray(scene.lines, np.float32)
            data = np.ascontiguousarray(
                np.stack([np.hstack([ln[:, 0:3], ln[:, 6:9]]), np.hstack([ln[:, 3:6], ln[:, 6:9]])],
                         axis=1).reshape(-1, 6)
            )
            if data.nbytes > self._line_vbo.size:
                self._line_vbo.orphan(int(data.nbytes * 1.5))
            self._line_vbo.write(data.tobytes())
            self._line["vp"].write(vp)  # type: ignore[union-attr]
            self._line_vao.render(moderngl.LINES, vertices=len(data))
        if scene.shadows:
            sh = np.ascontiguousarray(scene.shadows, np.float32)
            if sh.nbytes > self._shadow_inst.size:
                self._shadow_inst.orphan(int(sh.nbytes * 1.5))
            self._shadow_inst.write(sh.tobytes())
            self._shadow["vp"].write(vp)  # type: ignore[union-attr]
            c.enable(moderngl.BLEND)
            c.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
            target.depth_mask = False
            self._shadow_vao.render(moderngl.TRIANGLES, vertices=6, instances=len(sh))
            target.depth_mask = True
            c.disable(moderngl.BLEND)
        if self._ms_fbo is not None:
            c.copy_framebuffer(self._fbo, self._ms_fbo)

    def _draw_mesh(self, v: NDArray[np.float32], f: NDArray[np.int32],
                   colors: NDArray[np.float32], two_sided: bool) -> None:
        if not len(f):
            return
        data = np.ascontiguousarray(np.hstack([v, vertex_normals(v, f), colors]), np.float32)
        for buf, arr in ((self._mesh_vbo, data), (self._mesh_ibo, f)):
            if arr.nbytes > buf.size:
                buf.orphan(int(arr.nbytes * 1.5))
            buf.write(arr.tobytes())
        if not two_sided:
            self.ctx.enable(moderngl.CULL_FACE)
        self._mesh_vao.render(moderngl.TRIANGLES, vertices=int(f.size))
        self.ctx.disable(moderngl.CULL_FACE)

    def render(self, scene: Scene) -> NDArray[np.uint8]:
        """Draw ``scene`` with its HUD and return the picture: (H, W, 3) RGB uint8,
        top row first."""
        self.draw(scene)
        img = self.read()
        if scene.texts or scene.insets:
            draw_hud(img, scene)
        return img

    def read(self) -> NDArray[np.uint8]:
        """The last drawn picture as (H, W, 3) RGB uint8, top row first."""
        make_current(self.ctx)
        self._fbo.read_into(self._rgb, components=3, alignment=1)
        img = np.frombuffer(self._rgb, np.uint8).reshape(self.height, self.width, 3)
        return np.ascontiguousarray(img[::-1])  # GL rows run bottom-up

    def present(self, image: NDArray[np.uint8]) -> None:
        """Show an (H, W, 3) RGB picture (from :meth:`render`) on the context's screen
        (a window), stretched to it."""
        make_current(self.ctx)
        if self.ctx.screen is None:  # a standalone (headless) context has no screen
            return
        self._screen_tex.write(np.ascontiguousarray(image).tobytes())
        self._screen_tex.use(0)
        self.ctx.screen.use()
        self.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        self._overlay_vao.render(moderngl.TRIANGLES, vertices=3)

    def release(self) -> None:
        """Free every GL object (and the context if this renderer created it)."""
        if self._released:
            return
        self._released = True
        make_current(self.ctx)
        self._release_objects()
        if self._owns_ctx:
            self.ctx.release()

    def _release_objects(self) -> None:
        for inst in (self._sphere, self._box, self._cyl, self._cap):
            inst.release()
        objs: list[Any] = [
            self._floor_vao, self._shadow_vao, self._mesh_vao, self._overlay_vao, self._quad,
            self._line_vao, self._line_vbo, self._line,
            self._shadow_inst, self._mesh_vbo, self._mesh_ibo, self._mesh_inst, self._screen_tex,
            self._fbo, self._color, self._depth, self._lit, self._floor, self._shadow,
            self._overlay, *self._ms,
        ]
        if self._ms_fbo is not None:
            objs.append(self._ms_fbo)
        for o in objs:
            o.release()

    def __enter__(self) -> SceneRenderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()
