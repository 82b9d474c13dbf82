"""Renderers: numba id maps and silhouettes (batched, CPU) and moderngl shaded images.

:mod:`bodyplay.render.idmap` rasterizes many posed meshes into small id maps at once
for the trackers' pose databases; :mod:`bodyplay.render.gl` owns every OpenGL
context and the camera matrices; :mod:`bodyplay.render.shaded` draws lit meshes for
the synthetic camera and the apps, with motion-blur exposures summed in float by
:mod:`bodyplay.render.accumulate`; :mod:`bodyplay.render.scene` builds a primitive
stick figure for tests and benchmarks.
"""

from bodyplay.render.accumulate import Accumulation
from bodyplay.render.gl import GLContextError, create_context, gl_projection, gl_view
from bodyplay.render.idmap import (
    CropResult,
    IdMapRenderer,
    IdMapRendererOptions,
    crop_transform,
    project_vertices,
    rasterize_ids,
    render_crops,
    render_idmaps,
    silhouettes,
)
from bodyplay.render.scene import PrimitiveFigure, primitive_figure
from bodyplay.render.shaded import (
    DEFAULT_LIGHTS,
    Light,
    RenderMesh,
    ShadedRenderer,
    ShadedRendererOptions,
    vertex_normals,
)

__all__ = [
    "DEFAULT_LIGHTS",
    "Accumulation",
    "CropResult",
    "GLContextError",
    "IdMapRenderer",
    "IdMapRendererOptions",
    "Light",
    "PrimitiveFigure",
    "RenderMesh",
    "ShadedRenderer",
    "ShadedRendererOptions",
    "create_context",
    "crop_transform",
    "gl_projection",
    "gl_view",
    "primitive_figure",
    "project_vertices",
    "rasterize_ids",
    "render_crops",
    "render_idmaps",
    "silhouettes",
    "vertex_normals",
]
