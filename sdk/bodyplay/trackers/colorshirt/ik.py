"""Fitting the skeleton to patch centroids: 6-DOF global pose and upper-body IK.

Each visible patch is a *patch anchor* (its rendered centroid back-projected and
attached to its bone); the paper's energy ``sum ||c(q) - c||^2_Sigma_c + ||q -
q_b||^2_Sigma_b + ||q - q_h||^2_Sigma_p`` (diagonal covariances, :class:`PriorModel`)
is minimized by MINPACK's Levenberg-Marquardt, the pelvis orientation as a small
rotation applied to the start, the Jacobian's perturbed poses projected in one
numba call.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources

import numba
import numpy as np
from numpy.typing import NDArray
from scipy.optimize import leastsq

from bodyplay.body.rotations import matrix_to_rotvec, rodrigues_into, rotvec_to_matrix
from bodyplay.body.skeleton import NODE_NAMES, NODE_PARENTS, Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError

__all__ = [
    "IK_NODES",
    "GLOBAL_DOFS",
    "ik_dofs",
    "PatchAnchors",
    "PriorModel",
    "RootPrior",
    "KinematicSolver",
    "default_prior_model",
]

IK_NODES: tuple[str, ...] = (
    "pelvis", "lumbar", "thorax", "neck",
    "l_clavicle", "l_shoulder", "l_elbow",
    "r_clavicle", "r_shoulder", "r_elbow",
)
"""Nodes whose rotations IK adjusts (they move the shirt); the rest keep the blend."""

GLOBAL_DOFS: tuple[int, ...] = (0, 1, 2, 3, 4, 5)
"""Root position and pelvis orientation in the pose vector."""

_TURN = 4
"""Index of the pelvis's turn about its up axis among the 6-DOF fit's parameters."""
_TRUNK_TURN = [3 + 3 * IK_NODES.index(n) + 1 for n in ("pelvis", "lumbar", "thorax")]
"""Indices of the trunk's turns (pelvis, lumbar, thorax) among the IK's parameters."""


def ik_dofs() -> NDArray[np.int64]:
    """Indices into the pose vector of the IK's free parameters (root + IK_NODES)."""
    idx = [0, 1, 2]
    for name in IK_NODES:
        i = 3 + 3 * NODE_NAMES.index(name)
        idx += [i, i + 1, i + 2]
    return np.asarray(idx, dtype=np.int64)


