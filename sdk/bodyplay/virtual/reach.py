"""The reaching controller: a virtual keeper who moves hands, trunk or head to the ball.

:class:`ReachController` stands in real mocap idle motion
(:class:`~bodyplay.virtual.idle.IdleMotion`). A game tells it where and when a ball
will cross the keeper's plane (:meth:`ReachController.set_target`); it picks the
effector (:func:`~bodyplay.virtual.reach_ik.choose_effector`: the near hand, both
hands, or the head), solves the reach pose on the idle pose at the arrival time
(:func:`~bodyplay.virtual.reach_ik.solve_reach`, inside the joint limits, leaning
or stepping when an arm is not enough) and blends into it like a person would:

* nothing moves for a reaction time (0.2 s) after the ball is seen;
* the blend follows a minimum-jerk profile (Flash and Hogan 1985: the smooth,
  bell-shaped hand speed of human reaching), timed so the palm's peak speed stays
  under ``max_hand_speed``; when there is time it arrives ``arrive_early`` before
  the ball, when there is not it arrives late (and the ball may get past);
* it holds the reach ``hold`` seconds after the arrival, then returns to idle.

A new target while moving starts a new blend from wherever the body is, so the
pose is continuous (and so is its velocity: min-jerk blends start and end at
rest). Every output is projected into the skeleton's joint limits. The controller
is deterministic: the same calls give the same poses. :meth:`pose_at` is a pure
function of ``t`` for times at or after the ``now`` of the latest call that
changed the plan.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types
from bodyplay.testing.timeline import slerp_poses
from bodyplay.virtual.idle import IdleMotion
from bodyplay.virtual.reach_ik import (
    EFFECTORS,
    ReachPose,
    ReachWeights,
    body_axes,
    choose_effector,
    effector_points,
    solve_reach,
)

__all__ = [
    "STANCES", "ReachController", "ReachOptions", "ReachPlan", "make_reach_options", "min_jerk",
]

STANCES: tuple[str, ...] = ("ready", "relaxed")
"""How the keeper holds the arms between balls."""

# Peak speed of a minimum-jerk move over its average speed.
_MIN_JERK_PEAK = 1.875
_PATH_SAMPLES = 12


def min_jerk(s: float) -> float:
    """The minimum-jerk blend weight at normalized time ``s`` (0..1, clamped)."""
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (10.0 + s * (-15.0 + 6.0 * s))


@dataclass(frozen=True)
class ReachOptions:
    """How the virtual keeper reaches; build with :func:`make_reach_options`.

    Times in seconds, speeds in metres per second, distances in metres.
    ``reaction_time``: delay from seeing a ball to moving; ``max_hand_speed``: peak
    palm speed of a reach (``return_speed`` of the way back); ``min_move_time`` /
    ``preferred_move_time``: shortest and usual reach durations; ``arrive_early``:
    how long before the ball the reach completes; ``hold``: how long it is held
    after the arrival; ``max_step``: the largest sideways step; ``max_crouch``:
    the deepest drop of the pelvis (knees bend, feet stay planted); ``both_hands_width``
    / ``head_width``: half-widths about the body's midline where both hands / the
    head are used; ``use_head``: allow headers; ``hands_gap``: palm spacing of a
    two-handed catch; ``palm``: where on the hand bone the contact point is (0
    wrist .. 1 fingertips); ``reach_tolerance``: a reach whose effector ends
    farther than this from the target is reported as not reachable. ``stance``:
    ``"ready"`` (a keeper's: the palms held in front, ``ready_hands`` = half the
    distance between them, their height above the pelvis and how far forward) or
    ``"relaxed"`` (the mocap idle's arms, hanging). An imperfect keeper:
    ``aim_error`` (m) is the standard deviation of a Gaussian misjudgment of where the
    ball crosses (per axis of the keeper's plane), ``reaction_jitter`` (s) that of
    its reaction time (never below half of ``reaction_time``); both drawn from the
    controller's seeded generator, one draw per ball. 0 (the default): a perfect
    keeper.
    """

    reaction_time: float = 0.2
    max_hand_speed: float = 4.0
    return_speed: float = 1.5
    min_move_time: float = 0.2
    preferred_move_time: float = 0.45
    arrive_early: float = 0.05
    hold: float = 0.3
    max_step: float = 0.5
    max_crouch: float = 0.35
    both_hands_width: float = 0.22
    head_width: float = 0.14
    use_head: bool = True
    hands_gap: float = 0.18
    palm: float = 0.5
    reach_tolerance: float = 0.04
    aim_error: float = 0.0
    reaction_jitter: float = 0.0
    stance: str = "ready"
    ready_hands: tuple[float, float, float] = (0.28, 0.2, 0.3)

    def __post_init__(self) -> None:
        check_option_types(self)


def make_reach_options(**kwargs: Any) -> ReachOptions:
    """Validated :class:`ReachOptions`; an unknown or out-of-range value raises ConfigError."""
    known = {f.name for f in fields(ReachOptions)}
    unknown = sorted(set(kwargs) - known)
    if unknown:
        raise ConfigError(f"unknown reach option(s) {', '.join(unknown)}; "
                          f"known: {', '.join(sorted(known))}")
    o = ReachOptions(**kwargs)
    ranges = {
        "reaction_time": (0.0, 2.0), "max_hand_speed": (0.1, 20.0),
        "return_speed": (0.1, 20.0), "min_move_time": (0.02, 3.0),
        "preferred_move_time": (0.02, 5.0), "arrive_early": (0.0, 1.0), "hold": (0.0, 10.0),
        "max_step": (0.0, 2.0), "max_crouch": (0.0, 0.6), "both_hands_width": (0.0, 1.0),
        "head_width": (0.0, 0.5),
        "hands_gap": (0.0, 0.6), "palm": (0.0, 1.0), "reach_tolerance": (0.001, 1.0),
        "aim_error": (0.0, 1.0), "reaction_jitter": (0.0, 0.5),
    }
    if o.stance not in STANCES:
        raise ConfigError(f"stance {o.stance!r} must be one of {', '.join(STANCES)}")
    hands = np.asarray(o.ready_hands, dtype=np.float64)
    if hands.shape != (3,) or not (0.05 <= hands[0] <= 0.6 and -0.4 <= hands[1] <= 0.8
                                   and 0.0 <= hands[2] <= 0.6):
        raise ConfigError(f"ready_hands {o.ready_hands!r} must be (half-width 0.05..0.6, "
                          f"height -0.4..0.8, forward 0..0.6) metres")
    for name, (lo, hi) in ranges.items():
        v = getattr(o, name)
        if not (isinstance(v, int | float) and math.isfinite(v) and lo <= v <= hi):
            raise ConfigError(f"reach option {name}={v!r} must be within {lo}..{hi}")
    return o


@dataclass(frozen=True, eq=False)
class ReachPlan:
    """What the keeper will do about one ball (returned by :meth:`ReachController.set_target`).

    ``target``: where the ball crosses; ``aim``: where the keeper reaches (the
    target, misjudged by ``aim_error``); ``seen``: when the ball was seen;
    ``start``/``end``: the reach blend; ``arrival``: when the ball crosses;
    ``release``: when the return to idle starts; ``reach``: the solved
    :class:`~bodyplay.virtual.reach_ik.ReachPose` (effector, error...);
    ``reachable``: the effector gets within ``reach_tolerance`` of the aim;
    ``on_time``: the reach completes by the arrival.
    """

    target: NDArray[np.float64]
    aim: NDArray[np.float64]
    seen: float
    start: float
    end: float
    arrival: float
    release: float
    reach: ReachPose
    reachable: bool

    @property
    def effector(self) -> str:
        """``left``, ``right``, ``both`` or ``head``."""
        return self.reach.effector

    @property
    def on_time(self) -> bool:
        """Whether the reach completes by the ball's arrival."""
        return self.end <= self.arrival + 1e-9


@dataclass(frozen=True, eq=False)
class _Layer:
    """One blend: from whatever is below towards ``goal`` (None = idle), min-jerk."""

    start: float
    duration: float
    goal: ReachPose | None

    @property
    def end(self) -> float:
        return self.start + self.duration


class ReachController:
    """A virtual keeper: mocap idle plus IK reaches towards announced balls (module doc).

    ``skeleton`` should be the actor's (``load_actor(body).skeleton``, the default
    for body ``"m"``) so the rendered hands are where the IK put them; ``idle`` the
    base motion (default :class:`~bodyplay.virtual.idle.IdleMotion` at ``at`` facing
    ``facing``); ``options`` a :class:`ReachOptions`; ``weights`` the IK's costs;
    ``seed`` the generator of an imperfect keeper's errors (see :class:`ReachOptions`).
    """

    def __init__(
        self,
        skeleton: Skeleton | None = None,
        *,
        options: ReachOptions | None = None,
        idle: IdleMotion | None = None,
        at: ArrayLike = (0.0, 0.0),
        facing: float = 0.0,
        weights: ReachWeights | None = None,
        seed: int = 0,
    ) -> None:
        if skeleton is None:
            from bodyplay.body.actor import load_actor

            skeleton = load_actor("m").skeleton
        self.skeleton = skeleton
        # validated here too: options may be built without the factory
        self.options = make_reach_options(**asdict(options)) if options else ReachOptions()
        self.weights = weights or ReachWeights()
        self.idle = idle or IdleMotion(skeleton, at=at, facing=facing)
        if self.idle.skeleton != skeleton:
            raise ConfigError("the idle motion is for another skeleton than the controller's")
        self.stance: ReachPose | None = None
        if self.options.stance == "ready":
            q0 = self.idle.pose_at(0.0)
            pelvis, left, fwd = body_axes(skeleton, q0)
            half, up, ahead = self.options.ready_hands
            centre = pelvis + np.array([0.0, up, 0.0]) + ahead * fwd
            self.stance = solve_reach(skeleton, q0, centre, "both", hands_gap=2.0 * half,
                                      palm=self.options.palm, weights=self.weights, body=False)
        self._layers: list[_Layer] = []
        self._now = 0.0
        self.plans: list[ReachPlan] = []
        self._rng = np.random.default_rng(seed)

    # ---- evaluation ------------------------------------------------------------------
    def base_at(self, t: float) -> NDArray[np.float64]:
        """The pose between balls at ``t``: the idle motion in the chosen stance."""
        q = self.idle.pose_at(t)
        return q if self.stance is None else self.stance.apply(q)

    def pose_at(self, t: float) -> NDArray[np.float64]:
        """The pose vector at ``t`` seconds: idle with the planned reaches blended in."""
        if not math.isfinite(t):
            raise ConfigError(f"time must be finite, got {t}")
        t = float(t)
        self._now = max(self._now, t)
        idle = self.base_at(t)
        x = idle
        for layer in self._layers:
            if t <= layer.start:
                continue
            w = min_jerk((t - layer.start) / layer.duration)
            goal = idle if layer.goal is None else layer.goal.apply(idle)
            x = slerp_poses(x, goal, w)
        return self.skeleton.clamp(x)

    def joints_at(self, t: float) -> NDArray[np.float64]:
        """(17, 3) joints at ``t``."""
        return self.skeleton.joint_positions(self.pose_at(t))

    def effector_at(self, t: float, effector: str) -> NDArray[np.float64]:
        """(k, 3) effector point(s) at ``t`` (see :func:`effector_points`)."""
        return effector_points(self.skeleton, self.pose_at(t), effector, self.options.palm)

    # ---- planning --------------------------------------------------------------------
    def _resolve_now(self, now: float | None) -> float:
        n = self._now if now is None else float(now)
        if not math.isfinite(n):
            raise ConfigError(f"now must be finite, got {now}")
        return n

    def _prune(self, now: float) -> None:
        """Drop future blends and those hidden under a blend completed by ``now``."""
        self._layers = [layer for layer in self._layers if layer.start < now]
        done = [i for i, layer in enumerate(self._layers) if layer.end <= now]
        if done:
            last = done[-1]
            keep = self._layers[last:]
            if keep[0].goal is None:  # completed return to idle: nothing below matters
                keep = keep[1:]
            self._layers = keep

    def _path_length(
        self, a: NDArray[np.float64], b: NDArray[np.float64], effector: str
    ) -> float:
        """Longest effector path (m) of a blend from pose ``a`` to ``b``."""
        poses = np.stack([slerp_poses(a, b, w) for w in np.linspace(0, 1, _PATH_SAMPLES)])
        pts = effector_points(self.skeleton, poses, effector, self.options.palm)
        return float(np.max(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=-1), axis=0)))

    def set_target(
        self,
        t_arrival: float,
        point: ArrayLike,
        *,
        now: float | None = None,
        effector: str = "auto",
    ) -> ReachPlan:
        """Announce a ball crossing the keeper's plane at ``point`` (world metres) at
        ``t_arrival`` seconds, seen at ``now`` (default: the latest time posed).

        ``effector``: ``"auto"`` (choose by where the ball is) or one of
        ``left``, ``right``, ``both``, ``head``. Replaces any plan not yet started.
        """
        o = self.options
        n = self._resolve_now(now)
        p = np.asarray(point, dtype=np.float64).reshape(-1)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise ConfigError(f"the target must be one finite 3-D point in metres, got {point!r}")
        if not math.isfinite(t_arrival) or t_arrival < n:
            raise ConfigError(f"t_arrival {t_arrival} s must be finite and not before now ({n} s)")
        if effector != "auto" and effector not in EFFECTORS:
            raise ConfigError(f"effector {effector!r} must be 'auto' or one of "
                              f"{', '.join(EFFECTORS)}")
        self._prune(n)
        t_arrival = float(t_arrival)
        base = self.base_at(t_arrival)
        if effector == "auto":
            effector = choose_effector(
                self.skeleton, base, p, both_hands_width=o.both_hands_width,
                head_width=o.head_width, use_head=o.use_head,
            )
        aim = p.copy()
        reaction = o.reaction_time
        if o.aim_error > 0 or o.reaction_jitter > 0:
            _, left, _ = body_axes(self.skeleton, base)
            err = self._rng.normal(0.0, 1.0, size=3)
            aim += o.aim_error * (err[0] * left + err[1] * np.array([0.0, 1.0, 0.0]))
            reaction = max(0.5 * reaction, reaction + o.reaction_jitter * err[2])
        reach = solve_reach(self.skeleton, base, aim, effector, max_step=o.max_step,
                            max_crouch=o.max_crouch,
                            hands_gap=o.hands_gap, palm=o.palm, weights=self.weights)
        react = n + reaction
        length = self._path_length(self.pose_at(react), reach.pose, effector)
        fastest = max(o.min_move_time, _MIN_JERK_PEAK * length / o.max_hand_speed)
        goal_end = t_arrival - o.arrive_early
        duration = max(fastest, o.preferred_move_time)
        start = goal_end - duration
        if start < react:
            start = react
            duration = max(fastest, goal_end - react)
        end = start + duration
        back = max(o.min_move_time, _MIN_JERK_PEAK * length / o.return_speed)
        release = max(t_arrival, end) + o.hold
        self._layers.append(_Layer(start, duration, reach))
        self._layers.append(_Layer(release, back, None))
        plan = ReachPlan(target=p, aim=aim, seen=n, start=start, end=end, arrival=t_arrival,
                         release=release, reach=reach,
                         reachable=reach.error <= o.reach_tolerance)
        self.plans.append(plan)
        return plan

    def clear(self, now: float | None = None) -> None:
        """Forget the balls: return to idle after the reaction time from ``now``."""
        n = self._resolve_now(now)
        self._prune(n)
        if not self._layers:
            return
        self._layers.append(_Layer(n + self.options.reaction_time,
                                   max(self.options.min_move_time, 0.4), None))

    # ---- framing ---------------------------------------------------------------------
    def frame_joints(self) -> NDArray[np.float64]:
        """(T, 17, 3) joints bounding the keeper's reach: idle, a step each way with the
        arms raised and out, for a camera to frame."""
        sk = self.skeleton
        idle = np.stack([self.base_at(t) for t in np.linspace(0.0, self.idle.period, 8)])
        poses = [q for q in idle]
        _, left, _ = body_axes(sk, idle[0])
        arms_out = {"l_shoulder": (0.0, 0.0, 0.9), "r_shoulder": (0.0, 0.0, -0.9)}
        for side in (-1.0, 1.0):
            q = idle[0].copy()
            for name, rv in arms_out.items():
                i = 3 + 3 * sk.node_index(name)
                q[i : i + 3] = rv
            q[[0, 2]] += side * self.options.max_step * left[[0, 2]]
            poses.append(q)
        return sk.joint_positions(np.stack(poses))

