"""Specifications of the color-shirt 6-DOF and IK fits on patch anchors."""

from __future__ import annotations

import numpy as np

from bodyplay.body import Skeleton
from bodyplay.capture.camera import Camera, look_at
from bodyplay.trackers.colorshirt.ik import (
    KinematicSolver,
    PatchAnchors,
    default_prior_model,
)
from bodyplay.trackers.colorshirt.prediction import CropWindow, PoseRenderer

SK = Skeleton()
REN = PoseRenderer(SK)


def _cams() -> tuple[Camera, ...]:
    out = []
    for i, x in enumerate((-0.8, 0.8)):
        R, t = look_at((x, 1.3, 3.0), (0, 1.1, 0))
        out.append(Camera.from_fov(f"cam{i}", 640, 480, 60, R, t))
    return tuple(out)


def _anchors(sol: KinematicSolver, q_from: np.ndarray, q_true: np.ndarray) -> PatchAnchors:
    win = CropWindow(0, 0, 0.5, 320, 240)
    parts = []
    for ci, cam in enumerate(sol.cameras):
        r_true = REN.render(REN.vertices(q_true), cam, win)
        r_from = REN.render(REN.vertices(q_from), cam, win)
        pats = np.nonzero((r_true.stats.count > 5) & (r_from.stats.count > 5))[0]
        pats = pats[pats > 0]
        node = REN.patch_node[pats]
        local = sol.attach(q_from, node, REN.anchor_world(r_from, cam, win, pats))
        target = win.to_image(r_true.stats.centroid[pats])
        parts.append((node, local, np.full(len(pats), ci), target, pats))
    cat = [np.concatenate([p[i] for p in parts]) for i in range(5)]
    return PatchAnchors(cat[0], cat[1], cat[2].astype(np.int64), cat[3],
                        np.full(len(cat[0]), 2.0), cat[4].astype(np.int64))


