"""Renderers: numba id maps and silhouettes (batched, CPU) and moderngl shaded images.

:mod:`bodyplay.render.idmap` rasterizes many posed meshes into small id maps at once
for the trackers' pose databases; :mod:`bodyplay.render.gl` owns every OpenGL
context and draws lit meshes for the synthetic camera and the apps;
:mod:`bodyplay.render.scene` builds a primitive stick figure for tests and benchmarks.
"""

from bodyplay.render.gl import (
    DEFAULT_LIGHTS,
    GLContextError,
    Light,
    RenderMesh,
    ShadedRenderer,
    ShadedRendererOptions,
    create_context,
    gl_projection,
    gl_view,
    vertex_normals,
)
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

__all__ = [
    "DEFAULT_LIGHTS",
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
