"""Specifications of the synthetic actor (MakeHuman mesh with its own skeleton)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from bodyplay.body import BODY_SHAPES, JOINT_INDEX
from bodyplay.body.actor import Actor, actor_asset_path, load_actor
from bodyplay.body.skinning import Material
from bodyplay.errors import ConfigError


@pytest.fixture(scope="module")
def actor() -> Actor:
    return load_actor("m")


def _inside_local_hull(point: np.ndarray, verts: np.ndarray, radius: float) -> bool:
    """Whether ``point`` lies in the convex hull of the mesh vertices within ``radius``.

    Tested against the hull's facet planes (outward normals): a Delaunay point
    location gives the same answer but its LAPACK calls crawl when BLAS threads
    compete for a busy 2-core machine.
    """
    near = verts[np.linalg.norm(verts - point, axis=1) < radius]
    if len(near) <= 10:
        return False
    planes = ConvexHull(near).equations
    return bool(np.all(planes[:, :3] @ point + planes[:, 3] <= 1e-12))


def test_actor_asset_is_small_and_carries_its_licence_notice() -> None:
    path = actor_asset_path()
    assert os.path.getsize(path) < 5_000_000
    with np.load(path, allow_pickle=False) as z:
        assert "CC0" in str(z["notice"])


def test_actor_is_cached_and_unknown_presets_are_rejected(actor: Actor) -> None:
    assert load_actor("m") is actor
    with pytest.raises(ConfigError, match="unknown body preset"):
        load_actor("gigantic")


def test_actor_rest_pose_is_a_t_pose_with_straight_arms(actor: Actor) -> None:
    sk = actor.skeleton
    nodes = sk.node_positions(sk.rest_pose())
    for side, sign in (("l", 1.0), ("r", -1.0)):
        chain = nodes[[sk.node_index(f"{side}_{n}") for n in ("shoulder", "elbow", "wrist")]]
        d = np.diff(chain, axis=0)
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        np.testing.assert_allclose(d, [[sign, 0, 0]] * 2, atol=1e-3)
    v = actor.mesh.rest_vertices
    hands = v[np.abs(v[:, 0]) > 0.6]
    assert np.ptp(hands[:, 1]) < 0.2  # hands out at shoulder height, not hanging down


def test_skinning_the_actor_rest_pose_returns_its_rest_vertices(actor: Actor) -> None:
    out = actor.pose(actor.skeleton.rest_pose())
    np.testing.assert_allclose(out, actor.mesh.rest_vertices, atol=1e-5)


@pytest.mark.parametrize("bent", [False, True])
def test_truth_joints_lie_inside_the_actor_mesh(actor: Actor, bent: bool) -> None:
    sk = actor.skeleton
    q = sk.rest_pose()
    if bent:
        q = sk.pose(rotations={"l_shoulder": [0, 0, 0.9], "l_elbow": [0, -1.4, 0],
                               "r_shoulder": [0, 0.6, 0], "r_elbow": [0, 1.0, 0],
                               "l_hip": [-0.8, 0, 0], "l_knee": [1.0, 0, 0]})
    verts = actor.pose(q).astype(np.float64)
    joints = sk.joint_positions(q)
    for name, radius in (("l_wrist", 0.06), ("r_wrist", 0.06), ("l_elbow", 0.07),
                         ("r_elbow", 0.07), ("l_shoulder", 0.09), ("r_shoulder", 0.09),
                         ("l_knee", 0.09), ("r_knee", 0.09), ("l_ankle", 0.08),
                         ("r_ankle", 0.08), ("l_hip", 0.15), ("r_hip", 0.15),
                         ("head", 0.12), ("pelvis", 0.2), ("chest", 0.2)):
        assert _inside_local_hull(joints[JOINT_INDEX[name]], verts, radius), name


def test_every_patch_is_on_the_actor_and_seen_from_its_side(  # type: ignore[no-untyped-def]
    actor, check_patches_and_views
) -> None:
    check_patches_and_views(actor.mesh, actor.skeleton)


def test_actor_wears_skin_shirt_trousers_and_shoes(actor: Actor) -> None:
    m = actor.mesh
    v = m.rest_vertices
    mat = m.vertex_material
    head = v[:, 1] > actor.skeleton.node_positions(actor.skeleton.rest_pose())[4, 1]
    assert np.all(mat[head] == Material.SKIN)
    assert np.mean(mat[v[:, 1] < 0.03] == Material.SHOES) > 0.95
    knees = np.abs(v[:, 1] - 0.5) < 0.05
    assert np.mean(mat[knees] == Material.TROUSERS) > 0.95
    hands = np.abs(v[:, 0]) > 0.72
    assert np.all(mat[hands] == Material.SKIN)


@pytest.mark.parametrize("name", ["xs", "m", "m_heavy", "xxl"])
def test_actor_presets_have_the_declared_height_and_stand_on_the_floor(name: str) -> None:
    a = load_actor(name)
    v = a.mesh.rest_vertices
    assert abs(v[:, 1].max() - BODY_SHAPES[name].height) < 0.015
    assert abs(v[:, 1].min()) < 0.012


def test_actor_girth_thickens_the_limbs(actor: Actor) -> None:
    heavy = load_actor("m_heavy")

    def thigh_width(a: Actor) -> float:
        v = a.mesh.rest_vertices
        band = (np.abs(v[:, 1] - 0.65) < 0.02) & (v[:, 0] > 0.02)
        return float(np.ptp(v[band, 0]))

    assert thigh_width(heavy) > 1.1 * thigh_width(actor)
