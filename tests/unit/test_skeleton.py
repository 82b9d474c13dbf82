"""Specifications of the skeleton: forward kinematics, pose vectors, limits, body sizes."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.body import BODY_SHAPES, JOINT_INDEX, JOINT_NAMES, Skeleton
from bodyplay.body.rotations import matrix_to_rotvec, rotation_between, rotvec_to_matrix
from bodyplay.errors import ConfigError


def _segment_lengths(sk: Skeleton, q: np.ndarray) -> np.ndarray:
    nodes = sk.node_positions(q)
    parents = np.array(sk.parents)
    child = np.arange(1, sk.num_nodes)
    return np.linalg.norm(nodes[..., child, :] - nodes[..., parents[child], :], axis=-1)


def test_rest_pose_is_a_t_pose_standing_on_the_floor_facing_plus_z(skeleton: Skeleton) -> None:
    j = skeleton.joint_positions(skeleton.rest_pose())
    assert j[JOINT_INDEX["l_wrist"], 0] > 0.6  # person's left on +X
    assert j[JOINT_INDEX["r_wrist"], 0] < -0.6
    assert np.isclose(j[JOINT_INDEX["l_wrist"], 1], j[JOINT_INDEX["l_shoulder"], 1])
    assert 0.05 < j[JOINT_INDEX["l_ankle"], 1] < 0.12
    toe = skeleton.node_positions(skeleton.rest_pose())[skeleton.node_index("l_toe")]
    assert toe[2] > 0.1  # feet point forward, +Z


def test_derived_joints_follow_the_design_definitions(skeleton: Skeleton) -> None:
    rng = np.random.default_rng(1)
    q = skeleton.clamp(skeleton.rest_pose() + rng.normal(0, 0.3, skeleton.pose_dim))
    j = skeleton.joint_positions(q)
    pelvis = (j[JOINT_INDEX["l_hip"]] + j[JOINT_INDEX["r_hip"]]) / 2
    neck = (j[JOINT_INDEX["l_shoulder"]] + j[JOINT_INDEX["r_shoulder"]]) / 2
    np.testing.assert_allclose(j[JOINT_INDEX["pelvis"]], pelvis)
    np.testing.assert_allclose(j[JOINT_INDEX["neck"]], neck)
    np.testing.assert_allclose(j[JOINT_INDEX["spine"]], pelvis + (neck - pelvis) / 3)
    np.testing.assert_allclose(j[JOINT_INDEX["chest"]], pelvis + 2 * (neck - pelvis) / 3)


def test_forward_kinematics_keeps_bone_lengths_for_any_pose(skeleton: Skeleton) -> None:
    rng = np.random.default_rng(0)
    q = rng.normal(0, 1.0, (64, skeleton.pose_dim))
    rest = _segment_lengths(skeleton, skeleton.rest_pose())
    expected = np.broadcast_to(rest, (64, rest.size))
    np.testing.assert_allclose(_segment_lengths(skeleton, q), expected, atol=1e-9)


def test_elbow_flexion_of_ninety_degrees_points_the_forearm_forward(skeleton: Skeleton) -> None:
    # left arm along +X; bending the elbow about -Y brings the forearm to +Z
    q = skeleton.pose(rotations={"l_elbow": [0.0, -np.pi / 2, 0.0]})
    j = skeleton.joint_positions(q)
    forearm = j[JOINT_INDEX["l_wrist"]] - j[JOINT_INDEX["l_elbow"]]
    np.testing.assert_allclose(forearm / np.linalg.norm(forearm), [0, 0, 1], atol=1e-9)


def test_root_rotation_turns_the_whole_body_about_the_pelvis(skeleton: Skeleton) -> None:
    q = skeleton.pose(orientation=[0, np.pi, 0])
    j = skeleton.joint_positions(q)
    rest = skeleton.joint_positions(skeleton.rest_pose())
    pelvis = rest[JOINT_INDEX["pelvis"]]
    expected = (rest - pelvis) * np.array([-1, 1, -1]) + pelvis
    np.testing.assert_allclose(j, expected, atol=1e-9)


def test_batched_kinematics_equals_one_pose_at_a_time(skeleton: Skeleton) -> None:
    rng = np.random.default_rng(3)
    q = rng.normal(0, 0.5, (2, 5, skeleton.pose_dim))
    batched = skeleton.joint_positions(q)
    assert batched.shape == (2, 5, len(JOINT_NAMES), 3)
    np.testing.assert_allclose(batched[1, 3], skeleton.joint_positions(q[1, 3]))


def test_pose_vectors_of_the_wrong_length_are_rejected_with_a_clear_error(
    skeleton: Skeleton,
) -> None:
    with pytest.raises(ConfigError, match="pose vectors must have"):
        skeleton.joint_positions(np.zeros(10))
    with pytest.raises(ConfigError, match="NaN"):
        skeleton.joint_positions(np.full(skeleton.pose_dim, np.nan))


def test_clamp_projects_into_joint_limits(skeleton: Skeleton) -> None:
    rng = np.random.default_rng(5)
    q = rng.normal(0, 3.0, (100, skeleton.pose_dim))
    assert not skeleton.within_limits(q).all()
    assert skeleton.within_limits(skeleton.clamp(q)).all()
    assert skeleton.within_limits(skeleton.rest_pose())


def test_body_presets_span_the_heights_and_scale_the_skeleton() -> None:
    heights = sorted(s.height for s in BODY_SHAPES.values())
    assert len(heights) >= 6 and heights[0] <= 1.56 and heights[-1] >= 1.94
    for shape in BODY_SHAPES.values():
        sk = Skeleton.from_shape(shape.name)
        top = sk.node_positions(sk.rest_pose())[sk.node_index("head_top"), 1]
        assert abs(top - shape.height) < 0.04, shape.name


def test_unknown_body_preset_names_the_choices() -> None:
    with pytest.raises(ConfigError, match="choose one of"):
        Skeleton.from_shape("giant")


def test_rotation_helpers_round_trip() -> None:
    rng = np.random.default_rng(7)
    rv = rng.normal(0, 1, (50, 3))
    rv = rv / np.linalg.norm(rv, axis=1, keepdims=True) * rng.uniform(0, 3.0, (50, 1))
    np.testing.assert_allclose(matrix_to_rotvec(rotvec_to_matrix(rv)), rv, atol=1e-9)
    a, b = rng.normal(size=(2, 20, 3))
    R = rotation_between(a, b)
    out = np.einsum("nij,nj->ni", R, a / np.linalg.norm(a, axis=1, keepdims=True))
    np.testing.assert_allclose(out, b / np.linalg.norm(b, axis=1, keepdims=True), atol=1e-9)


def test_rotation_conversions_agree_with_scipy_at_zero_and_half_turns() -> None:
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(3)
    rv = rng.normal(0, 1, (200, 3))
    rv = rv / np.linalg.norm(rv, axis=1, keepdims=True) * rng.uniform(0, np.pi, (200, 1))
    edge = np.array([[0, 0, 0], [1e-12, 0, 0], [np.pi, 0, 0], [0, -np.pi, 0],
                     [0, 0, np.pi - 1e-9], [2.0, -1.0, 0.5]])
    rv = np.concatenate([edge, rv])
    R = rotvec_to_matrix(rv)
    np.testing.assert_allclose(R, Rotation.from_rotvec(rv).as_matrix(), atol=1e-12)
    back = matrix_to_rotvec(R)
    # a half turn has two equal rotation vectors; compare the rotations they make
    np.testing.assert_allclose(rotvec_to_matrix(back), R, atol=1e-9)
    assert np.all(np.linalg.norm(back, axis=1) <= np.pi + 1e-9)
    assert rotvec_to_matrix(np.zeros((2, 4, 3))).shape == (2, 4, 3, 3)
    assert matrix_to_rotvec(np.eye(3)).shape == (3,)
