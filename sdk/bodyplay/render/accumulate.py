"""Motion-blur exposures: sub-frame renders summed in float on the GPU.

A webcam frame integrates light over its exposure time, so a fast limb leaves a
smear. :meth:`bodyplay.render.shaded.ShadedRenderer.accumulate` renders the meshes
of each sub-frame (no background) into a float layer and adds the layers into a
float sum target with GL blending, then reads back once: only the image window the
meshes cover (:func:`mesh_window`), with no 8-bit rounding. The result, an
:class:`Accumulation`, is composited over a background once, on the CPU
(:meth:`Accumulation.composite`), which equals averaging full renders.
:class:`FloatAccumulator` owns those float targets for one renderer.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TypeVar

import moderngl
import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError

__all__ = ["Accumulation", "FloatAccumulator", "mesh_window"]

_SubFrame = TypeVar("_SubFrame")

# A full-screen triangle copying the float layer texel for texel into the sum target.
_ADD_VS = """
#version 330
void main() {
    vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
"""

_ADD_FS = """
#version 330
uniform sampler2D layer;
out vec4 f_color;
void main() { f_color = texelFetch(layer, ivec2(gl_FragCoord.xy), 0); }
"""



@dataclass(frozen=True, eq=False)
class Accumulation:
    """Sub-frame renders of meshes (no background) summed in float: a motion-blur exposure.

    ``rgba`` (h, w, 4) float32, top row first, is the window of the (``width``,
    ``height``) frame at column ``x0``, row ``y0`` that holds every sub-frame's
    meshes (nothing was drawn outside it): rgb sums the shaded linear colour times
    coverage over the ``count`` sub-frames, alpha sums the coverage (the number of
    sub-frames covering the pixel; fractional with MSAA). :meth:`composite` puts it
    over a background, which is what averaging ``count`` full renders gives.
    """

    rgba: NDArray[np.float32]
    x0: int
    y0: int
    count: int
    width: int
    height: int

    def composite(self, background: NDArray[np.float32]) -> NDArray[np.float32]:
        """Average of the sub-frames over a linear (H, W, 3) float32 ``background`` (copied)."""
        bg = np.asarray(background, dtype=np.float32)
        if bg.shape != (self.height, self.width, 3):
            raise ConfigError(
                f"composite needs a ({self.height}, {self.width}, 3) background, got {bg.shape}"
            )
        out = bg.copy()
        h, w = self.rgba.shape[:2]
        if h and w:
            win = out[self.y0 : self.y0 + h, self.x0 : self.x0 + w]
            inv = np.float32(1.0 / self.count)
            keep = 1.0 - self.rgba[:, :, 3:] * inv  # share of the exposure the wall shows
            win *= keep
            win += self.rgba[:, :, :3] * inv
        return out



def mesh_window(vertices: ArrayLike, camera: Camera, near: float) -> tuple[int, int, int, int]:
    """Window (x0, y0, x1, y1) of ``camera``'s image, exclusive ends, holding every vertex.

    ``vertices`` (V, 3) are world points; the window is one pixel wider than their
    projections on every side (pixel x covers [x - 0.5, x + 0.5]) and clipped to
    the image; (0, 0, 0, 0) when there are no vertices or none project into the
    image. The whole image when a vertex is at or behind the ``near`` plane (its
    projection says nothing about where its triangles land).
    """
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    if not len(v):
        return (0, 0, 0, 0)
    cam = camera
    x = v @ cam.R.T + cam.t
    z = x[:, 2]
    if z.min() <= near:
        return (0, 0, cam.width, cam.height)
    K = cam.K
    u = (K[0, 0] * x[:, 0] + K[0, 1] * x[:, 1]) / z + K[0, 2]
    w = K[1, 1] * x[:, 1] / z + K[1, 2]
    x0 = max(0, int(np.floor(u.min())) - 1)
    x1 = min(cam.width, int(np.ceil(u.max())) + 2)
    y0 = max(0, int(np.floor(w.min())) - 1)
    y1 = min(cam.height, int(np.ceil(w.max())) + 2)
    if x1 <= x0 or y1 <= y0:
        return (0, 0, 0, 0)
    return (x0, y0, x1, y1)


class FloatAccumulator:
    """The float layer and sum targets of one renderer, made once and reused per exposure.

    A (``width``, ``height``) RGBA float32 layer with its depth buffer (drawn into
    through a multisampled float buffer when ``samples`` > 0), a float32 sum
    target and the program that adds the layer to the sum. :meth:`run` leaves the
    context's drawing state as it found it (blending off, moderngl's default blend
    function, no scissor) so the renderer's other draws are unaffected.
    """

    def __init__(self, ctx: moderngl.Context, width: int, height: int, samples: int) -> None:
        self.ctx = ctx
        self.width, self.height = width, height
        size = (width, height)
        self._layer = ctx.texture(size, 4, dtype="f4")
        self._layer.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._depth = ctx.depth_renderbuffer(size)
        self._sum = ctx.texture(size, 4, dtype="f4")
        self._add = ctx.program(vertex_shader=_ADD_VS, fragment_shader=_ADD_FS)
        self._layer_fbo = ctx.framebuffer([self._layer], self._depth)
        self._sum_fbo = ctx.framebuffer([self._sum])
        self._add_vao = ctx.vertex_array(self._add, [])
        self._ms_fbo: moderngl.Framebuffer | None = None
        self._ms_bufs: list[moderngl.Renderbuffer] = []
        if samples:
            mc = ctx.renderbuffer(size, 4, samples=samples, dtype="f4")
            md = ctx.depth_renderbuffer(size, samples=samples)
            self._ms_bufs = [mc, md]
            self._ms_fbo = ctx.framebuffer([mc], md)

    def run(
        self,
        sub_frames: Sequence[_SubFrame],
        draw: Callable[[_SubFrame], None],
        window: tuple[int, int, int, int],
    ) -> Accumulation:
        """Sum ``draw(sub)`` for every sub-frame inside ``window`` (x0, y0, x1, y1).

        ``draw`` issues the sub-frame's draw calls into the bound framebuffer with
        its shader already set up; depth testing is on, culling and blending off.
        Nothing outside ``window`` (top-row-first pixel bounds, exclusive ends,
        non-empty) is drawn or read.
        """
        x0, y0, x1, y1 = window
        if not (0 <= x0 < x1 <= self.width and 0 <= y0 < y1 <= self.height):
            raise ValueError(f"accumulation window {window} is empty or outside the frame")
        ctx = self.ctx
        layer_fbo, acc_fbo, ms_fbo = self._layer_fbo, self._sum_fbo, self._ms_fbo
        draw_fbo = ms_fbo if ms_fbo is not None else layer_fbo
        box = (x0, self.height - y1, x1 - x0, y1 - y0)  # GL rows count from the bottom
        for fbo in (layer_fbo, acc_fbo, draw_fbo):
            fbo.scissor = box
        acc_fbo.use()
        acc_fbo.clear(0.0, 0.0, 0.0, 0.0, viewport=box)
        ctx.disable(moderngl.CULL_FACE | moderngl.BLEND)
        if "layer" in self._add:  # the GLSL compiler drops unused uniforms
            self._add["layer"].value = 0  # type: ignore[union-attr]
        for sub in sub_frames:
            draw_fbo.use()
            draw_fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0, viewport=box)
            ctx.enable(moderngl.DEPTH_TEST)
            ctx.depth_func = "<"
            draw(sub)
            if ms_fbo is not None:
                ctx.copy_framebuffer(layer_fbo, ms_fbo)
            acc_fbo.use()
            ctx.disable(moderngl.DEPTH_TEST)
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = (moderngl.ONE, moderngl.ONE)
            self._layer.use(0)
            self._add_vao.render(moderngl.TRIANGLES, vertices=3)
            ctx.disable(moderngl.BLEND)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA)  # moderngl default
        for fbo in (layer_fbo, acc_fbo, draw_fbo):
            fbo.scissor = None  # type: ignore[assignment]  # None resets it to the full frame
        data = acc_fbo.read(viewport=box, components=4, dtype="f4", alignment=1)
        rgba = np.frombuffer(data, dtype=np.float32).reshape(y1 - y0, x1 - x0, 4)
        return Accumulation(
            np.ascontiguousarray(rgba[::-1]), x0, y0, len(sub_frames), self.width, self.height
        )

    def release(self) -> None:
        """Free the GL objects (not the context)."""
        objs: list[moderngl.Framebuffer | moderngl.Renderbuffer | moderngl.Texture
                   | moderngl.Program | moderngl.VertexArray] = [
            self._layer_fbo, self._sum_fbo, self._add_vao, self._add, self._layer,
            self._depth, self._sum,
        ]
        if self._ms_fbo is not None:
            objs += [self._ms_fbo, *self._ms_bufs]
        for obj in objs:
            obj.release()
