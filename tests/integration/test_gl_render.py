"""Specifications of the moderngl renderers (bodyplay.render.gl, .shaded, .accumulate),
checked against the numba rasterizer and the Camera's projection."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.render.gl import GLContextError, create_context, gl_projection, gl_view
from bodyplay.render.idmap import render_idmaps, silhouettes
from bodyplay.render.scene import primitive_figure
from bodyplay.render.shaded import Light, RenderMesh, ShadedRenderer, ShadedRendererOptions


def _camera(width: int = 640, height: int = 480) -> Camera:
    """An off-centre principal point and unequal focal lengths catch axis mix-ups."""
    R, t = look_at([0.5, 1.3, 3.1], [0.0, 0.95, 0.0])
    K = np.array([[560.0, 0.0, 300.0], [0.0, 548.0, 262.0], [0.0, 0.0, 1.0]])
    return Camera("cam0", 640, 480, K, R, t).with_size(width, height)


@pytest.fixture(scope="module")
def gl_ctx() -> Iterator[object]:
    try:
        ctx = create_context(headless=True)
    except GLContextError as exc:
        pytest.skip(f"no headless EGL OpenGL context: {exc}")
    yield ctx
    ctx.release()


def test_gl_matrices_project_like_the_camera() -> None:
    cam = _camera()
    pts = np.random.default_rng(0).uniform([-1, 0, -1], [1, 2, 1], (30, 3))
    clip = (gl_projection(cam, 0.05, 50.0) @ gl_view(cam) @ np.c_[pts, np.ones(30)].T).T
    ndc = clip[:, :3] / clip[:, 3:]
    # GL window coordinates, rows counted from the top, pixel centres at +0.5
    u = (ndc[:, 0] + 1) / 2 * cam.width - 0.5
    v = (1 - ndc[:, 1]) / 2 * cam.height - 0.5
    np.testing.assert_allclose(np.c_[u, v], cam.project(pts), atol=1e-6)
    assert np.all(np.abs(ndc[:, 2]) < 1)


@pytest.mark.gl
@pytest.mark.parametrize("size", [(160, 120), (640, 480)])
def test_gl_and_numba_id_maps_agree(gl_ctx: object, size: tuple[int, int]) -> None:
    fig = primitive_figure(3, seed=11)
    cam = _camera()
    numba_maps = render_idmaps(fig.vertices, fig.faces, fig.face_ids, cam, size)
    with ShadedRenderer(ShadedRendererOptions(*size), ctx=gl_ctx) as r:  # type: ignore[arg-type]
        for b in range(3):
            gl_map = r.render_ids(fig.vertices[b], fig.faces, fig.face_ids, cam)
            assert gl_map.shape == (size[1], size[0])
            assert (gl_map == numba_maps[b]).mean() >= 0.99
            assert len(np.unique(gl_map)) >= 8  # most parts visible: a real comparison


@pytest.mark.gl
def test_shaded_image_lines_up_with_the_numba_silhouette(gl_ctx: object) -> None:
    fig = primitive_figure(1, seed=12)
    cam = _camera()
    with ShadedRenderer(ShadedRendererOptions(), ctx=gl_ctx) as r:  # type: ignore[arg-type]
        img = r.render(RenderMesh(fig.vertices[0], fig.faces, fig.colors), cam)
    assert img.shape == (480, 640, 3) and img.dtype == np.uint8
    sil = silhouettes(fig.vertices, fig.faces, cam)[0]
    assert sil.mean() > 0.02
    assert ((img.max(axis=2) > 0) == sil).mean() >= 0.995


@pytest.mark.gl
def test_background_is_drawn_upright_behind_the_meshes(gl_ctx: object) -> None:
    bg = np.zeros((30, 20, 3), np.uint8)
    bg[:15, :, 0] = 255  # top half red
    bg[15:, :, 2] = 255  # bottom half blue
    fig = primitive_figure(1, seed=13)
    cam = _camera(160, 120)
    with ShadedRenderer(ShadedRendererOptions(160, 120), ctx=gl_ctx) as r:  # type: ignore[arg-type]
        img = r.render([], cam, background=bg)
        np.testing.assert_array_equal(img[5, 80], [255, 0, 0])
        np.testing.assert_array_equal(img[115, 80], [0, 0, 255])
        with_fig = r.render(RenderMesh(fig.vertices[0], fig.faces, fig.colors), cam, bg)
    sil = silhouettes(fig.vertices, fig.faces, cam)[0]
    changed = np.any(with_fig != img, axis=2)
    assert (changed == sil).mean() > 0.99


@pytest.mark.gl
def test_coloured_lights_tint_a_white_surface(gl_ctx: object) -> None:
    cam = _camera(160, 120)
    # a square facing the camera, wound counter-clockwise towards it
    c = cam.center
    centre = np.array([0.0, 0.95, 0.0])
    d = (c - centre) / np.linalg.norm(c - centre)
    right = np.cross([0.0, 1.0, 0.0], d)
    right /= np.linalg.norm(right)
    up = np.cross(d, right)
    quad = np.array([centre + 0.3 * (sx * right + sy * up) for sx, sy in
                     [(-1, -1), (1, -1), (1, 1), (-1, 1)]], np.float32)
    mesh = RenderMesh(quad, [[0, 1, 2], [0, 2, 3]], colors=(1.0, 1.0, 1.0))
    opts = ShadedRendererOptions(160, 120, ambient=0.0, specular=0.0)
    with ShadedRenderer(opts, ctx=gl_ctx) as r:  # type: ignore[arg-type]
        red = r.render(mesh, cam, lights=[Light(color=(1, 0, 0), direction=tuple(-d))])
        green_point = r.render(mesh, cam, lights=[Light(color=(0, 1, 0), position=tuple(c))])
        dark = r.render(mesh, cam, lights=[Light(direction=tuple(d))])  # from behind
    px = tuple(np.round(cam.project(centre)).astype(int))[::-1]
    assert red[px][0] > 240 and red[px][1] == 0 and red[px][2] == 0
    assert green_point[px][1] > 240 and green_point[px][0] == 0
    assert dark.max() == 0


@pytest.mark.gl
def test_msaa_renders_the_same_scene_with_smoothed_edges(gl_ctx: object) -> None:
    fig = primitive_figure(1, seed=14)
    cam = _camera()
    mesh = RenderMesh(fig.vertices[0], fig.faces, fig.colors)
    with ShadedRenderer(ShadedRendererOptions(), ctx=gl_ctx) as plain, ShadedRenderer(  # type: ignore[arg-type]
        ShadedRendererOptions(samples=4), ctx=gl_ctx  # type: ignore[arg-type]
    ) as msaa:
        a = plain.render(mesh, cam).astype(int)
        b = msaa.render(mesh, cam).astype(int)
    differ = np.abs(a - b).max(axis=2) > 8
    assert 0 < differ.mean() < 0.02  # only edge pixels change


@pytest.mark.gl
def test_renderer_reuses_buffers_across_frames_and_mesh_sizes(gl_ctx: object) -> None:
    small = primitive_figure(2, seed=15, sections=6)
    big = primitive_figure(2, seed=15, sections=24)
    cam = _camera(160, 120)
    with ShadedRenderer(ShadedRendererOptions(160, 120), ctx=gl_ctx) as r:  # type: ignore[arg-type]
        frames = []
        for fig in (small, big, small):
            meshes = [RenderMesh(fig.vertices[b], fig.faces, fig.colors) for b in range(2)]
            frames.append(r.render(meshes, cam))
        assert len(r._slots) == 2
    np.testing.assert_array_equal(frames[0], frames[2])
    assert not np.array_equal(frames[0], frames[1])


@pytest.mark.gl
def test_released_renderer_refuses_to_render(gl_ctx: object) -> None:
    r = ShadedRenderer(ShadedRendererOptions(32, 24), ctx=gl_ctx)  # type: ignore[arg-type]
    r.release()
    r.release()  # twice is harmless
    fig = primitive_figure(1)
    with pytest.raises(GLContextError, match="released"):
        r.render(RenderMesh(fig.vertices[0], fig.faces), _camera())


def test_renderer_options_and_lights_are_validated() -> None:
    with pytest.raises(ConfigError, match="samples"):
        ShadedRendererOptions(samples=3)
    with pytest.raises(ConfigError, match="exactly one"):
        Light()
    with pytest.raises(ConfigError, match="exactly one"):
        Light(direction=(0, 0, 1), position=(0, 0, 0))
    with pytest.raises(ConfigError, match="colors"):
        RenderMesh(np.zeros((3, 3)), [[0, 1, 2]], colors=np.zeros((2, 3)))


@pytest.mark.gl
def test_closed_meshes_cull_back_faces_without_changing_the_picture(gl_ctx: object) -> None:
    fig = primitive_figure(1, seed=16)  # trimesh primitives: watertight, wound outwards
    cam = _camera(160, 120)
    with ShadedRenderer(ShadedRendererOptions(160, 120), ctx=gl_ctx) as r:  # type: ignore[arg-type]
        two_sided = r.render(RenderMesh(fig.vertices[0], fig.faces, fig.colors), cam)
        culled = r.render(RenderMesh(fig.vertices[0], fig.faces, fig.colors, closed=True), cam)
        inside_out = r.render(
            RenderMesh(fig.vertices[0], fig.faces[:, ::-1], fig.colors, closed=True), cam
        )
    assert two_sided.max(axis=2).mean() > 5  # the figure is in view
    assert (np.abs(two_sided.astype(int) - culled).max(axis=2) <= 1).mean() >= 0.999
    # wound the wrong way, a closed mesh shows its far side: proof faces are culled
    assert (np.abs(two_sided.astype(int) - inside_out).max(axis=2) > 8).mean() > 0.005


@pytest.mark.gl
def test_one_accumulated_sub_frame_composites_to_the_rendered_image(gl_ctx: object) -> None:
    fig = primitive_figure(1, seed=17)
    cam = _camera(160, 120)
    bg = np.random.default_rng(1).integers(0, 256, (120, 160, 3), dtype=np.uint8)
    mesh = RenderMesh(fig.vertices[0], fig.faces, fig.colors)
    with ShadedRenderer(ShadedRendererOptions(160, 120), ctx=gl_ctx) as r:  # type: ignore[arg-type]
        img = r.render(mesh, cam, background=bg)
        acc = r.accumulate([mesh], cam)
    assert acc.count == 1 and (acc.width, acc.height) == (160, 120)
    h, w = acc.rgba.shape[:2]
    assert 0 < h < 120 and 0 < w < 160  # a window around the figure, not the frame
    assert set(np.unique(acc.rgba[:, :, 3])) == {0.0, 1.0}  # no MSAA: all or nothing
    out = acc.composite((bg / 255).astype(np.float32))
    np.testing.assert_allclose(out * 255, img, atol=1.0)
    sil = silhouettes(fig.vertices, fig.faces, cam)[0]
    covered = np.zeros((120, 160), bool)
    covered[acc.y0 : acc.y0 + h, acc.x0 : acc.x0 + w] = acc.rgba[:, :, 3] > 0
    assert (covered == sil).mean() >= 0.995


@pytest.mark.gl
def test_accumulated_sub_frames_average_like_separate_renders(gl_ctx: object) -> None:
    fig = primitive_figure(3, seed=18)
    cam = _camera(160, 120)
    bg = np.full((120, 160, 3), 90, np.uint8)
    subs = [RenderMesh(fig.vertices[b], fig.faces, fig.colors) for b in range(3)]
    opts = ShadedRendererOptions(160, 120, samples=4)
    with ShadedRenderer(opts, ctx=gl_ctx) as r:  # type: ignore[arg-type]
        renders = [r.render(m, cam, background=bg).astype(np.float64) for m in subs]
        acc = r.accumulate(subs, cam)
        empty = r.accumulate([[]], cam)
        with pytest.raises(ConfigError, match="at least one"):
            r.accumulate([], cam)
    assert acc.count == 3 and acc.rgba[:, :, 3].max() == pytest.approx(3.0)
    out = acc.composite((bg / 255).astype(np.float32)) * 255
    np.testing.assert_allclose(out, np.mean(renders, axis=0), atol=1.5)
    assert empty.rgba.shape == (0, 0, 4) and empty.count == 1
    np.testing.assert_array_equal(empty.composite(bg.astype(np.float32)), bg)
