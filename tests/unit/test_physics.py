"""The pymunk bridge: body-part colliders driven by poses, contact begin/end pairs."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.errors import ConfigError
from bodyplay.events.types import ContactEvent
from bodyplay.physics import (
    PART_COLLISION_TYPE,
    PART_NAMES,
    PhysicsOptions,
    PhysicsWorld,
    attach_physics,
)
from bodyplay.runtime import ArrayPoseSource, FixedClock, create_session
from bodyplay.testing import Timeline, key_pose, scripted_session

FPS = 30.0
NO_GRAVITY = PhysicsOptions(gravity=(0.0, 0.0))


@pytest.fixture(scope="module")
def idle(skeleton: Any) -> np.ndarray:
    """(17, 3) joints of the standing reference body, arms down (faces +Z)."""
    return np.asarray(skeleton.joint_positions(key_pose("idle", skeleton)))


@pytest.fixture(scope="module")
def t_pose(skeleton: Any) -> np.ndarray:
    """(17, 3) joints of the reference body with the arms out horizontally."""
    return np.asarray(skeleton.joint_positions(key_pose("t_pose", skeleton)))


def _session(joints: np.ndarray, options: PhysicsOptions = NO_GRAVITY) -> tuple[Any, Any, list]:
    src = ArrayPoseSource(joints, fps=FPS)
    session = create_session(source=src, clock=FixedClock(1.0 / FPS))
    world = attach_physics(session, options)
    log: list[ContactEvent] = []
    session.subscribe("contact", log.append)
    return session, world, log


def _held(pose: np.ndarray, frames: int) -> np.ndarray:
    return np.repeat(pose[None], frames, axis=0)


def _phases(log: list[ContactEvent]) -> list[tuple[str, str, str]]:
    return [(e.part, e.obj, e.phase) for e in log]


def test_ball_thrown_at_static_right_hand_begins_then_ends_once_with_impulse(idle):
    session, world, log = _session(_held(idle, 30))
    session.step()
    hand = world.part_shape("r_hand")
    assert hand is not None
    u, v = hand.body.position
    assert u < -0.2  # the right hand hangs on the person's right, world -X
    world.add_ball((u - 1.2, v), (8.0, 0.0), radius=0.11, mass=0.43, name="ball")
    session.run()
    assert _phases(log) == [("r_hand", "ball", "begin"), ("r_hand", "ball", "end")]
    begin, end = log
    # a 0.43 kg ball at 8 m/s bouncing off an immovable hand (restitution 0.8 * 0.5)
    assert begin.impulse == pytest.approx(0.43 * 8.0 * 1.4, rel=0.02)
    assert end.impulse == 0.0 and end.t > begin.t
    assert begin.point[1] == pytest.approx(v, abs=0.02)
    assert begin.point[2] == pytest.approx(world.depth)
    assert u - 0.1 < begin.point[0] < u
    assert world.objects["ball"].body.velocity.x < 0  # it bounced back


def test_ball_missing_the_body_produces_no_contact(idle):
    session, world, log = _session(_held(idle, 30))
    session.step()
    world.add_ball((-1.5, 2.3), (6.0, 0.0), name="high")
    world.add_ball((1.5, 0.2), (0.0, 0.0), name="still")
    session.run()
    world.close()
    assert log == []
    assert world.objects == {}


def test_joint_lost_while_in_contact_ends_the_contact(t_pose):
    joints = _held(t_pose, 40)
    joints[25:, JOINT_INDEX["l_wrist"]] = np.nan  # the tracker loses the left wrist
    options = PhysicsOptions(gravity=(0.0, -9.81), elasticity=0.0)
    session, world, log = _session(joints, options)
    session.step()
    fore = world.part_shape("l_forearm")
    assert fore is not None
    u, v = fore.body.position
    world.add_ball((u + 0.02, v + 0.25), (0.0, 0.0), name="ball", elasticity=0.0)
    session.run(24)
    assert _phases(log) == [("l_forearm", "ball", "begin")]  # resting on the forearm
    assert world.contacts == (("l_forearm", "ball"),)
    session.run(1)
    assert _phases(log) == [("l_forearm", "ball", "begin"), ("l_forearm", "ball", "end")]
    assert log[-1].t == pytest.approx(25 / FPS)
    assert world.part_shape("l_forearm") is None and world.part_shape("l_hand") is None
    assert world.contacts == ()


def test_removing_an_object_or_closing_the_world_ends_its_contacts(t_pose):
    options = PhysicsOptions(gravity=(0.0, -9.81), elasticity=0.0)
    session, world, log = _session(_held(t_pose, 40), options)
    session.step()
    for side, name in (("l_forearm", "a"), ("r_forearm", "b")):
        shape = world.part_shape(side)
        assert shape is not None
        u, v = shape.body.position
        world.add_ball((u, v + 0.2), (0.0, 0.0), name=name, elasticity=0.0)
    session.run(20)
    assert world.contacts == (("l_forearm", "a"), ("r_forearm", "b"))
    assert world.remove("a") and not world.remove("a")
    assert _phases(log)[-1] == ("l_forearm", "a", "end")
    world.close()
    assert _phases(log)[-1] == ("r_forearm", "b", "end")
    n = len(log)
    session.run()  # the closed world no longer follows the session
    assert len(log) == n and world.closed


@pytest.mark.parametrize("via", ["contact_subscriber", "pymunk_handler"])
def test_game_removing_a_ball_as_it_touches_still_gets_the_end(idle, via):
    session, world, log = _session(_held(idle, 30))
    session.step()
    hand = world.part_shape("r_hand")
    assert hand is not None
    u, v = hand.body.position
    ball = world.add_ball((u - 1.2, v), (8.0, 0.0), name="ball")
    if via == "contact_subscriber":
        session.subscribe("contact", lambda e: world.remove(e.obj) if e.phase == "begin" else None)
    else:  # the game's own handler for its ball type, called inside the pymunk step
        ball.shapes[0].collision_type = 5
        world.space.on_collision(PART_COLLISION_TYPE, 5,
                                 begin=lambda arbiter, space, data: world.remove("ball"))
    session.run()
    assert _phases(log) == [("r_hand", "ball", "begin"), ("r_hand", "ball", "end")]
    assert log[0].t == log[1].t and log[0].impulse > 0
    assert world.objects == {} and world.contacts == ()


def test_swinging_forearm_gives_a_resting_ball_its_speed(t_pose):
    # the right arm swings down from horizontal about the shoulder at 3 rad/s
    frames, rate = 30, 3.0
    shoulder = t_pose[JOINT_INDEX["r_shoulder"]]
    joints = _held(t_pose, frames)
    for i in range(frames):
        a = min(rate * i / FPS, 1.4)
        rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
        for name in ("r_elbow", "r_wrist"):
            k = JOINT_INDEX[name]
            joints[i, k] = shoulder + rot @ (t_pose[k] - shoulder)
    session, world, log = _session(joints)
    session.step()
    wrist = joints[0, JOINT_INDEX["r_wrist"]]
    r_ball, reach = 0.05, abs(wrist[0] - shoulder[0])
    # at rest just below the wrist's path, hit after about a quarter second
    a_hit = 0.8
    c = shoulder[:2] + (reach - 0.02) * np.array([-np.cos(a_hit), -np.sin(a_hit)])
    ball = world.add_ball(c, (0.0, 0.0), radius=r_ball, mass=0.2, name="ball", elasticity=1.0)
    speeds: list[float] = []
    session.subscribe("contact", lambda e: speeds.append(ball.body.velocity.length))
    session.run()
    first = log[0]
    assert (first.part, first.obj, first.phase) == ("r_forearm", "ball", "begin")
    arm_speed = rate * (reach - 0.02)  # of the forearm where it meets the ball
    # restitution 1.0 * 0.5: the ball leaves at 1.5 times the arm's speed
    assert speeds[0] == pytest.approx(1.5 * arm_speed, rel=0.05)
    assert first.impulse == pytest.approx(0.2 * speeds[0], rel=0.02)


def test_two_runs_of_the_same_pose_stream_give_byte_identical_contact_logs():
    def run() -> list[str]:
        timeline = Timeline().gesture("wave_right").gesture("punch_left").hold("idle", 0.5)
        session = scripted_session(timeline, FPS, player={"noise": 0.01, "seed": 3})
        world = attach_physics(session, PhysicsOptions(dt=1.0 / 240.0))
        lines: list[str] = []
        session.subscribe("contact", lambda e: lines.append(json.dumps(e.to_json())))

        def fire(pose: Any) -> None:  # a deterministic "game": a ball every 6 frames
            if pose.frame % 6 == 0:
                k = pose.frame // 6
                side = -1.0 if k % 2 else 1.0
                world.add_ball((1.2 * side, 0.6 + 0.1 * (k % 9)), (-6.0 * side, 2.0))
            if pose.frame % 6 == 5:
                world.remove(f"ball{max(0, pose.frame // 6 - 3)}")

        session.subscribe("pose", fire)
        session.run()
        world.close()
        return lines

    first, second = run(), run()
    assert len(first) >= 6 and any('"begin"' in line for line in first)
    assert first == second


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_contacts_stay_balanced_over_a_long_random_stream(idle, seed):
    rng = np.random.default_rng(seed)
    frames = 240
    offsets = np.cumsum(rng.normal(0.0, 0.03, size=(frames, 17, 3)), axis=0)
    offsets[:, :5] *= 0.2  # the torso wobbles, the limbs wander
    joints = idle[None] + np.clip(offsets, -0.4, 0.4)
    groups = [["r_wrist"], ["l_wrist", "l_elbow"], ["head"], ["pelvis"], ["r_knee"]]
    for _ in range(12):  # bursts of lost joints
        start, length = rng.integers(0, frames), rng.integers(1, 15)
        for name in groups[rng.integers(len(groups))]:
            joints[start:start + length, JOINT_INDEX[name]] = np.nan
    session, world, log = _session(joints, PhysicsOptions())
    open_pairs: set[tuple[str, str]] = set()
    problems: list[str] = []

    def check(e: ContactEvent) -> None:
        key = (e.part, e.obj)
        if e.phase == "begin":
            if key in open_pairs:
                problems.append(f"second begin {key} at {e.t}")
            open_pairs.add(key)
        else:
            if key not in open_pairs:
                problems.append(f"end without begin {key} at {e.t}")
            open_pairs.discard(key)

    session.subscribe("contact", check)

    def game(pose: Any) -> None:
        if pose.frame % 4 == 0:
            u, v = rng.uniform(-1.2, 1.2), rng.uniform(0.2, 1.9)
            target = rng.uniform([-0.4, 0.5], [0.4, 1.7])
            vel = (target - (u, v)) * rng.uniform(2.0, 8.0)
            world.add_ball((u, v), vel, radius=rng.uniform(0.05, 0.15))
        names = list(world.objects)
        if names and rng.random() < 0.2:
            world.remove(names[rng.integers(len(names))])

    session.subscribe("pose", game)
    session.run()
    world.close()
    assert problems == []
    assert open_pairs == set()
    assert sum(e.phase == "begin" for e in log) >= 10
    assert {e.part for e in log} <= set(PART_NAMES)


def test_upper_body_stream_has_no_leg_colliders(idle):
    src = ArrayPoseSource(_held(idle, 3), fps=FPS, upper_body_only=True)
    session = create_session(source=src, clock=FixedClock(1.0 / FPS))
    world = attach_physics(session)
    session.run()
    assert world.enabled_parts == PART_NAMES[:8]
    assert world.height == pytest.approx(1.75, abs=0.01)


def test_plane_depth_follows_the_torso_unless_fixed(idle):
    shifted = _held(idle + np.array([0.0, 0.0, 2.5]), 2)
    follow = PhysicsWorld()
    fixed = PhysicsWorld(PhysicsOptions(depth=1.0))
    for world in (follow, fixed):
        session = create_session(source=ArrayPoseSource(shifted, fps=FPS))
        session.subscribe("pose", world.on_pose)
        session.run()
    assert follow.depth == pytest.approx(2.5 + idle[[0, 3], 2].mean())
    assert fixed.depth == 1.0
    assert fixed.to_world((0.3, 1.2)) == (0.3, 1.2, 1.0)


def test_part_subset_builds_only_those_colliders(idle):
    options = PhysicsOptions(parts=("l_hand", "r_hand"), body_height=1.6)
    session, world, _ = _session(_held(idle, 2), options)
    session.run()
    assert world.enabled_parts == ("l_hand", "r_hand")
    hand = world.part_shape("r_hand")
    assert hand is not None and hand.radius == pytest.approx(0.035 * 1.6)  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    "bad",
    [
        {"plane": "top"},
        {"dt": 0.0},
        {"dt": -0.01},
        {"dt": 0.5},
        {"gravity": (0.0,)},
        {"gravity": (0.0, float("nan"))},
        {"parts": ("r_hand", "tail")},
        {"parts": ()},
        {"parts": ("head", "head")},
        {"body_height": -1.0},
        {"body_height": 175.0},
        {"hand_radius": 0.0},
        {"torso_radius": 2.0},
        {"hand_offset": -0.1},
        {"elasticity": -1.0},
        {"iterations": 0},
        {"max_steps_per_pose": 2.5},
        {"depth": float("inf")},
    ],
)
def test_bad_options_raise_config_error(bad):
    with pytest.raises(ConfigError):
        PhysicsWorld(PhysicsOptions(**bad))


def test_bad_objects_raise_config_error(idle):
    world = PhysicsWorld()
    world.add_ball((0.0, 3.0), name="a")
    with pytest.raises(ConfigError, match="already"):
        world.add_ball((0.0, 3.0), name="a")
    with pytest.raises(ConfigError):
        world.add_ball((0.0, 3.0), radius=-0.1)
    with pytest.raises(ConfigError):
        world.add_ball((0.0, float("nan")))
    with pytest.raises(ConfigError):
        world.part_shape("tail")
    world.close()
    with pytest.raises(ConfigError, match="closed"):
        world.add_ball((0.0, 3.0))


def test_resume_after_a_pause_skips_the_gap_without_moving_objects(idle):
    from bodyplay.events.types import PoseEvent

    world = PhysicsWorld(PhysicsOptions())  # with gravity

    def pose(t: float, frame: int) -> PoseEvent:
        return PoseEvent(t=t, emitted_t=t, frame=frame, joints=idle, state=("tracked",) * 17,
                         confidence=np.ones(17))

    world.on_pose(pose(0.0, 0))
    ball = world.add_ball((1.5, 3.0), (0.0, 0.0), name="ball")
    world.on_pose(pose(0.1, 1))
    y_before = ball.body.position.y
    steps = world.steps
    world.resume(pose(5.0, 2))  # five seconds later: nothing simulated
    assert ball.body.position.y == y_before and world.steps == steps
    world.on_pose(pose(5.1, 3))  # and the next pose steps 0.1 s only
    assert world.steps == steps + 12
    assert 3.0 - ball.body.position.y < 0.3  # fell for 0.2 s in all, not 5 s
