"""Specifications of the color-shirt pose database: rendering, search, blending, cache."""

from __future__ import annotations

import time

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.body.mesh import body_mesh
from bodyplay.errors import ConfigError
from bodyplay.motion import sample_poses
from bodyplay.render.idmap import crop_transform, project_vertices
from bodyplay.trackers.colorshirt.database import (
    DatabaseOptions,
    _matvec,
    _project_crops,
    build_database,
    canonical_camera,
    load_or_build_database,
    mismatch,
    shirt_vertex_mask,
)

SK = Skeleton()


def _poses(n: int, seed: int) -> np.ndarray:
    return sample_poses(SK, n, np.random.default_rng(seed), mode="upper_body",
                        yaw_range=(-1.2, 1.2))


@pytest.fixture(scope="module")
def small_db():  # type: ignore[no-untyped-def]
    return build_database(SK, DatabaseOptions(size=600, pca_dims=32, candidates=64), _poses(600, 0))


def test_database_maps_show_the_shirt_in_a_normalized_40x40_crop(small_db) -> None:  # type: ignore[no-untyped-def]
    assert small_db.ids.shape == (600, 40, 40)
    on = small_db.ids > 0
    assert on.mean() > 0.15
    # the shirt's bounding box fills the crop up to the 5% margin on its longer side
    rows = on.any(axis=2)
    cols = on.any(axis=1)
    extent = np.maximum(rows.sum(axis=1), cols.sum(axis=1))
    assert np.median(extent) >= 34
    assert small_db.ids.max() <= 10


def test_fused_projection_matches_crop_transform() -> None:
    mesh = body_mesh(SK)
    verts = mesh.pose(SK, _poses(5, 1))
    cam = canonical_camera()
    vm = shirt_vertex_mask(mesh)
    uvz, scale, offset = _project_crops(verts, cam.R, cam.t, cam.K, vm, 40, 0.05)
    ref = crop_transform(project_vertices(verts, cam), 40, 0.05, vm)
    assert np.allclose(uvz, ref.uvz, atol=1e-3)
    assert np.allclose(scale, ref.scale, rtol=1e-5)
    assert np.allclose(offset, ref.offset, atol=1e-3)


def test_query_finds_an_entry_itself_and_agrees_with_exhaustive_search(small_db) -> None:  # type: ignore[no-untyped-def]
    nb = small_db.query(small_db.ids[17])
    assert nb.index[0] == 17 and nb.distance[0] == 0.0
    queries = build_database(SK, DatabaseOptions(size=40), _poses(40, 2)).ids
    recall = 0.0
    for q in queries:
        fast = set(small_db.query(q).index)
        exact = small_db.query(q, exact=True)
        recall += len(fast & set(exact.index)) / len(exact.index)
    assert recall / len(queries) > 0.9
    d = small_db.query(queries[0])
    assert np.allclose(d.distance, mismatch(small_db.ids[d.index], queries[0]) / 1600)


def test_query_keeps_to_poses_facing_near_the_expected_way(small_db) -> None:  # type: ignore[no-untyped-def]
    f = small_db.facings
    assert np.allclose(np.linalg.norm(f, axis=1), 1.0)
    q = small_db.ids[17]
    same = small_db.query(q, facing=f[17], min_cos=0.0)
    assert same.index[0] == 17 and np.all(f[same.index] @ f[17] >= 0.0)
    away = small_db.query(q, facing=-f[17], min_cos=0.0)  # the other half of the turns
    assert 17 not in away.index and np.all(f[away.index] @ -f[17] >= 0.0)
    # too few poses that way round: the plain search
    assert np.array_equal(small_db.query(q, facing=-f[17], min_cos=0.9999).index,
                          small_db.query(q).index)


def test_query_projection_matches_numpy_matrix_product(small_db) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(4)
    A = rng.normal(size=(300, 17)).astype(np.float32)
    x = rng.normal(size=17).astype(np.float32)
    assert np.allclose(_matvec(A, x), A @ x, atol=1e-4)
    f = small_db.query_features(small_db.ids[3])
    assert np.allclose(f, small_db.features[3], atol=1e-3)


def test_blend_of_one_pose_repeated_is_that_pose(small_db) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.colorshirt.database import Neighbours

    nb = Neighbours(np.array([5, 5, 5]), np.array([0.1, 0.2, 0.3]))
    b = small_db.blend(nb)
    ref = SK.joint_positions(small_db.poses[5].astype(float))
    assert np.allclose(SK.joint_positions(b.pose), ref, atol=1e-4)
    assert b.root_depth == pytest.approx(float(small_db.root_depth[5]), rel=1e-5)


def test_cache_is_reused_and_keyed_by_the_inputs(tmp_path) -> None:  # type: ignore[no-untyped-def]
    def src(sk, n, rng, o):  # type: ignore[no-untyped-def]
        return _poses(n, 3)

    o = DatabaseOptions(size=50, pca_dims=16, candidates=32)
    a = load_or_build_database(SK, o, tmp_path, pose_source=src)
    files = list(tmp_path.glob("colorshirt_db_*.npz"))
    assert len(files) == 1
    t0 = time.perf_counter()
    b = load_or_build_database(SK, o, tmp_path, pose_source=src)
    assert time.perf_counter() - t0 < 5.0
    assert np.array_equal(a.ids, b.ids)
    load_or_build_database(SK, DatabaseOptions(size=50, pca_dims=16, candidates=32, margin=0.1),
                           tmp_path, pose_source=src)
    assert len(list(tmp_path.glob("colorshirt_db_*.npz"))) == 2


def test_invalid_database_options_are_rejected() -> None:
    with pytest.raises(ConfigError):
        DatabaseOptions(size=5)
    with pytest.raises(ConfigError):
        DatabaseOptions(map_size=42)
    with pytest.raises(ConfigError):
        DatabaseOptions(neighbours=200, candidates=100)
