"""Specifications of bodyplay.motion.sampling: pose databases within the joint limits."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.motion import (
    SAMPLING_MODES,
    random_upper_body,
    sample_poses,
    uniform_subsample,
)


def _yaw(poses: np.ndarray) -> np.ndarray:
    fwd = Rotation.from_rotvec(poses[:, 3:6]).apply([0.0, 0.0, 1.0])
    return np.arctan2(fwd[:, 0], fwd[:, 2])


@pytest.mark.parametrize("mode", SAMPLING_MODES)
def test_sample_poses_stay_within_the_joint_limits(mode: str) -> None:
    sk = Skeleton.from_shape("l")
    q = sample_poses(sk, 300, np.random.default_rng(0), clips=["131_03"], mode=mode)
    assert q.shape == (300, sk.pose_dim)
    assert np.all(sk.within_limits(q))
    assert np.all(np.isfinite(q))


def test_sample_poses_is_reproducible_from_the_generator() -> None:
    sk = Skeleton()
    a = sample_poses(sk, 50, np.random.default_rng(7), clips=["131_03"])
    b = sample_poses(sk, 50, np.random.default_rng(7), clips=["131_03"])
    assert np.array_equal(a, b)


def test_upper_body_poses_face_the_camera_within_the_yaw_range() -> None:
    sk = Skeleton()
    q = random_upper_body(sk, 500, np.random.default_rng(1), yaw_range=(-np.pi / 2, np.pi / 2))
    yaw = np.degrees(_yaw(q))
    assert np.all(np.abs(yaw) < 90.0 + 10.0)  # tilt adds a little
    assert yaw.min() < -60 and yaw.max() > 60
    # arms move: elbows bend over their range, shoulders vary
    e = 3 + 3 * sk.node_index("l_elbow")
    assert q[:, e + 1].min() < -2.0 and q[:, e + 1].max() > -0.5


def test_clip_frames_get_a_random_yaw_all_round() -> None:
    sk = Skeleton()
    q = sample_poses(sk, 400, np.random.default_rng(2), clips=["131_01"], mode="clips")
    yaw = np.degrees(_yaw(q))
    assert yaw.min() < -150 and yaw.max() > 150
    assert np.allclose(q[:, [0, 2]], 0.0, atol=1e-9)  # centred over the origin


def test_uniform_subsample_spreads_poses_wider_than_random_choice() -> None:
    sk = Skeleton()
    rng = np.random.default_rng(3)
    pool = sample_poses(sk, 1500, rng, clips=["131_03"], mode="mixed")
    k = 100
    far = uniform_subsample(sk, pool, k, rng)
    assert len(set(far.tolist())) == k
    rand = rng.choice(len(pool), k, replace=False)

    def min_gap(idx: np.ndarray) -> float:
        J = sk.joint_positions(pool[idx])
        J = (J - J[:, :1]).reshape(k, -1)
        d = np.linalg.norm(J[:, None] - J[None], axis=-1)
        return float(np.min(d + np.eye(k) * 1e9))

    assert min_gap(far) > 2.0 * min_gap(rand)


def test_sample_poses_with_oversampling_returns_n_spread_poses() -> None:
    sk = Skeleton()
    q = sample_poses(sk, 80, np.random.default_rng(4), mode="upper_body", oversample=3)
    assert q.shape == (80, sk.pose_dim) and np.all(sk.within_limits(q))


def test_sample_poses_rejects_bad_arguments() -> None:
    sk = Skeleton()
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError, match="mode"):
        sample_poses(sk, 10, rng, mode="everything")
    with pytest.raises(ConfigError, match="n must"):
        sample_poses(sk, 0, rng)
    with pytest.raises(ConfigError, match="yaw_range"):
        sample_poses(sk, 10, rng, mode="upper_body", yaw_range=(1.0, -1.0))
    with pytest.raises(ConfigError, match="blend_share"):
        sample_poses(sk, 10, rng, mode="upper_body", blend_share=2.0)
