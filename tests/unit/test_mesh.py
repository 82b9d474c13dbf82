"""Specifications of the generic body mesh and linear blend skinning."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.body import BODY_SHAPES, Skeleton
from bodyplay.body.mesh import body_mesh, build_body_mesh
from bodyplay.body.skinning import Material, SkinnedMesh
from bodyplay.errors import ConfigError


@pytest.fixture(scope="module")
def mesh(skeleton: Skeleton) -> SkinnedMesh:
    return body_mesh(skeleton)


def test_generic_mesh_has_about_four_thousand_triangles(mesh: SkinnedMesh) -> None:
    assert 3000 <= mesh.num_faces <= 6000
    assert mesh.rest_vertices.dtype == np.float32 and mesh.faces.dtype == np.int32
    assert mesh.bone_indices.shape == mesh.bone_weights.shape == (mesh.num_vertices, 4)


def test_generic_mesh_is_cached_per_skeleton(skeleton: Skeleton) -> None:
    assert body_mesh(skeleton) is body_mesh(Skeleton())
    assert body_mesh(Skeleton.from_shape("xl")) is not body_mesh(skeleton)


def test_generic_mesh_spans_the_body_from_floor_to_head_top(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
    v = mesh.rest_vertices
    top = skeleton.node_positions(skeleton.rest_pose())[skeleton.node_index("head_top"), 1]
    assert abs(v[:, 1].min()) < 0.01
    assert abs(v[:, 1].max() - top) < 0.03


def test_generic_mesh_size_follows_the_body_preset() -> None:
    for name in ("xs", "xxl"):
        sk = Skeleton.from_shape(name)
        v = body_mesh(sk).rest_vertices
        assert abs(v[:, 1].max() - BODY_SHAPES[name].height) < 0.04

    def chest_depth(name: str) -> float:
        v = body_mesh(Skeleton.from_shape(name)).rest_vertices
        band = (np.abs(v[:, 1] - 1.25) < 0.05) & (np.abs(v[:, 0]) < 0.12)
        return float(np.ptp(v[band, 2]))

    assert chest_depth("m_heavy") > 1.1 * chest_depth("m_slim")


def test_every_patch_is_on_the_generic_mesh_and_seen_from_its_side(  # type: ignore[no-untyped-def]
    mesh, skeleton, check_patches_and_views
) -> None:
    check_patches_and_views(mesh, skeleton)


def test_generic_mesh_materials_cover_skin_shirt_trousers_shoes(mesh: SkinnedMesh) -> None:
    found = set(np.unique(mesh.vertex_material).tolist())
    assert {Material.SKIN, Material.SHIRT, Material.TROUSERS, Material.SHOES} <= found
    assert np.all((mesh.face_part == 0) | (mesh.face_part <= 20))


def test_skinning_the_rest_pose_returns_the_rest_vertices(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
    out = mesh.pose(skeleton, skeleton.rest_pose())
    assert out.shape == (mesh.num_vertices, 3) and out.dtype == np.float32
    np.testing.assert_allclose(out, mesh.rest_vertices, atol=1e-5)


def test_skinning_keeps_batch_shape_and_follows_the_root(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
    q = np.tile(skeleton.rest_pose(), (2, 3, 1))
    q[1, :, 0] += 0.5
    out = mesh.pose(skeleton, q)
    assert out.shape == (2, 3, mesh.num_vertices, 3)
    np.testing.assert_allclose(out[1] - out[0], np.broadcast_to([0.5, 0, 0], out[0].shape),
                               atol=1e-5)


def test_skinning_preserves_distance_to_the_bone_of_rigid_vertices(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(3)
    lo, hi = skeleton.limits
    q = np.tile(skeleton.rest_pose(), (20, 1))
    q[:, 3:] = rng.uniform(np.maximum(lo[3:], -1.0), np.minimum(hi[3:], 1.0), (20, q.shape[1] - 3))
    posed = mesh.pose(skeleton, q).astype(np.float64)
    nodes = skeleton.node_positions(q)
    rest_nodes = skeleton.node_positions(skeleton.rest_pose())
    rigid = np.nonzero(mesh.bone_weights[:, 0] > 0.9999)[0]
    assert len(rigid) > 500
    n = mesh.bone_indices[rigid, 0]
    child = {skeleton.parents[i]: i for i in range(1, skeleton.num_nodes)}
    c = np.array([child.get(int(i), int(i)) for i in n])
    for a, b in ((n, n), (n, c)):  # distance to the node and to its child node
        d_rest = np.linalg.norm(mesh.rest_vertices[rigid] - rest_nodes[a if b is n else c], axis=1)
        d_pose = np.linalg.norm(posed[:, rigid] - nodes[:, a if b is n else c], axis=-1)
        np.testing.assert_allclose(d_pose, np.broadcast_to(d_rest, d_pose.shape), atol=2e-4)


def test_bending_the_elbow_does_not_tear_the_arm(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
    q = skeleton.pose(rotations={"l_elbow": [0, -2.2, 0], "r_elbow": [0, 2.2, 0],
                                 "l_shoulder": [0, 0, 1.2], "lumbar": [0.6, 0, 0]})
    rest = mesh.rest_vertices.astype(np.float64)
    posed = mesh.pose(skeleton, q).astype(np.float64)
    e = np.concatenate([mesh.faces[:, [0, 1]], mesh.faces[:, [1, 2]], mesh.faces[:, [2, 0]]])
    stretch = (np.linalg.norm(posed[e[:, 0]] - posed[e[:, 1]], axis=1)
               / np.linalg.norm(rest[e[:, 0]] - rest[e[:, 1]], axis=1))
    assert stretch.max() < 2.5


def test_skinning_rejects_pose_vectors_of_the_wrong_length(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError):
        mesh.pose(skeleton, np.zeros(5))


def test_skinned_mesh_rejects_weights_that_do_not_sum_to_one() -> None:
    with pytest.raises(ConfigError, match="sum to 1"):
        SkinnedMesh(np.zeros((3, 3)), np.array([[0, 1, 2]]), np.zeros((3, 1)),
                    np.full((3, 1), 0.5), np.zeros(1), np.zeros(3), np.zeros((3, 3)))


def test_build_body_mesh_accepts_explicit_rest_offsets(skeleton: Skeleton) -> None:
    off = skeleton.offsets.copy()
    off[skeleton.node_index("l_elbow")] *= 1.2
    sk = Skeleton(skeleton.shape, rest_offsets=tuple(map(tuple, off)))
    m = build_body_mesh(sk)
    assert m.rest_vertices[:, 0].max() > body_mesh(skeleton).rest_vertices[:, 0].max() + 0.04
