"""Inverse kinematics for a reach: which body parts move, and the pose that gets there.

:func:`solve_reach` poses the skeleton so an *effector* touches a target point:
one hand's palm (``"left"``/``"right"``), both palms side by side (``"both"``, a
two-handed catch) or the head (``"head"``, a header). It is a bounded nonlinear
least-squares problem (``scipy.optimize.least_squares``, trust-region reflective)
over the joints a keeper would use, every one inside the skeleton's joint limits:

* the arm(s): clavicle, shoulder (3 DOF each) and the elbow hinge;
* the trunk: lumbar and thorax (lean sideways, forwards, twist);
* the neck and head: to put the head on the ball (a header) or, for the hands, to
  watch it come (an optional soft gaze cost);
* a step: the whole body moves horizontally by up to ``max_step`` metres;
* a crouch: the pelvis drops by up to ``max_crouch`` metres.

Besides the effector's distance to the target, each group costs its distance from
the idle pose with its own weight (arms are cheap, leaning dearer, stepping dearest),
so a keeper moves an arm for a ball it can reach, leans for a wider one and steps
(or crouches, for a low one) only for one still further out. The legs then follow
(:mod:`~bodyplay.virtual.legs`): the feet stay on the floor, the leading one steps.
A second pass with a tenth of those weights polishes the contact to millimetres.
:func:`choose_effector` picks the effector from where the target is relative to
the body.

Simplification (named in docs/virtual-players.md): the stepping foot glides to
its new place during the blend (it is not lifted).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.rotations import matrix_to_rotvec, rotation_between, rotvec_to_matrix
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.errors import ConfigError
from bodyplay.virtual.legs import LEG_INDICES, leg_reach, plant_feet

__all__ = ["EFFECTORS", "ReachPose", "ReachWeights", "body_axes", "choose_effector",
           "effector_points", "solve_reach"]

EFFECTORS: tuple[str, ...] = ("left", "right", "both", "head")
"""What can touch the ball: a palm, both palms, or the head."""

_N = {name: i for i, name in enumerate(NODE_NAMES)}
_FD_STEP = 1e-6  # radians (or metres) of the Jacobian's forward differences


def _comp(node: str, axes: tuple[int, ...] = (0, 1, 2)) -> list[int]:
    """Pose-vector indices of ``node``'s rotation components ``axes``."""
    base = 3 + 3 * _N[node]
    return [base + a for a in axes]


@dataclass(frozen=True)
class ReachWeights:
    """Cost per radian (or metre, for ``step``) of moving each group away from idle.

    The effector's error costs 1 per metre; these are relative to it. ``legs`` is
    the cost per metre of stretching a leg past its reach from the spot its foot
    stood on (so a wide step crouches rather than drag the trailing foot); ``gaze``
    the cost of the face's forward axis pointing away from the ball (unit vectors'
    difference): with ``gaze=0.3`` the keeper turns its head to watch the ball come.
    Off by default: the one-camera color-shirt tracker follows the wrists of a keeper
    whose head turns much worse (benchmark median at idle 18.6 -> 35.7 cm).
    """

    arm: float = 0.01
    clavicle: float = 0.06
    trunk: float = 0.08
    neck: float = 0.05
    step: float = 0.15
    crouch: float = 0.2
    legs: float = 3.0
    gaze: float = 0.0


@dataclass(frozen=True, eq=False)
class ReachPose:
    """A solved reach: the pose vector and which of its values the reach sets.

    ``indices``/``values``: the pose-vector components the reach moved (joint
    rotations, absolute in their parent frames, legs included after a step or a
    crouch); ``shift``: the root's move (x, y, z) metres (a step, a crouch);
    ``error``: metres from the effector point(s) to the target(s) (the worst, for
    two hands); ``targets``: (1 or 2, 3) points the effector(s) aim at.
    """

    effector: str
    pose: NDArray[np.float64]
    indices: NDArray[np.int64]
    values: NDArray[np.float64]
    shift: NDArray[np.float64]
    error: float
    targets: NDArray[np.float64]

    def apply(self, base: NDArray[np.float64]) -> NDArray[np.float64]:
        """This reach laid over another pose (e.g. the idle motion at another time)."""
        out = np.array(base, dtype=np.float64, copy=True)
        out[self.indices] = self.values
        out[:3] += self.shift
        return out


