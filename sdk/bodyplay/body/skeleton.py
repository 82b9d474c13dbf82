"""The kinematic skeleton: bones, pose vectors, forward kinematics, joint limits.

The skeleton has internal *nodes* (a tree of rigid bones, e.g. clavicles, hand and
toe ends) from which the 17 output joints of :mod:`bodyplay.body.joints` are derived.

A *pose vector* ``q`` has ``pose_dim = 3 + 3 * num_nodes`` numbers: the root (pelvis)
position in world metres, then one rotation vector per node, expressed in the
parent's frame (node 0's is the global orientation of the pelvis). The rest pose
(all rotations zero) is a T-pose standing on the floor, facing +Z, Y up, the
person's left on +X. Every function takes any leading batch shape, ``(..., pose_dim)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numba import njit, prange
from numpy.typing import ArrayLike, NDArray

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES, NUM_JOINTS
from bodyplay.body.rotations import rodrigues_into
from bodyplay.body.shapes import BodyShape, body_shape
from bodyplay.errors import ConfigError

__all__ = ["Skeleton", "NODE_NAMES", "NODE_PARENTS"]

# name, parent, offset from parent in the reference (1.75 m) T-pose, metres,
# and whether the offset's x component is a breadth (scaled by build, not height).
_NODES: tuple[tuple[str, str | None, tuple[float, float, float], bool], ...] = (
    ("pelvis", None, (0.0, 0.0, 0.0), False),
    ("lumbar", "pelvis", (0.0, 0.12, -0.01), False),
    ("thorax", "lumbar", (0.0, 0.16, -0.01), False),
    ("neck", "thorax", (0.0, 0.22, 0.0), False),
    ("head", "neck", (0.0, 0.18, 0.01), False),
    ("head_top", "head", (0.0, 0.13, 0.0), False),
    ("l_clavicle", "neck", (0.03, -0.01, 0.0), True),
    ("l_shoulder", "l_clavicle", (0.155, 0.0, -0.01), True),
    ("l_elbow", "l_shoulder", (0.285, 0.0, 0.0), False),
    ("l_wrist", "l_elbow", (0.255, 0.0, 0.0), False),
    ("l_hand", "l_wrist", (0.09, 0.0, 0.0), False),
    ("r_clavicle", "neck", (-0.03, -0.01, 0.0), True),
    ("r_shoulder", "r_clavicle", (-0.155, 0.0, -0.01), True),
    ("r_elbow", "r_shoulder", (-0.285, 0.0, 0.0), False),
    ("r_wrist", "r_elbow", (-0.255, 0.0, 0.0), False),
    ("r_hand", "r_wrist", (-0.09, 0.0, 0.0), False),
    ("l_hip", "pelvis", (0.09, 0.0, 0.0), True),
    ("l_knee", "l_hip", (0.0, -0.43, 0.0), False),
    ("l_ankle", "l_knee", (0.0, -0.42, 0.0), False),
    ("l_toe", "l_ankle", (0.0, -0.06, 0.15), False),
    ("r_hip", "pelvis", (-0.09, 0.0, 0.0), True),
    ("r_knee", "r_hip", (0.0, -0.43, 0.0), False),
    ("r_ankle", "r_knee", (0.0, -0.42, 0.0), False),
    ("r_toe", "r_ankle", (0.0, -0.06, 0.15), False),
)

NODE_NAMES: tuple[str, ...] = tuple(n[0] for n in _NODES)
"""Internal skeleton nodes, in pose-vector order."""

NODE_PARENTS: tuple[int, ...] = tuple(
    -1 if p is None else NODE_NAMES.index(p) for _, p, _, _ in _NODES
)
"""Index of each node's parent (-1 for the root)."""

# Height of the ankle centres above the floor for the 1.75 m body.
_REFERENCE_ANKLE_HEIGHT = 0.08