def _err(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.linalg.norm(SK.joint_positions(a)[:11] - SK.joint_positions(b)[:11], axis=1)


def test_anchor_projection_matches_the_rendered_centroids() -> None:
    sol = KinematicSolver(SK, _cams())
    q = SK.pose(rotations={"l_shoulder": [0, 0.3, 0.8]})
    a = _anchors(sol, q, q)
    assert np.abs(sol.project(q, a)[0] - a.target).max() < 1e-6


def test_global_fit_recovers_a_shifted_and_turned_body() -> None:
    sol = KinematicSolver(SK, _cams())
    q_true = SK.pose(root=(0.1, 0.95, 0.05), orientation=(0, 0.25, 0))
    q_start = SK.pose(root=(0.0, 0.93, -0.1), orientation=(0, 0.0, 0))
    a = _anchors(sol, q_start, q_true)
    q = sol.solve_global(q_start, a)
    assert _err(q_start, q_true).mean() > 0.08
    assert _err(q, q_true).mean() < 0.03


def test_ik_with_two_cameras_recovers_arm_poses() -> None:
    sol = KinematicSolver(SK, _cams())
    rot_true = {"l_shoulder": [0.3, 0.2, 0.9], "l_elbow": [0, -0.9, 0],
                "r_shoulder": [0, -0.4, -0.6], "r_elbow": [0, 1.1, 0]}
    q_true = SK.pose(rotations=rot_true)
    q_start = SK.pose(rotations={"l_shoulder": [0, 0, 0.5], "l_elbow": [0, -0.4, 0],
                                 "r_shoulder": [0, 0, -0.3], "r_elbow": [0, 0.5, 0]})
    q = q_start
    for _ in range(2):  # re-anchoring once more, as after a fresh render
        q = sol.solve_ik(q, _anchors(sol, q, q_true), default_prior_model(), None)
    assert _err(q_start, q_true).max() > 0.15
    assert _err(q, q_true).mean() < 0.05
    assert SK.within_limits(q, tol=1e-6)


def test_patch_stats_counts_centroids_and_mean_depths_per_id() -> None:
    from bodyplay.trackers.colorshirt.prediction import patch_stats

    ids = np.zeros((6, 8), np.uint8)
    ids[1:3, 2:6] = 4  # 8 pixels, centroid (3.5, 1.5)
    ids[5, 7] = 20
    ids[0, 0] = 200  # not a patch id: ignored
    depth = np.full((6, 8), np.inf, np.float32)
    depth[1:3, 2:6] = 2.0
    depth[1, 2] = 4.0
    stats, mean_depth = patch_stats(ids, depth)
    assert stats.count[4] == 8 and stats.count[20] == 1 and stats.count.sum() == 47
    np.testing.assert_allclose(stats.centroid[4], (3.5, 1.5))
    np.testing.assert_allclose(stats.centroid[20], (7.0, 5.0))
    assert mean_depth is not None
    assert mean_depth[4] == (7 * 2.0 + 4.0) / 8
    assert mean_depth[20] == 0.0  # an infinite depth (nothing rendered) adds nothing
    assert patch_stats(ids)[1] is None


def test_root_prior_pins_the_depth_one_camera_cannot_tell() -> None:
    from bodyplay.trackers.colorshirt.ik import RootPrior

    cam = _cams()[:1]
    sol = KinematicSolver(SK, cam)
    q_true = SK.pose(root=(0.0, 0.95, 0.0))
    a = _anchors(sol, q_true, q_true)
    # the anchors hold exactly at the truth; a prior 30 cm deeper must move the root
    # back along the camera's axis, a prior at the true depth must keep it
    depth = float(cam[0].world_to_camera(q_true[None, :3])[0, 2])
    for offset in (0.0, 0.3):
        prior = RootPrior.camera_depth(cam[0], depth + offset, 0.01)
        q = sol.solve_global(q_true, a, root_priors=(prior,))
        got = float(cam[0].world_to_camera(q[None, :3])[0, 2])
        assert abs(got - (depth + offset)) < (0.02 if offset == 0 else 0.1)
        q_ik = sol.solve_ik(q_true, a, default_prior_model(), None, root_priors=(prior,))
        got_ik = float(cam[0].world_to_camera(q_ik[None, :3])[0, 2])
        assert abs(got_ik - depth) < 0.02 if offset == 0 else got_ik - depth > 0.1


def test_global_fit_without_a_position_prior_reads_the_depth_from_the_layout() -> None:
    cam = _cams()[:1]
    sol = KinematicSolver(SK, cam)
    q_true = SK.pose(root=(0.0, 0.95, 0.0))
    # a placement 20% too far along the camera's ray (the shirt's extent read far)
    centre = cam[0].center
    q_far = q_true.copy()
    q_far[:3] = centre + (q_true[:3] - centre) * 1.2
    a = _anchors(sol, q_far, q_true)

    def depth(q: np.ndarray) -> float:
        return float(cam[0].world_to_camera(q[None, :3])[0, 2])

    true = depth(q_true)
    held = depth(sol.solve_global(q_far, a))
    free = depth(sol.solve_global(q_far, a, position_std=np.inf))
    loose = depth(sol.solve_global(q_far, a, position_std=1.0))  # a lone camera's hold
    assert held - true > 0.05  # the 0.3 m prior keeps part of the wrong depth
    assert abs(free - true) < 0.02  # the torso's layout alone tells it
    assert abs(loose - true) < 0.03


def _turn(q: np.ndarray) -> float:
    """The shoulders' turn about the vertical (rad; 0: square to the cameras)."""
    j = SK.joint_positions(q)
    v = j[5] - j[8]
    return float(np.arctan2(-v[2], v[0]))


def test_turn_std_holds_the_trunks_turn_that_one_camera_barely_sees() -> None:
    cam = _cams()[:1]
    sol = KinematicSolver(SK, cam)
    q_start = SK.pose(root=(0.0, 0.95, 0.0))
    q_true = SK.pose(root=(0.0, 0.95, 0.0), orientation=(0, 0.4, 0))
    a = _anchors(sol, q_start, q_true)
    free = sol.solve_global(q_start, a)
    held = sol.solve_global(q_start, a, turn_std=0.02)
    assert abs(_turn(free)) > 0.2  # loosely held (0.3 rad), the fit follows the anchors
    assert abs(_turn(held)) < 0.05  # held, it keeps the start's turn
    ik_free = sol.solve_ik(q_start, a, default_prior_model(), None)
    ik_held = sol.solve_ik(q_start, a, default_prior_model(), None, turn_std=0.02)
    assert abs(_turn(ik_held)) < abs(_turn(ik_free)) - 0.1
    assert np.array_equal(sol.solve_global(q_start, a, turn_std=None), free)