def body_axes(
    skeleton: Skeleton, pose: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(pelvis, left, forward) of a pose: the horizontal unit axes of the body."""
    j = skeleton.joint_positions(pose)
    across = (j[JOINT_INDEX["l_hip"]] - j[JOINT_INDEX["r_hip"]]
              + j[JOINT_INDEX["l_shoulder"]] - j[JOINT_INDEX["r_shoulder"]])
    across[1] = 0.0
    left = across / max(float(np.linalg.norm(across)), 1e-9)
    forward = np.cross(left, [0.0, 1.0, 0.0])
    return j[JOINT_INDEX["pelvis"]], left, forward


def choose_effector(
    skeleton: Skeleton,
    pose: NDArray[np.float64],
    target: ArrayLike,
    *,
    both_hands_width: float = 0.22,
    head_width: float = 0.14,
    use_head: bool = True,
) -> str:
    """The effector a keeper standing in ``pose`` uses for a ball at ``target``.

    Within ``head_width`` of the body's midline at head height: the head (if
    ``use_head``); within ``both_hands_width``: both hands; else the hand on the
    ball's side.
    """
    p = np.asarray(target, dtype=np.float64).reshape(3)
    pelvis, left, _ = body_axes(skeleton, pose)
    lateral = float(np.dot(p - pelvis, left))
    head = skeleton.joint_positions(pose)[JOINT_INDEX["head"]]
    if use_head and abs(lateral) <= head_width and head[1] - 0.08 <= p[1] <= head[1] + 0.15:
        return "head"
    if abs(lateral) <= both_hands_width:
        return "both"
    return "left" if lateral > 0 else "right"


def effector_points(
    skeleton: Skeleton, poses: ArrayLike, effector: str, palm: float = 0.5
) -> NDArray[np.float64]:
    """(..., k, 3) effector points of poses: palm(s) (``palm`` of the way from the
    wrist to the hand's end) or the head centre; k = 2 for ``"both"`` (left, right)."""
    return _effector_from_nodes(skeleton.node_positions(poses), effector, palm)


def _effector_from_nodes(
    nodes: NDArray[np.float64], effector: str, palm: float
) -> NDArray[np.float64]:
    def palm_of(side: str) -> NDArray[np.float64]:
        w, h = nodes[..., _N[f"{side}_wrist"], :], nodes[..., _N[f"{side}_hand"], :]
        return np.asarray(w + palm * (h - w))

    if effector == "head":
        return nodes[..., _N["head"], :][..., None, :]
    if effector == "both":
        return np.stack([palm_of("l"), palm_of("r")], axis=-2)
    if effector in ("left", "right"):
        return palm_of(effector[0])[..., None, :]
    raise ConfigError(f"unknown effector {effector!r}; choose one of {', '.join(EFFECTORS)}")


def _groups(effector: str, body: bool, gaze: bool) -> list[tuple[list[int], str]]:
    """(pose indices, weight name) of the joints a reach with ``effector`` moves
    (``body``: also the trunk, a step and a crouch; ``gaze``: the neck and head)."""
    groups: list[tuple[list[int], str]] = []
    if body:
        groups += [(_comp("lumbar"), "trunk"), (_comp("thorax"), "trunk"), ([0, 2], "step"),
                   ([1], "crouch")]
    sides = {"left": ("l",), "right": ("r",), "both": ("l", "r")}.get(effector, ())
    for s in sides:
        groups.append((_comp(f"{s}_clavicle"), "clavicle"))
        groups.append((_comp(f"{s}_shoulder"), "arm"))
        groups.append((_comp(f"{s}_elbow", (1,)), "arm"))
    if effector == "head" or gaze:
        groups.append((_comp("neck"), "neck"))
        groups.append((_comp("head"), "neck"))
    return groups


def _aim_arm(
    skeleton: Skeleton, pose: NDArray[np.float64], side: str, target: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``pose`` with the ``side`` arm's shoulder turned to point the arm at ``target``
    and the elbow slightly bent: the start of the search."""
    q = pose.copy()
    q[_comp(f"{side}_elbow", (1,))[0]] = -0.3 if side == "l" else 0.3
    f = skeleton.forward(q)
    ish, iwr = _N[f"{side}_shoulder"], _N[f"{side}_wrist"]
    sh, wr = f[ish, :3, 3], f[iwr, :3, 3]
    turn = rotation_between(wr - sh, target - sh)
    parent = f[_N[f"{side}_clavicle"], :3, :3]
    local = rotvec_to_matrix(q[_comp(f"{side}_shoulder")])
    new_local = parent.T @ turn @ parent @ local
    q[_comp(f"{side}_shoulder")] = matrix_to_rotvec(new_local)
    return q


def solve_reach(
    skeleton: Skeleton,
    base: ArrayLike,
    target: ArrayLike,
    effector: str,
    *,
    max_step: float = 0.5,
    max_crouch: float = 0.35,
    hands_gap: float = 0.18,
    palm: float = 0.5,
    weights: ReachWeights | None = None,
    body: bool = True,
) -> ReachPose:
    """Pose ``skeleton`` from ``base`` so ``effector`` touches ``target`` (see module doc).

    ``hands_gap``: metres between the palms of a two-handed catch (across the body);
    ``max_step``: the largest horizontal step, ``max_crouch`` the deepest drop of the
    pelvis, metres; ``body=False`` moves only the arms (or neck and head): no lean,
    no step, no crouch. After a step or a crouch the legs are re-solved so the feet
    stay on the floor (:func:`~bodyplay.virtual.legs.plant_feet`).
    """
    w = weights or ReachWeights()
    q0 = np.asarray(base, dtype=np.float64).reshape(-1)
    if q0.shape != (skeleton.pose_dim,):
        raise ConfigError(f"the base pose must have {skeleton.pose_dim} values, got {q0.shape}")
    p = np.asarray(target, dtype=np.float64).reshape(-1)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise ConfigError(f"a reach target must be one finite 3-D point (metres), got {target!r}")
    if effector not in EFFECTORS:
        raise ConfigError(f"unknown effector {effector!r}; choose one of {', '.join(EFFECTORS)}")
    if not 0.0 <= max_step <= 2.0:
        raise ConfigError(f"max_step {max_step} m must be within 0..2")
    if not 0.0 <= max_crouch <= 0.6:
        raise ConfigError(f"max_crouch {max_crouch} m must be within 0..0.6")
    _, left, _ = body_axes(skeleton, q0)
    if effector == "both":
        targets = np.stack([p + 0.5 * hands_gap * left, p - 0.5 * hands_gap * left])
    else:
        targets = p[None]

    look = body and w.gaze > 0 and effector != "head"
    groups = _groups(effector, body, look)
    idx = np.concatenate([np.asarray(g, dtype=np.int64) for g, _ in groups])
    cost = np.concatenate([np.full(len(g), getattr(w, name)) for g, name in groups])
    lo_all, hi_all = skeleton.limits
    lo, hi = lo_all[idx].copy(), hi_all[idx].copy()
    is_step = np.isin(idx, [0, 2])
    lo[is_step] = q0[idx[is_step]] - max_step
    hi[is_step] = q0[idx[is_step]] + max_step
    is_drop = idx == 1
    lo[is_drop] = q0[1] - max_crouch
    hi[is_drop] = q0[1]
    is_root = is_step | is_drop
    span = np.maximum(hi - lo, 1e-9)
    lo_in, hi_in = lo + 1e-6 * span, hi - 1e-6 * span
    ref = np.clip(q0[idx], lo, hi)

    start = q0.copy()
    if effector in ("left", "right"):
        start = _aim_arm(skeleton, start, effector[0], p)
    elif effector == "both":
        start = _aim_arm(skeleton, _aim_arm(skeleton, start, "l", targets[0]), "r", targets[1])
    x0 = np.clip(start[idx], lo_in, hi_in)
    q = q0.copy()

    n = len(idx)
    batch = np.repeat(q0[None], n + 1, axis=0)
    steps = np.full(n, _FD_STEP)
    rows = np.arange(n)

    hips = [_N["l_hip"], _N["r_hip"]]
    ankles = skeleton.node_positions(q0)[[_N["l_ankle"], _N["r_ankle"]]]
    reach = np.array([leg_reach(skeleton, "l"), leg_reach(skeleton, "r")])
    leg_w = w.legs if body else 0.0

    head = _N["head"]
    gaze_w = w.gaze if look else 0.0

    def points(poses: NDArray[np.float64]) -> NDArray[np.float64]:
        """(..., k*3 + 4): effector points; how far the farther planted foot is beyond
        its leg's reach (a step or crouch must leave one foot where it was); the
        face's forward axis minus the direction to the ball (the gaze)."""
        frames = skeleton.forward(poses)
        nodes = frames[..., :3, 3]
        pts = _effector_from_nodes(nodes, effector, palm)
        over = np.linalg.norm(nodes[..., hips, :] - ankles, axis=-1) - reach
        excess = leg_w * np.maximum(np.max(over, axis=-1), 0.0)
        to_ball = p - nodes[..., head, :]
        to_ball = to_ball / np.maximum(np.linalg.norm(to_ball, axis=-1, keepdims=True), 1e-9)
        gaze = gaze_w * (frames[..., head, :3, 2] - to_ball)
        return np.concatenate([pts.reshape(pts.shape[:-2] + (-1,)), excess[..., None], gaze],
                              -1)

    goal = np.concatenate([targets.ravel(), [0.0, 0.0, 0.0, 0.0]])

    def residual(x: NDArray[np.float64], scale: float) -> NDArray[np.float64]:
        q[idx] = x
        return np.concatenate([points(q) - goal, scale * cost * (x - ref)])

    def jacobian(x: NDArray[np.float64], scale: float) -> NDArray[np.float64]:
        # forward differences, every perturbed pose in one batched FK call
        batch[:, idx] = x
        batch[rows + 1, idx] += steps
        pts = points(batch)
        jac_eff = ((pts[1:] - pts[0]) / steps[:, None]).T
        return np.vstack([jac_eff, np.diag(scale * cost)])

    sol = least_squares(residual, x0, jac=jacobian, bounds=(lo, hi), args=(1.0,),
                        method="trf", max_nfev=60)
    sol = least_squares(residual, np.clip(sol.x, lo_in, hi_in), jac=jacobian,
                        bounds=(lo, hi), args=(0.1,), method="trf", max_nfev=30)
    x = np.clip(sol.x, lo, hi)
    pose = q0.copy()
    pose[idx] = x
    err = float(np.max(np.linalg.norm(
        effector_points(skeleton, pose, effector, palm) - targets, axis=-1)))
    shift = pose[:3] - q0[:3]
    indices, values = idx[~is_root], x[~is_root]
    if float(np.linalg.norm(shift)) > 1e-4:
        pose = plant_feet(skeleton, q0, pose, left)
        indices = np.concatenate([indices, LEG_INDICES])
        values = np.concatenate([values, pose[LEG_INDICES]])
    return ReachPose(effector=effector, pose=pose, indices=indices, values=values,
                     shift=shift, error=err, targets=targets)