@numba.njit(cache=True, nogil=True)
def _fk(  # pragma: no cover - compiled
    q: NDArray[np.float64],
    R0: NDArray[np.float64],
    offsets: NDArray[np.float64],
    parents: NDArray[np.int64],
    upto: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Node rotations and positions for nodes 0..upto-1; root rotation is R0 exp(q[3:6])."""
    rot = np.empty((upto, 3, 3))
    pos = np.empty((upto, 3))
    Rl = np.empty((3, 3))
    for i in range(upto):
        rodrigues_into(q[3 + 3 * i], q[4 + 3 * i], q[5 + 3 * i], Rl)
        p = parents[i]
        # parent rotation (R0 for the root) times the local one, written out: a
        # 3x3 product through np.dot costs more in call overhead than in arithmetic
        P = R0 if p < 0 else rot[p]
        for r in range(3):
            for c in range(3):
                rot[i, r, c] = P[r, 0] * Rl[0, c] + P[r, 1] * Rl[1, c] + P[r, 2] * Rl[2, c]
        if p < 0:
            pos[i, 0] = q[0]
            pos[i, 1] = q[1]
            pos[i, 2] = q[2]
        else:
            for r in range(3):
                pos[i, r] = pos[p, r] + (
                    P[r, 0] * offsets[i, 0] + P[r, 1] * offsets[i, 1] + P[r, 2] * offsets[i, 2]
                )
    return rot, pos


@numba.njit(cache=True, nogil=True)
def _project_anchors(  # pragma: no cover - compiled
    Q: NDArray[np.float64],
    R0: NDArray[np.float64],
    offsets: NDArray[np.float64],
    parents: NDArray[np.int64],
    upto: int,
    a_node: NDArray[np.int64],
    a_local: NDArray[np.float64],
    a_cam: NDArray[np.int64],
    Ks: NDArray[np.float64],
    Rs: NDArray[np.float64],
    ts: NDArray[np.float64],
) -> NDArray[np.float64]:
    P = Q.shape[0]
    A = a_node.shape[0]
    out = np.empty((P, A, 2))
    for b in range(P):
        rot, pos = _fk(Q[b], R0, offsets, parents, upto)
        for a in range(A):
            n = a_node[a]
            w = np.empty(3)
            for r in range(3):
                w[r] = pos[n, r] + (
                    rot[n, r, 0] * a_local[a, 0]
                    + rot[n, r, 1] * a_local[a, 1]
                    + rot[n, r, 2] * a_local[a, 2]
                )
            c = a_cam[a]
            x = Rs[c, 0, 0] * w[0] + Rs[c, 0, 1] * w[1] + Rs[c, 0, 2] * w[2] + ts[c, 0]
            y = Rs[c, 1, 0] * w[0] + Rs[c, 1, 1] * w[1] + Rs[c, 1, 2] * w[2] + ts[c, 1]
            z = Rs[c, 2, 0] * w[0] + Rs[c, 2, 1] * w[1] + Rs[c, 2, 2] * w[2] + ts[c, 2]
            z = max(z, 1e-3)
            out[b, a, 0] = Ks[c, 0, 0] * x / z + Ks[c, 0, 1] * y / z + Ks[c, 0, 2]
            out[b, a, 1] = Ks[c, 1, 1] * y / z + Ks[c, 1, 2]
    return out


@dataclass(frozen=True, eq=False)
class PatchAnchors:
    """Points attached to bones whose projections should hit observed centroids.

    ``node`` (A,) skeleton node of each anchor, ``local`` (A, 3) its position in that
    node's frame, ``camera`` (A,) camera index, ``target`` (A, 2) observed pixel
    centroid, ``sigma`` (A,) pixel standard deviation of the constraint,
    ``patch`` (A,) patch id (for reporting).
    """

    node: NDArray[np.int64]
    local: NDArray[np.float64]
    camera: NDArray[np.int64]
    target: NDArray[np.float64]
    sigma: NDArray[np.float64]
    patch: NDArray[np.int64]

    def __len__(self) -> int:
        return int(self.node.shape[0])

    @classmethod
    def empty(cls) -> PatchAnchors:
        """No anchors."""
        z = np.zeros(0, np.int64)
        return cls(z, np.zeros((0, 3)), z, np.zeros((0, 2)), np.zeros(0), z)

    def join(self, other: PatchAnchors) -> PatchAnchors:
        """These anchors followed by ``other``'s."""
        if len(other) == 0:
            return self
        return PatchAnchors(*(np.concatenate([getattr(self, f), getattr(other, f)]) for f in
                              ("node", "local", "camera", "target", "sigma", "patch")))


@dataclass(frozen=True)
class PriorModel:
    """Diagonal covariances of the IK energy, trained on synthetic ground truth
    (``benchmarks/colorshirt_train_prior.py``).

    ``centroid`` is the std of a centroid constraint as a fraction of the shirt's
    size in the image; ``blend`` and ``previous`` are per-free-DOF stds (metres for
    the root, radians for rotations) of ``q - q_b`` and ``q - q_h``.
    """

    centroid: float
    blend: tuple[float, ...]
    previous: tuple[float, ...]

    def __post_init__(self) -> None:
        n = len(ik_dofs())
        if len(self.blend) != n or len(self.previous) != n:
            raise ConfigError(f"prior model needs {n} blend and previous stds")
        if self.centroid <= 0 or min(self.blend) <= 0 or min(self.previous) <= 0:
            raise ConfigError("prior model stds must be positive")

    def to_dict(self) -> dict[str, object]:
        """JSON-ready form."""
        return {"centroid": self.centroid, "blend": list(self.blend),
                "previous": list(self.previous)}

    @classmethod
    def from_dict(cls, data: dict[str, object]) -> PriorModel:
        """Inverse of :meth:`to_dict`."""
        return cls(float(data["centroid"]),  # type: ignore[arg-type]
                   tuple(float(v) for v in data["blend"]),  # type: ignore[attr-defined]
                   tuple(float(v) for v in data["previous"]))  # type: ignore[attr-defined]


def default_prior_model() -> PriorModel:
    """The shipped trained priors, or hand-set ones when none are installed."""
    res = resources.files("bodyplay").joinpath("assets", "colorshirt", "ik_prior.json")
    if res.is_file():
        return PriorModel.from_dict(json.loads(res.read_text()))
    n = len(ik_dofs())
    blend = [0.05] * 3 + [0.15] * 3 + [0.35] * (n - 6)
    prev = [0.05] * 3 + [0.1] * 3 + [0.3] * (n - 6)
    return PriorModel(0.02, tuple(blend), tuple(prev))


@dataclass(frozen=True)
class RootPrior:
    """A Gaussian prior ``direction . root ~ N(target, std^2)`` (metres), e.g. the
    root's depth along a camera's axis (:meth:`camera_depth`)."""

    direction: tuple[float, float, float]
    target: float
    std: float

    @classmethod
    def camera_depth(cls, camera: Camera, depth: float, std: float) -> RootPrior:
        """The root at ``depth`` metres along ``camera``'s optical axis."""
        axis = camera.R[2]
        return cls((float(axis[0]), float(axis[1]), float(axis[2])),
                   float(depth - camera.t[2]), float(std))


class KinematicSolver:
    """Projects bone-attached anchors and solves 6-DOF and IK fits for one skeleton."""

    def __init__(self, skeleton: Skeleton, cameras: tuple[Camera, ...]) -> None:
        self.skeleton = skeleton
        self.cameras = cameras
        self._offsets = np.ascontiguousarray(skeleton.offsets, dtype=np.float64)
        self._parents = np.asarray(NODE_PARENTS, dtype=np.int64)
        # nodes up to and including the last upper-body node are enough for anchors
        self._upto = NODE_NAMES.index("r_hand") + 1
        self._Ks = np.stack([c.K for c in cameras]).astype(np.float64)
        self._Rs = np.stack([c.R for c in cameras]).astype(np.float64)
        self._ts = np.stack([c.t for c in cameras]).astype(np.float64)
        self._free_ik = ik_dofs()
        self._torso_nodes = np.array([NODE_NAMES.index(n) for n in ("lumbar", "thorax")])
        self._lo, self._hi = skeleton.limits

    # ---- anchors -----------------------------------------------------------------
    def attach(
        self, q: NDArray[np.float64], node: NDArray[np.int64], world: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Express world points (A, 3) in the frames of ``node`` (A,) at pose ``q``."""
        G = self.skeleton.forward(q)
        R = G[node, :3, :3]
        p = G[node, :3, 3]
        return np.einsum("aji,aj->ai", R, world - p)

    def project(self, Q: NDArray[np.float64], anchors: PatchAnchors,
                R0: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """(P, pose_dim) poses -> (P, A, 2) pixel projections of the anchors."""
        return _project_anchors(
            np.ascontiguousarray(np.atleast_2d(Q), dtype=np.float64),
            np.eye(3) if R0 is None else R0,
            self._offsets, self._parents, self._upto,
            anchors.node, anchors.local, anchors.camera, self._Ks, self._Rs, self._ts,
        )

    # ---- solving -----------------------------------------------------------------
    def _solve(self, q0: NDArray[np.float64], R0: NDArray[np.float64], free: NDArray[np.int64],
               a: PatchAnchors, priors: list[tuple[NDArray[np.float64], NDArray[np.float64]]],
               root_priors: tuple[RootPrior, ...], max_nfev: int, limits: bool
               ) -> NDArray[np.float64]:
        """Levenberg-Marquardt on anchors + priors (one or more; + joint limits as residuals
        ``(q - hi) / 0.02`` beyond the bounds; the result is clamped to them)."""
        inv_sigma = 1.0 / a.sigma
        lo = self._lo[free].copy()
        hi = self._hi[free].copy()
        lo[:6] = -np.inf  # root position and the pelvis delta rotation are free
        hi[:6] = np.inf
        lim = np.isfinite(lo) & limits
        x0 = np.clip(q0[free], lo, hi)
        n_a = len(a)
        n_x = len(free)
        n_rp = len(root_priors)
        n_res = 2 * n_a + n_x * len(priors) + n_rp + int(lim.sum())
        if n_res < n_x:  # LM needs at least as many residuals as unknowns
            return q0
        inv_soft = 1.0 / 0.02
        Qbuf = np.repeat(q0[None], n_x + 1, axis=0)
        lim_idx = np.nonzero(lim)[0]
        lo_l, hi_l = lo[lim_idx], hi[lim_idx]
        n_pr = n_x * len(priors)
        targets = np.concatenate([t for t, _ in priors])
        inv_std = np.concatenate([w for _, w in priors])
        tgt = (a.target * inv_sigma[:, None]).ravel()
        inv_s = np.repeat(inv_sigma, 2)
        r_out = np.empty(n_res)
        # the prior rows of the Jacobian are constant; only anchors and limits change
        J_out = np.zeros((n_res, n_x))
        for k in range(len(priors)):
            J_out[2 * n_a + k * n_x: 2 * n_a + (k + 1) * n_x] = np.diag(priors[k][1])
        rp_dir = np.array([r.direction for r in root_priors]).reshape(n_rp, 3)
        rp_w = np.array([1.0 / r.std for r in root_priors])
        rp_t = np.array([r.target for r in root_priors]) * rp_w
        if n_rp:  # the root position is free dofs 0..2
            J_out[2 * n_a + n_pr: 2 * n_a + n_pr + n_rp, :3] = rp_dir * rp_w[:, None]
        lim_rows = 2 * n_a + n_pr + n_rp + np.arange(len(lim_idx))
        eps = 1e-6
        steps = np.eye(n_x) * eps

        def fun(x: NDArray[np.float64]) -> NDArray[np.float64]:
            Qbuf[0, free] = x
            proj = self.project(Qbuf[:1], a, R0)[0]
            r_out[: 2 * n_a] = proj.ravel() * inv_s - tgt
            r_out[2 * n_a: 2 * n_a + n_pr] = (np.tile(x, len(priors)) - targets) * inv_std
            if n_rp:
                r_out[2 * n_a + n_pr: 2 * n_a + n_pr + n_rp] = (rp_dir @ x[:3]) * rp_w - rp_t
            if len(lim_idx):
                xl = x[lim_idx]
                r_out[2 * n_a + n_pr + n_rp:] = (np.maximum(xl - hi_l, 0.0)
                                                 + np.minimum(xl - lo_l, 0.0)) * inv_soft
            return r_out.copy()

        def jac(x: NDArray[np.float64]) -> NDArray[np.float64]:
            Qbuf[:, free] = x
            Qbuf[1:, free] += steps
            proj = self.project(Qbuf, a, R0).reshape(n_x + 1, 2 * n_a)
            J_out[: 2 * n_a] = ((proj[1:] - proj[0]) * (inv_s / eps)).T
            if len(lim_idx):
                xl = x[lim_idx]
                J_out[lim_rows, lim_idx] = ((xl > hi_l) | (xl < lo_l)) * inv_soft
            return J_out.copy()

        # MINPACK's lmder through leastsq (least_squares' tolerances, less Python)
        x_opt = leastsq(fun, x0, Dfun=jac, ftol=1e-8, xtol=1e-8, gtol=1e-8,
                        maxfev=max_nfev, full_output=True)[0]
        q = q0.copy()
        q[free] = np.clip(x_opt, lo, hi)
        return q

    def _with_delta_root(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                 NDArray[np.float64]]:
        R0 = rotvec_to_matrix(q[3:6])
        qd = q.copy()
        qd[3:6] = 0.0
        return qd, R0

    @staticmethod
    def _compose_root(q: NDArray[np.float64], R0: NDArray[np.float64]) -> NDArray[np.float64]:
        out = q.copy()
        out[3:6] = matrix_to_rotvec(R0 @ rotvec_to_matrix(q[3:6]))
        return out

    def solve_global(self, q: NDArray[np.float64], anchors: PatchAnchors,
                     max_nfev: int = 10, root_priors: tuple[RootPrior, ...] = (),
                     position_std: float | None = None,
                     turn_std: float | None = None) -> NDArray[np.float64]:
        """6-DOF fit: root position and pelvis orientation; the articulation is kept.

        Only torso anchors when at least three are visible (the blend's arms may be
        wrong). A prior holds the fit near ``q``: 0.3 rad on the orientation (the
        turn ``turn_std`` if given), ``position_std`` metres on the root (None: 1 / 3.3).
        """
        torso = np.isin(anchors.node, self._torso_nodes)
        if int(torso.sum()) >= 3:
            anchors = PatchAnchors(*(getattr(anchors, f)[torso] for f in
                                     ("node", "local", "camera", "target", "sigma", "patch")))
        if len(anchors) < 3:
            return q
        qd, R0 = self._with_delta_root(q)
        free = np.asarray(GLOBAL_DOFS, dtype=np.int64)
        # the database placement is a fair guess: stds 0.3 m and 0.3 rad
        w = 3.3 if position_std is None else 1.0 / position_std
        inv = np.array([w, w, w, 3.3, 3.3, 3.3])
        if turn_std is not None:
            inv[_TURN] = 1.0 / turn_std
        prior = [(qd[free].copy(), inv)]
        out = self._solve(qd, R0, free, anchors, prior, root_priors, max_nfev, limits=False)
        return self._compose_root(out, R0)

    def solve_ik(
        self,
        q_blend: NDArray[np.float64],
        anchors: PatchAnchors,
        prior: PriorModel | None,
        q_prev: NDArray[np.float64] | None,
        max_nfev: int = 10,
        root_priors: tuple[RootPrior, ...] = (),
        turn_std: float | None = None,
    ) -> NDArray[np.float64]:
        """Upper-body IK on the anchors from ``q_blend``, with priors towards it and
        ``q_prev`` (without a prior model, a weak one towards the blend)."""
        qd, R0 = self._with_delta_root(q_blend)
        free = self._free_ik

        def as_delta(q: NDArray[np.float64]) -> NDArray[np.float64]:
            out = q[free].copy()
            out[3:6] = matrix_to_rotvec(R0.T @ rotvec_to_matrix(q[3:6]))
            return out

        blend = 1.0 / np.asarray(prior.blend) if prior is not None else np.full(len(free), 0.5)
        if turn_std is not None:  # a second prior on the trunk's turns, combined
            blend = blend.copy()
            blend[_TRUNK_TURN] = np.hypot(blend[_TRUNK_TURN], 1.0 / turn_std)
        priors: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = [
            (as_delta(q_blend), blend)]
        if prior is not None and q_prev is not None:
            priors.append((as_delta(q_prev), 1.0 / np.asarray(prior.previous)))
        out = self._solve(qd, R0, free, anchors, priors, root_priors, max_nfev, limits=True)
        return self._compose_root(out, R0)
