"""Specifications of the numba id-map rasterizer (bodyplay.render.idmap)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.render.idmap import (
    IdMapRenderer,
    IdMapRendererOptions,
    crop_transform,
    project_vertices,
    rasterize_ids,
    render_crops,
    render_idmaps,
    silhouettes,
)
from bodyplay.render.scene import primitive_figure


def _camera() -> Camera:
    R, t = look_at([0.4, 1.2, 3.2], [0.0, 0.95, 0.0])
    K = np.array([[150.0, 0.0, 83.0], [0.0, 148.0, 57.0], [0.0, 0.0, 1.0]])
    return Camera("cam0", 160, 120, K, R, t)


def _quad(x0: float, y0: float, x1: float, y1: float, z: float = 1.0) -> np.ndarray:
    return np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], dtype=np.float32)


QUAD_FACES = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int32)


def test_square_with_corners_between_pixels_covers_exactly_the_pixels_inside() -> None:
    ids = rasterize_ids(_quad(-0.5, 0.5, 3.5, 3.5), QUAD_FACES, [7, 7], 6, 5)
    expected = np.zeros((5, 6), np.uint8)
    expected[1:4, 0:4] = 7
    np.testing.assert_array_equal(ids, expected)


def test_triangle_covers_the_pixel_centres_inside_it() -> None:
    tri = np.array([[1.3, 0.7, 2.0], [17.6, 4.2, 2.0], [6.1, 13.9, 2.0]], np.float32)
    ids = rasterize_ids(tri, [[0, 1, 2]], [3], 20, 16)
    ys, xs = np.mgrid[0:16, 0:20]
    p = np.stack([xs, ys], -1).astype(float)
    a, b, c = tri[:, :2].astype(float)

    def side(q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
        return (q1[0] - q0[0]) * (p[..., 1] - q0[1]) - (q1[1] - q0[1]) * (p[..., 0] - q0[0])

    s = np.stack([side(a, b), side(b, c), side(c, a)])
    inside = (s > 0).all(0) | (s < 0).all(0)
    np.testing.assert_array_equal(ids == 3, inside)
    assert inside.sum() > 50


def test_top_left_rule_gives_shared_edges_to_exactly_one_triangle() -> None:
    # corners on pixel centres: the square's left/top edges are in, right/bottom out
    quad = _quad(0.0, 0.0, 4.0, 4.0)
    first = rasterize_ids(quad, QUAD_FACES[:1], [1], 6, 6) > 0
    second = rasterize_ids(quad, QUAD_FACES[1:], [1], 6, 6) > 0
    assert not np.any(first & second)
    expected = np.zeros((6, 6), bool)
    expected[0:4, 0:4] = True
    np.testing.assert_array_equal(first | second, expected)


def test_triangulated_region_is_covered_once_without_gaps() -> None:
    rng = np.random.default_rng(3)
    # vertices on a quarter-pixel grid make many pixel centres fall exactly on edges
    pts = np.round(rng.uniform(2, 30, (40, 2)) * 4) / 4
    pts = np.vstack([pts, [[2, 2], [30, 2], [30, 30], [2, 30]]])
    tri = Delaunay(pts).simplices.astype(np.int32)
    uvz = np.hstack([pts, np.ones((len(pts), 1))]).astype(np.float32)
    count = np.zeros((32, 32), int)
    for face in tri:
        count += rasterize_ids(uvz, face[None], [1], 32, 32) > 0
    ys, xs = np.mgrid[0:32, 0:32]
    interior = (xs >= 2) & (xs < 30) & (ys >= 2) & (ys < 30)
    np.testing.assert_array_equal(count, interior.astype(int))


def test_nearer_triangle_wins_whatever_the_drawing_order() -> None:
    near_quad = _quad(0.5, 0.5, 6.5, 6.5, z=1.0)
    far_quad = _quad(3.5, 3.5, 9.5, 9.5, z=2.0)
    faces_near_first = np.vstack([QUAD_FACES, QUAD_FACES + 4])
    for verts, ids in (
        (np.vstack([near_quad, far_quad]), [1, 1, 2, 2]),
        (np.vstack([far_quad, near_quad]), [2, 2, 1, 1]),
    ):
        m = rasterize_ids(verts, faces_near_first, ids, 12, 12)
        assert m[5, 5] == 1 and m[2, 2] == 1 and m[8, 8] == 2 and m[0, 0] == 0


def test_depth_output_is_the_perspective_correct_camera_depth() -> None:
    cam = _camera()
    # a tilted plane: the depth at each covered pixel is where its ray meets the plane
    corners = np.array([[-0.6, 0.4, -0.3], [0.6, 0.4, 0.4], [0.6, 1.6, 0.4], [-0.6, 1.6, -0.3]])
    uvz = project_vertices(corners, cam)
    ids, depth = rasterize_ids(uvz, QUAD_FACES, [1, 1], 160, 120, return_depth=True)
    assert np.isinf(depth[ids == 0]).all()
    pc = cam.world_to_camera(corners)
    normal = np.cross(pc[1] - pc[0], pc[3] - pc[0])
    ys, xs = np.nonzero(ids)
    rays = np.linalg.solve(cam.K, np.stack([xs, ys, np.ones_like(xs)]).astype(float)).T
    z_true = (normal @ pc[0]) / (rays @ normal)
    np.testing.assert_allclose(depth[ys, xs], z_true, rtol=2e-4)


def test_batch_equals_single_calls() -> None:
    fig = primitive_figure(5, seed=2)
    uvz = project_vertices(fig.vertices, _camera())
    batch = rasterize_ids(uvz, fig.faces, fig.face_ids, 160, 120)
    assert isinstance(batch, np.ndarray) and batch.shape == (5, 120, 160)
    for b in range(5):
        single = rasterize_ids(uvz[b], fig.faces, fig.face_ids, 160, 120)
        np.testing.assert_array_equal(batch[b], single)
    assert len(np.unique(batch)) > 5


def test_empty_scenes_are_all_background() -> None:
    cam = _camera()
    empty = rasterize_ids(np.zeros((3, 0, 3), np.float32), np.zeros((0, 3)), np.zeros(0), 40, 30)
    assert empty.shape == (3, 30, 40) and not empty.any()
    fig = primitive_figure(1)
    behind = fig.vertices + np.asarray(cam.center + [0.0, 0.0, 5.0], np.float32)
    assert not render_idmaps(behind, fig.faces, fig.face_ids, cam).any()
    aside = fig.vertices + np.array([50.0, 0.0, 0.0], np.float32)
    assert not render_idmaps(aside, fig.faces, fig.face_ids, cam).any()


def test_project_vertices_agrees_with_camera_project() -> None:
    cam = _camera()
    pts = np.random.default_rng(1).uniform([-1, 0, -1], [1, 2, 1], (50, 3))
    uvz = project_vertices(pts, cam)
    np.testing.assert_allclose(uvz[:, :2], cam.project(pts), atol=1e-3)
    np.testing.assert_allclose(uvz[:, 2], cam.world_to_camera(pts)[:, 2], rtol=1e-6)


def test_back_face_culling_keeps_the_look_of_closed_meshes() -> None:
    box = trimesh.creation.box(extents=[0.5, 0.8, 0.4])
    cam = _camera()
    ids = np.arange(1, 13, dtype=np.uint8)
    R = trimesh.transformations.euler_matrix(0.3, 0.7, 0.1)[:3, :3]
    verts = (box.vertices @ R.T + [0.0, 1.0, 0.0])[None]
    full = render_idmaps(verts, box.faces, ids, cam)
    culled = render_idmaps(verts, box.faces, ids, cam, cull_backfaces=True)
    np.testing.assert_array_equal(full, culled)
    assert len(np.unique(full)) >= 5  # three visible sides, two triangles each
    inside_out = render_idmaps(verts, box.faces[:, ::-1], ids, cam, cull_backfaces=True)
    assert not np.array_equal(inside_out, full)


def test_crop_transform_fits_each_pose_into_the_square_with_margin() -> None:
    fig = primitive_figure(4, seed=5)
    uvz = project_vertices(fig.vertices, _camera())
    crop = crop_transform(uvz, 40, margin=0.1)
    lo = crop.uvz[..., :2].min(axis=1)
    hi = crop.uvz[..., :2].max(axis=1)
    extent = (hi - lo).max(axis=1)
    np.testing.assert_allclose(extent, 32.0, rtol=1e-4)
    np.testing.assert_allclose((lo + hi) / 2, 19.5, atol=1e-3)
    np.testing.assert_allclose(crop.to_image(crop.to_crop(uvz[..., :2])), uvz[..., :2], atol=1e-3)
    ids, crop2 = render_crops(fig.vertices, fig.faces, fig.face_ids, _camera(), 40, margin=0.1)
    assert ids.shape == (4, 40, 40)
    assert not ids[:, :3].any() and not ids[:, -3:].any()  # the margin rows are empty
    np.testing.assert_allclose(crop2.scale, crop.scale)


def test_crop_transform_uses_only_masked_vertices() -> None:
    fig = primitive_figure(2, seed=6)
    uvz = project_vertices(fig.vertices, _camera())
    torso = np.zeros(fig.vertices.shape[1], bool)
    torso[np.unique(fig.faces[fig.face_ids == 1])] = True
    crop = crop_transform(uvz, 40, margin=0.0, vertex_mask=torso)
    box = crop.uvz[:, torso, :2]
    np.testing.assert_allclose((box.max(1) - box.min(1)).max(1), 40.0, rtol=1e-4)


def test_silhouettes_are_the_non_background_pixels() -> None:
    fig = primitive_figure(3, seed=4)
    cam = _camera()
    sil = silhouettes(fig.vertices, fig.faces, cam, (80, 60))
    ids = render_idmaps(fig.vertices, fig.faces, fig.face_ids, cam, (80, 60))
    assert sil.dtype == bool and sil.shape == (3, 60, 80)
    np.testing.assert_array_equal(sil, ids > 0)
    assert sil.any(axis=(1, 2)).all()


def test_renderer_class_matches_the_functions() -> None:
    fig = primitive_figure(3, seed=7)
    cam = _camera()
    r = IdMapRenderer(IdMapRendererOptions(80, 60), fig.faces, fig.face_ids)
    expected = render_idmaps(fig.vertices, fig.faces, fig.face_ids, cam, (80, 60))
    np.testing.assert_array_equal(r.render(fig.vertices, cam), expected)
    np.testing.assert_array_equal(r.render(fig.vertices[1], cam), expected[1])


def test_bad_inputs_raise_config_errors() -> None:
    with pytest.raises(ConfigError, match="uvz"):
        rasterize_ids(np.zeros((2, 3, 2)), [[0, 1, 2]], [1], 4, 4)
    with pytest.raises(ConfigError, match="faces index"):
        rasterize_ids(np.zeros((3, 3)), [[0, 1, 3]], [1], 4, 4)
    with pytest.raises(ConfigError, match="face_ids"):
        rasterize_ids(np.zeros((3, 3)), [[0, 1, 2]], [256], 4, 4)
    with pytest.raises(ConfigError, match="size"):
        rasterize_ids(np.zeros((3, 3)), [[0, 1, 2]], [1], 0, 4)
    with pytest.raises(ConfigError):
        IdMapRendererOptions(width=-1)
    r = IdMapRenderer(IdMapRendererOptions(8, 8), [[0, 1, 5]], [1])
    with pytest.raises(ConfigError, match="at least 6"):
        r.render_uvz(np.zeros((4, 3)))
