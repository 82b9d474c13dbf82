"""Specifications of the virtual keeper: mocap idle, IK reaches, timing and continuity."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError
from bodyplay.virtual import (
    IdleMotion,
    ReachController,
    effector_points,
    make_reach_options,
    min_jerk,
    solve_reach,
)


@pytest.fixture(scope="module")
def actor_skeleton():  # type: ignore[no-untyped-def]
    from bodyplay.body.actor import load_actor

    return load_actor("m").skeleton


@pytest.fixture(scope="module")
def idle(actor_skeleton):  # type: ignore[no-untyped-def]
    return IdleMotion(actor_skeleton)


@pytest.fixture()
def keeper(actor_skeleton, idle):  # type: ignore[no-untyped-def]
    return ReachController(actor_skeleton, idle=idle)


def _palm_speeds(ctrl: ReachController, times: np.ndarray, effector: str) -> np.ndarray:
    pts = np.stack([ctrl.effector_at(float(t), effector) for t in times])
    return np.linalg.norm(np.diff(pts, axis=0), axis=-1).max(axis=1) / np.diff(times)


def test_idle_motion_loops_without_jumps_and_repeats_each_period(idle, actor_skeleton) -> None:
    times = np.arange(0.0, 2.2 * idle.period, 1.0 / 240.0)
    joints = actor_skeleton.joint_positions(idle.poses_at(times))
    speed = np.linalg.norm(np.diff(joints, axis=0), axis=-1) * 240.0
    assert speed.max() < 1.0  # a calm stance: no joint ever jumps
    np.testing.assert_allclose(idle.pose_at(0.3), idle.pose_at(0.3 + idle.period), atol=1e-6)
    assert np.ptp(joints[:, :, 1]) > 0  # it does move (real motion, not a still)
    assert speed.mean() > 0.01


def test_idle_motion_stands_on_the_spot_facing_plus_z(actor_skeleton) -> None:
    idle = IdleMotion(actor_skeleton, at=(1.0, -2.0))
    j = actor_skeleton.joint_positions(idle.poses_at(np.linspace(0, idle.period, 20)))
    assert np.allclose(j[:, 0, [0, 2]].mean(0), (1.0, -2.0), atol=0.03)
    left = (j[:, 5] - j[:, 8]).mean(0)  # l_shoulder - r_shoulder: the person's left is +X
    assert left[0] > 0.25 and abs(left[2]) < 0.08
    assert j[:, [13, 16], 1].min() > 0.0  # ankles above the floor


def test_idle_motion_rejects_a_segment_outside_the_clip(actor_skeleton) -> None:
    with pytest.raises(ConfigError, match="after the clip"):
        IdleMotion(actor_skeleton, start=0.0, end=400.0)


@pytest.mark.parametrize(
    ("target", "effector"),
    [((0.5, 1.25, 0.3), "left"), ((-0.55, 1.5, 0.3), "right"), ((0.0, 1.1, 0.35), "both"),
     ((0.02, 1.63, 0.25), "head"), ((-0.35, 0.8, 0.35), "right"), ((0.9, 1.0, 0.3), "left"),
     ((0.4, 0.3, 0.35), "left"), ((0.0, 0.35, 0.4), "both")],
)
def test_keeper_reaches_reachable_targets_by_the_arrival(keeper, target, effector) -> None:
    keeper.pose_at(0.0)
    plan = keeper.set_target(1.0, target, now=0.2)
    assert plan.effector == effector
    assert plan.reachable and plan.on_time
    pts = keeper.effector_at(1.0, effector)
    assert np.linalg.norm(pts - plan.reach.targets, axis=-1).max() < 0.03


def test_far_ball_makes_the_keeper_step_and_near_ball_does_not(keeper) -> None:
    near = keeper.set_target(1.0, (0.45, 1.3, 0.3), now=0.0)
    far = keeper.set_target(3.0, (1.1, 1.2, 0.3), now=2.0)
    assert np.linalg.norm(near.reach.shift) < 0.05
    assert far.reach.shift[0] > 0.15 and far.reachable


def test_low_ball_makes_the_keeper_crouch_with_the_feet_planted(keeper, actor_skeleton) -> None:
    base = actor_skeleton.joint_positions(keeper.base_at(1.0))
    plan = keeper.set_target(1.0, (-0.35, 0.3, 0.35), now=0.0)
    assert plan.reachable and plan.reach.shift[1] < -0.15
    j = keeper.joints_at(1.0)
    assert j[0, 1] < base[0, 1] - 0.15  # the pelvis went down
    # the ankles stay on the floor; only the leading (right) foot may step sideways
    np.testing.assert_allclose(j[[13, 16], 1], base[[13, 16], 1], atol=0.01)
    assert np.linalg.norm(j[13] - base[13]) < 0.02
    assert j[15, 1] < base[15, 1] - 0.05  # the knees bend


def test_a_step_moves_the_leading_foot_and_keeps_the_trailing_one(keeper, actor_skeleton) -> None:
    base = actor_skeleton.joint_positions(keeper.base_at(1.0))
    plan = keeper.set_target(1.0, (1.05, 1.15, 0.3), now=0.0)
    assert plan.reachable and plan.reach.shift[0] > 0.15
    j = keeper.joints_at(1.0)
    moved = j[[13, 16]] - base[[13, 16]]
    assert moved[0, 0] > 0.1  # left foot leads to the left
    assert np.linalg.norm(moved[1]) < 0.02  # right foot planted
    np.testing.assert_allclose(j[[13, 16], 1], base[[13, 16], 1], atol=0.01)


def test_unreachable_target_is_approached_within_joint_limits(keeper, actor_skeleton) -> None:
    target = np.array([-2.0, 2.3, 0.3])
    before = np.linalg.norm(keeper.effector_at(0.0, "right") - target)
    plan = keeper.set_target(1.0, target, now=0.0)
    assert not plan.reachable
    after = np.linalg.norm(keeper.effector_at(1.0, "right") - target)
    assert after < before - 0.5  # it stretches towards the ball
    poses = np.stack([keeper.pose_at(t) for t in np.arange(0.0, 2.5, 0.01)])
    assert actor_skeleton.within_limits(poses).all()
    assert actor_skeleton.within_limits(plan.reach.pose)


def test_nothing_moves_before_the_reaction_time(keeper) -> None:
    keeper.set_target(1.2, (0.5, 1.3, 0.3), now=0.5)
    for t in (0.5, 0.6, 0.69):
        np.testing.assert_allclose(keeper.pose_at(t), keeper.base_at(t), atol=1e-9)
    assert np.abs(keeper.pose_at(0.9) - keeper.base_at(0.9)).max() > 0.05


def test_ready_stance_holds_the_palms_in_front_and_relaxed_keeps_the_mocap_arms(
    actor_skeleton, idle
) -> None:
    from bodyplay.virtual import body_axes

    ready = ReachController(actor_skeleton, idle=idle)
    relaxed = ReachController(actor_skeleton, idle=idle,
                              options=make_reach_options(stance="relaxed"))
    for t in (0.0, 0.7):
        q = ready.pose_at(t)
        pelvis, left, fwd = body_axes(actor_skeleton, q)
        palms = effector_points(actor_skeleton, q, "both")
        assert np.all((palms - pelvis) @ fwd > 0.2)  # in front of the body
        assert abs(float((palms[0] - palms[1]) @ left) - 0.56) < 0.05
        np.testing.assert_allclose(relaxed.pose_at(t), idle.pose_at(t), atol=1e-9)
    with pytest.raises(ConfigError, match="stance"):
        make_reach_options(stance="crouched")


def test_late_ball_is_reached_late_at_the_speed_limit(actor_skeleton, idle) -> None:
    ctrl = ReachController(actor_skeleton, idle=idle,
                           options=make_reach_options(max_hand_speed=2.0))
    plan = ctrl.set_target(0.45, (0.6, 1.6, 0.3), now=0.0)
    assert not plan.on_time and plan.end > plan.arrival
    dist = np.linalg.norm(ctrl.effector_at(plan.arrival, "left") - plan.reach.targets)
    assert dist > 0.03  # the ball arrives before the hand
    times = np.arange(0.0, 1.5, 1.0 / 500.0)
    # the min-jerk blend keeps the palm under the limit (idle sway adds a little)
    assert _palm_speeds(ctrl, times, "left").max() < 2.0 * 1.15


def test_pose_is_continuous_through_retargets_and_the_return(keeper, actor_skeleton) -> None:
    keeper.set_target(1.0, (0.5, 1.3, 0.3), now=0.0)
    dt = 1.0 / 500.0
    times = np.arange(0.0, 3.5, dt)
    poses = []
    for t in times:
        if abs(t - 0.6) < dt / 2:  # a new prediction mid-reach: the other side
            keeper.set_target(1.1, (-0.6, 1.1, 0.3), now=float(t))
        poses.append(keeper.pose_at(float(t)))
    joints = actor_skeleton.joint_positions(np.stack(poses))
    assert joints[:, [13, 16], 1].min() > 0.08  # the feet never sink into the floor
    step = np.linalg.norm(np.diff(joints, axis=0), axis=-1).max()
    assert step < 8.0 * dt  # no joint faster than 8 m/s anywhere: no jumps
    np.testing.assert_allclose(keeper.pose_at(3.4), keeper.base_at(3.4), atol=1e-9)


def test_same_calls_give_the_same_poses(actor_skeleton, idle) -> None:
    def run() -> np.ndarray:
        c = ReachController(actor_skeleton, idle=idle)
        out = []
        for i, t in enumerate(np.arange(0.0, 2.0, 1 / 30)):
            if i == 5:
                c.set_target(1.0, (0.4, 1.4, 0.3))
            if i == 40:
                c.clear()
            out.append(c.pose_at(float(t)))
        return np.stack(out)

    np.testing.assert_array_equal(run(), run())


def test_imperfect_keeper_misjudges_by_about_aim_error_and_repeats_per_seed(
    actor_skeleton, idle
) -> None:
    def misses(seed: int) -> np.ndarray:
        c = ReachController(actor_skeleton, idle=idle, seed=seed,
                            options=make_reach_options(aim_error=0.1, reaction_jitter=0.05))
        out = []
        for k in range(12):
            target = np.array([0.5 if k % 2 else -0.5, 1.3, 0.3])
            plan = c.set_target(2.0 * k + 1.0, target, now=2.0 * k)
            out.append(np.linalg.norm(c.effector_at(plan.arrival, plan.effector)[0] - target))
        return np.asarray(out)

    a, b = misses(1), misses(1)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, misses(2))
    assert 0.05 < float(np.median(a)) < 0.25  # about 0.1 m per axis of the plane


def test_set_target_rejects_bad_points_times_and_effectors(keeper) -> None:
    keeper.pose_at(1.0)
    with pytest.raises(ConfigError, match="3-D point"):
        keeper.set_target(2.0, (0.0, np.nan, 0.0))
    with pytest.raises(ConfigError, match="not before now"):
        keeper.set_target(0.5, (0.3, 1.2, 0.3))
    with pytest.raises(ConfigError, match="effector"):
        keeper.set_target(2.0, (0.3, 1.2, 0.3), effector="foot")


def test_reach_options_reject_unknown_names_and_out_of_range_values() -> None:
    with pytest.raises(ConfigError, match="unknown reach option"):
        make_reach_options(reaction=0.1)
    with pytest.raises(ConfigError, match="max_hand_speed"):
        make_reach_options(max_hand_speed=-1.0)
    from bodyplay.virtual import ReachOptions

    with pytest.raises(ConfigError, match="stance"):  # built without the factory
        ReachController(options=ReachOptions(stance="bogus"))


def test_min_jerk_starts_and_ends_at_rest() -> None:
    assert min_jerk(0.0) == 0.0 and min_jerk(1.0) == 1.0 and min_jerk(0.5) == 0.5
    eps = 1e-4
    assert min_jerk(eps) / eps < 1e-6 and (1 - min_jerk(1 - eps)) / eps < 1e-6


def test_the_keeper_turns_its_head_to_watch_the_ball_when_asked(actor_skeleton, idle) -> None:
    from bodyplay.virtual import ReachWeights

    keeper = ReachController(actor_skeleton, idle=idle, weights=ReachWeights(gaze=0.3))
    target = np.array([-0.9, 0.9, 0.3])
    plan = keeper.set_target(1.0, target, now=0.0)
    f = actor_skeleton.forward(keeper.pose_at(1.0))
    to_ball = target - f[4, :3, 3]
    cos = float(f[4, :3, 2] @ to_ball / np.linalg.norm(to_ball))
    f0 = actor_skeleton.forward(keeper.pose_at(0.0))
    cos0 = float(f0[4, :3, 2] @ (target - f0[4, :3, 3]) / np.linalg.norm(target - f0[4, :3, 3]))
    assert plan.reachable and cos > 0.95 and cos0 < 0.8


def test_solve_reach_two_hands_straddle_the_target(actor_skeleton, idle) -> None:
    r = solve_reach(actor_skeleton, idle.pose_at(0.0), (0.0, 1.2, 0.35), "both", hands_gap=0.2)
    pts = effector_points(actor_skeleton, r.pose, "both")
    assert r.error < 0.01
    assert abs(np.linalg.norm(pts[0] - pts[1]) - 0.2) < 0.02
    assert pts[0, 0] > pts[1, 0]  # left palm on the person's left (+X)