# Joint limits as boxes on rotation-vector components (radians), in the parent frame.
# Rest T-pose: arms along +-X, legs along -Y. Loose but anatomical.
_LIMITS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "pelvis": ((-np.pi, -np.pi, -np.pi), (np.pi, np.pi, np.pi)),
    "lumbar": ((-0.5, -0.6, -0.4), (0.9, 0.6, 0.4)),
    "thorax": ((-0.4, -0.5, -0.3), (0.6, 0.5, 0.3)),
    "neck": ((-0.6, -1.0, -0.6), (0.8, 1.0, 0.6)),
    "head": ((-0.5, -0.5, -0.4), (0.5, 0.5, 0.4)),
    "l_clavicle": ((-0.3, -0.4, -0.2), (0.3, 0.4, 0.5)),
    "l_shoulder": ((-1.6, -1.7, -1.8), (1.6, 1.3, 1.7)),
    "l_elbow": ((-0.1, -2.6, -0.1), (0.1, 0.05, 0.1)),
    "l_wrist": ((-1.2, -0.6, -0.9), (1.2, 0.6, 0.9)),
    "r_clavicle": ((-0.3, -0.4, -0.5), (0.3, 0.4, 0.2)),
    "r_shoulder": ((-1.6, -1.3, -1.7), (1.6, 1.7, 1.8)),
    "r_elbow": ((-0.1, -0.05, -0.1), (0.1, 2.6, 0.1)),
    "r_wrist": ((-1.2, -0.6, -0.9), (1.2, 0.6, 0.9)),
    "l_hip": ((-2.2, -0.8, -0.6), (0.6, 0.8, 1.2)),
    "l_knee": ((-0.05, -0.1, -0.1), (2.5, 0.1, 0.1)),
    "l_ankle": ((-0.8, -0.4, -0.4), (0.6, 0.4, 0.4)),
    "r_hip": ((-2.2, -0.8, -1.2), (0.6, 0.8, 0.6)),
    "r_knee": ((-0.05, -0.1, -0.1), (2.5, 0.1, 0.1)),
    "r_ankle": ((-0.8, -0.4, -0.4), (0.6, 0.4, 0.4)),
}


_PARENTS = np.array(NODE_PARENTS, dtype=np.int64)
_PARENTS.setflags(write=False)

# Batches at least this large run the forward kinematics on all cores. A pose costs
# about 1-3 us, so below this waking the worker threads (which may be descheduled on a
# busy machine) costs as much as it saves.
_PARALLEL_BATCH = 1024


@njit(cache=True)
def _fk_pose(q, offsets, parents, out):  # pragma: no cover
    """World transforms (N, 4, 4) of one pose vector ``q`` into ``out``.

    Node rotations follow :func:`~bodyplay.body.rotations.rotvec_to_matrix` (Rodrigues,
    first-order below 1e-8 rad); parents precede their children in node order.
    """
    n = parents.shape[0]
    R = np.empty((3, 3))
    for i in range(n):
        rx = q[3 + 3 * i]
        ry = q[4 + 3 * i]
        rz = q[5 + 3 * i]
        rodrigues_into(rx, ry, rz, R)
        p = parents[i]
        for a in range(3):
            out[i, 3, a] = 0.0
        out[i, 3, 3] = 1.0
        if p < 0:
            for a in range(3):
                for b in range(3):
                    out[i, a, b] = R[a, b]
                out[i, a, 3] = q[a]
        else:
            ox, oy, oz = offsets[i, 0], offsets[i, 1], offsets[i, 2]
            for a in range(3):
                g0, g1, g2 = out[p, a, 0], out[p, a, 1], out[p, a, 2]
                for b in range(3):
                    out[i, a, b] = g0 * R[0, b] + g1 * R[1, b] + g2 * R[2, b]
                out[i, a, 3] = out[p, a, 3] + (g0 * ox + g1 * oy + g2 * oz)


@njit(cache=True)
def _fk_serial(q, offsets, parents, out):  # pragma: no cover
    """:func:`_fk_pose` for every row of ``q`` (B, pose_dim) into ``out`` (B, N, 4, 4)."""
    for b in range(q.shape[0]):
        _fk_pose(q[b], offsets, parents, out[b])


@njit(cache=True, parallel=True)
def _fk_parallel(q, offsets, parents, out):  # pragma: no cover
    """:func:`_fk_serial` with the batch spread over all cores."""
    for b in prange(q.shape[0]):
        _fk_pose(q[b], offsets, parents, out[b])


