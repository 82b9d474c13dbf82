"""OpenGL with moderngl: the one place that creates GL contexts, and camera matrices.

:func:`create_context` gives a headless EGL context (CI, synthetic cameras, headless
apps) or wraps the context of the current pygame OpenGL window. :func:`gl_view` and
:func:`gl_projection` turn a calibrated :class:`~bodyplay.capture.camera.Camera` into
OpenGL matrices that reproduce ``Camera.project`` pixel for pixel (pinhole part).
The renderers built on them live in :mod:`bodyplay.render.shaded` (lit meshes, id
maps) and :mod:`bodyplay.render.accumulate` (motion-blur exposures).

Headless EGL needs the system packages ``libegl1 libgl1 libgl1-mesa-dri`` (Mesa's
llvmpipe software renderer is enough).
"""

from __future__ import annotations

import moderngl
import numpy as np
from numpy.typing import NDArray

from bodyplay.capture.camera import Camera
from bodyplay.errors import BodyplayError, ConfigError

__all__ = [
    "GLContextError",
    "create_context",
    "gl_projection",
    "gl_view",
]


class GLContextError(BodyplayError, RuntimeError):
    """No OpenGL context could be created (missing EGL/Mesa, or no window)."""


def create_context(headless: bool = True) -> moderngl.Context:
    """An OpenGL 3.3+ context: standalone EGL when ``headless``, else the current window's.

    With ``headless=False`` a pygame window must already have been opened with
    ``pygame.OPENGL`` (its context is current); moderngl then draws into it.
    """
    try:
        if headless:
            return moderngl.create_standalone_context(
                backend="egl", require=330  # type: ignore[arg-type]
            )
        return moderngl.create_context(require=330)
    except Exception as exc:  # moderngl raises plain Exception subclasses
        if headless:
            raise GLContextError(
                f"could not create a headless EGL OpenGL context ({exc}); install the "
                "system packages libegl1 libgl1 libgl1-mesa-dri (Mesa's llvmpipe is "
                "enough); on machines without a GPU try EGL_PLATFORM=surfaceless"
            ) from exc
        raise GLContextError(
            f"could not use the current OpenGL context ({exc}); open a pygame window "
            "with pygame.OPENGL | pygame.DOUBLEBUF before creating the renderer"
        ) from exc


def make_current(ctx: moderngl.Context) -> None:
    """Make a standalone context current on this thread before drawing with it.

    Two standalone contexts in one thread (the synthetic camera's and a game's scene
    renderer) must each be made current before use, or the driver draws with the
    other one's objects (and crashes).
    """
    ctx.__enter__()


# ---- camera matrices -----------------------------------------------------------------


def gl_view(camera: Camera) -> NDArray[np.float64]:
    """4x4 world-to-eye matrix in OpenGL axes (x right, y up, looking down -z).

    OpenCV camera axes (x right, y down, z forward) are flipped about x.
    """
    m = np.eye(4)
    m[:3, :3] = camera.R
    m[:3, 3] = camera.t
    return np.diag([1.0, -1.0, -1.0, 1.0]) @ m


def gl_projection(camera: Camera, near: float, far: float) -> NDArray[np.float64]:
    """4x4 OpenGL projection reproducing ``camera.K`` pixel for pixel.

    OpenCV pixel ``u`` (centre of pixel ``u`` at integer ``u``) is GL window
    coordinate ``u + 0.5``; the image is drawn upside down in GL's bottom-up
    framebuffer rows and flipped on read-back, so row 0 is the top row.
    """
    if not 0 < near < far:
        raise ConfigError(f"near {near} and far {far} must satisfy 0 < near < far")
    K = camera.K
    W, H = float(camera.width), float(camera.height)
    fx, s, cx = K[0, 0], K[0, 1], K[0, 2]
    fy, cy = K[1, 1], K[1, 2]
    P = np.zeros((4, 4))
    # eye coordinates: X = x_e, Y = -y_e, Z = -z_e (OpenCV camera from GL eye)
    P[0, 0] = 2.0 * fx / W
    P[0, 1] = -2.0 * s / W
    P[0, 2] = -(2.0 * (cx + 0.5) / W - 1.0)
    P[1, 1] = 2.0 * fy / H
    P[1, 2] = 2.0 * (cy + 0.5) / H - 1.0
    P[2, 2] = -(far + near) / (far - near)
    P[2, 3] = -2.0 * far * near / (far - near)
    P[3, 2] = -1.0
    return P