@dataclass(frozen=True)
class Skeleton:
    """A skeleton of a given body size; computes joint positions from pose vectors.

    Build one with ``Skeleton()`` (reference 1.75 m body) or
    ``Skeleton.from_shape("xl")``. Skeletons are immutable and cheap to share.
    """

    shape: BodyShape = field(default_factory=lambda: body_shape("m"))
    rest_offsets: tuple[tuple[float, float, float], ...] | None = None
    """Explicit (num_nodes, 3) rest offsets, e.g. measured from a mesh; else from shape."""

    @classmethod
    def from_shape(cls, shape: str | BodyShape) -> Skeleton:
        """A skeleton for a body preset name (see :data:`bodyplay.body.BODY_SHAPES`)."""
        return cls(body_shape(shape))

    # ---- structure -------------------------------------------------------------------
    @property
    def node_names(self) -> tuple[str, ...]:
        """Names of the internal nodes, in pose-vector order."""
        return NODE_NAMES

    @property
    def parents(self) -> tuple[int, ...]:
        """Parent index of every node (-1 for the root)."""
        return NODE_PARENTS

    @property
    def num_nodes(self) -> int:
        """Number of internal nodes."""
        return len(NODE_NAMES)

    @property
    def pose_dim(self) -> int:
        """Length of a pose vector: root position plus one rotation vector per node."""
        return 3 + 3 * len(NODE_NAMES)

    def node_index(self, name: str) -> int:
        """Index of a node by name, with a clear error for unknown names."""
        try:
            return NODE_NAMES.index(name)
        except ValueError:
            raise ConfigError(
                f"unknown skeleton node {name!r}; nodes are {', '.join(NODE_NAMES)}"
            ) from None

    @cached_property
    def offsets(self) -> NDArray[np.float64]:
        """(num_nodes, 3) offset of each node from its parent in the rest pose, metres."""
        if self.rest_offsets is not None:
            given = np.asarray(self.rest_offsets, dtype=np.float64)
            if given.shape != (len(_NODES), 3):
                raise ConfigError(f"rest_offsets must have shape ({len(_NODES)}, 3)")
            return given
        s = self.shape
        out = np.zeros((len(_NODES), 3))
        for i, (_, _, off, is_breadth) in enumerate(_NODES):
            o = np.asarray(off) * s.length_scale
            if is_breadth:
                o[0] = off[0] * s.length_scale * s.breadth
            out[i] = o
        return out

    @property
    def pelvis_height(self) -> float:
        """Height of the hip centres above the floor in the rest pose."""
        o = self.offsets
        leg = -(o[NODE_NAMES.index("l_knee"), 1] + o[NODE_NAMES.index("l_ankle"), 1])
        return float(leg + _REFERENCE_ANKLE_HEIGHT * self.shape.length_scale)

    @cached_property
    def limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper bounds of the pose vector (root position unbounded)."""
        lo = np.full(self.pose_dim, -np.inf)
        hi = np.full(self.pose_dim, np.inf)
        for name, (a, b) in _LIMITS.items():
            i = 3 + 3 * NODE_NAMES.index(name)
            lo[i : i + 3] = a
            hi[i : i + 3] = b
        for name in NODE_NAMES:
            if name not in _LIMITS:  # end nodes do not rotate
                i = 3 + 3 * NODE_NAMES.index(name)
                lo[i : i + 3] = 0.0
                hi[i : i + 3] = 0.0
        return lo, hi

    # ---- poses ----------------------------------------------------------------------
    def rest_pose(self) -> NDArray[np.float64]:
        """The T-pose standing on the floor at the origin, facing +Z."""
        q = np.zeros(self.pose_dim)
        q[1] = self.pelvis_height
        return q

    def pose(
        self,
        root: ArrayLike | None = None,
        orientation: ArrayLike | None = None,
        rotations: dict[str, ArrayLike] | None = None,
    ) -> NDArray[np.float64]:
        """Build a pose vector from a root position, orientation and per-node rotations.

        Missing values keep the rest pose; ``rotations`` maps node names to rotation
        vectors in the parent frame.
        """
        q = self.rest_pose()
        if root is not None:
            q[0:3] = np.asarray(root, dtype=float)
        if orientation is not None:
            q[3:6] = np.asarray(orientation, dtype=float)
        for name, rv in (rotations or {}).items():
            i = 3 + 3 * self.node_index(name)
            q[i : i + 3] = np.asarray(rv, dtype=float)
        return q

    def clamp(self, poses: ArrayLike) -> NDArray[np.float64]:
        """Project pose vectors into the joint limits."""
        lo, hi = self.limits
        return np.clip(np.asarray(poses, dtype=float), lo, hi)

    def within_limits(self, poses: ArrayLike, tol: float = 1e-9) -> NDArray[np.bool_]:
        """Whether each pose vector respects the joint limits."""
        lo, hi = self.limits
        q = np.asarray(poses, dtype=float)
        return np.all((q >= lo - tol) & (q <= hi + tol), axis=-1)

    def _check(self, poses: ArrayLike) -> NDArray[np.float64]:
        q = np.asarray(poses, dtype=np.float64)
        if q.shape[-1:] != (self.pose_dim,):
            raise ConfigError(
                f"pose vectors must have {self.pose_dim} values (last axis), got shape {q.shape}"
            )
        if not np.all(np.isfinite(q)):
            raise ConfigError("pose vectors contain NaN or infinite values")
        return q

    # ---- kinematics -----------------------------------------------------------------
    def forward(self, poses: ArrayLike) -> NDArray[np.float64]:
        """Forward kinematics: (..., pose_dim) -> (..., num_nodes, 4, 4) world transforms.

        Each transform maps the node's local frame (rest-pose axes) to world; its
        translation is the node's position. The work is a numba kernel (Rodrigues'
        formula and the chain down the tree per pose), parallel over large batches:
        a single pose costs microseconds, not a Python loop over the nodes.
        """
        q = self._check(poses)
        batch = q.shape[:-1]
        flat = np.ascontiguousarray(q.reshape(-1, self.pose_dim))
        out = np.empty((flat.shape[0], self.num_nodes, 4, 4))
        kernel = _fk_parallel if flat.shape[0] >= _PARALLEL_BATCH else _fk_serial
        kernel(flat, self.offsets, _PARENTS, out)
        return out.reshape(batch + (self.num_nodes, 4, 4))

    def node_positions(self, poses: ArrayLike) -> NDArray[np.float64]:
        """(..., num_nodes, 3) world positions of the internal nodes."""
        return self.forward(poses)[..., :3, 3]

    def joints_from_nodes(self, nodes: NDArray[np.float64]) -> NDArray[np.float64]:
        """Derive the 17 output joints (DESIGN.md definitions) from node positions."""
        idx = {name: i for i, name in enumerate(NODE_NAMES)}
        out = np.empty(nodes.shape[:-2] + (NUM_JOINTS, 3))
        pelvis = 0.5 * (nodes[..., idx["l_hip"], :] + nodes[..., idx["r_hip"], :])
        neck = 0.5 * (nodes[..., idx["l_shoulder"], :] + nodes[..., idx["r_shoulder"], :])
        out[..., JOINT_INDEX["pelvis"], :] = pelvis
        out[..., JOINT_INDEX["neck"], :] = neck
        out[..., JOINT_INDEX["spine"], :] = pelvis + (neck - pelvis) / 3.0
        out[..., JOINT_INDEX["chest"], :] = pelvis + 2.0 * (neck - pelvis) / 3.0
        for name in JOINT_NAMES:
            if name in ("pelvis", "neck", "spine", "chest"):
                continue
            out[..., JOINT_INDEX[name], :] = nodes[..., idx[name], :]
        return out

    def joint_positions(self, poses: ArrayLike) -> NDArray[np.float64]:
        """(..., 17, 3) world positions of the output joints, in JOINT_NAMES order."""
        return self.joints_from_nodes(self.node_positions(poses))

    def bone_lengths(self) -> NDArray[np.float64]:
        """(num_nodes,) length of the bone from each node's parent to it (0 for root)."""
        return np.linalg.norm(self.offsets, axis=-1)
