"""Per-arm refinement of the tree filter's pose against the silhouette (an addition to
the paper).

The tree holds whole-body templates: a pose is only found if some training pose has
*both* arms, the torso, the legs and the heading of the player at once. The
vendored clips never raise one arm while the body stands, so a wave or a raised
hand is answered with the arm down (measured on the tune clips: the right wrist 88
cm off on wave-right-hand; the best leaf of the whole tree by silhouette distance
has it down too). A silhouette shows each arm separately, and the distance of eq.
10-11 is linear in the template mask, so an arm can be searched on its own:

* the body without the arms: the MAP leaf rendered without its arms
  (:mod:`.armless`, ``body="torso"``: where the torso lies behind an arm it is
  the torso's whatever the arm does; silhouette within :data:`MISFIT_BAND` of its
  outline is the torso's own misfit and credits no arm, though an arm there still
  pays for background), or the leaf's template less its arms'
  capsules (upper arm, forearm, hand as thick segments of the body's measured
  radii; ``body="template"``: a leaf whose arm hangs in front of the torso leaves a
  hole over torso silhouette, and its own arm, filling it again, is credited with
  the torso it hid);
* every arm of an *atlas* (configurations spread evenly over where an arm can put
  its elbow and wrist, :func:`arm_atlas`: real arms of the training pose set and
  random ones within the joint limits) is put on the leaf's shoulder and drawn as
  capsules; its cost is the sum of A = D(S) - W (eq. 11's per-pixel term) over its
  pixels outside the body: negative where it covers silhouette left uncovered,
  positive where it sticks out (the arm the tracker would report otherwise, from
  the blended leaves, is scored the same way);
* plus ``stay`` times the 3-D distance (in window pixels) of its elbow and wrist
  from the reported arm's: among arms of about the same silhouette (forward or
  back, hidden in front of the torso) the tree's answer stays.

The best atlas arm replaces the reported one when it is cheaper by more than
``margin``; it hangs from the reported shoulder. A numba kernel scores all
candidates of one arm in a few milliseconds at level 2 (160x120).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numba
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.rotations import rodrigues_into
from bodyplay.body.skeleton import NODE_NAMES, NODE_PARENTS, Skeleton
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.armless import ArmlessBody
from bodyplay.trackers.silhouette.recombine import (
    LIMB_GROUPS,
    limb_columns,
    random_limb_config,
)
from bodyplay.trackers.silhouette.stature import shifted
from bodyplay.trackers.silhouette.window import WindowGeometry

__all__ = ["ARM_BODIES", "MISFIT_BAND", "ArmFit", "ArmFitter", "arm_atlas"]

ARM_BODIES = ("torso", "template")
"""What the arms are scored against (:class:`ArmFitter`'s ``body``)."""

MISFIT_BAND = 0.036
"""Silhouette within this distance (m; 2 pixels at level 2) of the body rendered
without its arms is the body's own misfit and credits no arm (chosen on the tune
captures over three tree seeds: 0, 1, 2, 3 pixels gave a mean of 10.7, 10.5, 10.3,
10.4 cm)."""

_RADII = (0.05, 0.04, 0.035)  # upper arm, forearm, hand (m): the body mesh's medians
_HAND = 0.17  # the hand capsule runs this far on along the forearm (finger tips, m)


def arm_atlas(skeleton: Skeleton, sources: list[NDArray[np.float64]], count: int,
              rng: np.random.Generator, candidates: int = 6000) -> NDArray[np.float64]:
    """``count`` left-arm configurations (the columns of :data:`LIMB_GROUPS`' left arm,
    (count, 12)) spread evenly over the places an arm can put its elbow and wrist.

    Candidates: every left arm of ``sources`` (mirrored sources give right arms
    moved to the left) and ``candidates`` random configurations within the joint
    limits; each is placed on the upright rest body and the greedy farthest-point
    rule picks ``count`` of them by the elbow and wrist positions relative to the
    shoulder (what a silhouette shows of an arm)."""
    if count < 1:
        raise ConfigError("the arm atlas needs at least one arm")
    cols = limb_columns(skeleton, LIMB_GROUPS[1])
    real = np.concatenate([s[:, cols] for s in sources]) if sources else np.zeros((0, len(cols)))
    rand = np.array([random_limb_config(skeleton, LIMB_GROUPS[1], rng) for _ in range(candidates)])
    arms = np.concatenate([real, rand])
    X = np.empty((len(arms), 6))
    q = np.empty((len(arms), skeleton.pose_dim))
    for a in range(0, len(arms), 2000):  # in chunks: the forward kinematics' 4x4 frames
        qa = np.tile(skeleton.rest_pose(), (len(arms[a:a + 2000]), 1))
        qa[:, cols] = arms[a:a + 2000]
        q[a:a + 2000] = qa = skeleton.clamp(qa)
        J = skeleton.joint_positions(qa)
        sh = J[:, JOINT_INDEX["l_shoulder"]]
        X[a:a + 2000, :3] = J[:, JOINT_INDEX["l_elbow"]] - sh
        X[a:a + 2000, 3:] = J[:, JOINT_INDEX["l_wrist"]] - sh
    count = min(count, len(X))
    chosen = np.empty(count, np.int64)
    chosen[0] = int(rng.integers(len(X)))
    d = np.sum((X - X[chosen[0]]) ** 2, axis=1)
    for k in range(1, count):
        chosen[k] = int(np.argmax(d))
        np.minimum(d, np.sum((X - X[chosen[k]]) ** 2, axis=1), out=d)
    return q[chosen][:, cols]


@numba.njit(cache=True)
def _chain_positions(top, rotvecs, offsets, nodes, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """World positions of a chain's nodes for many rotations of its joints, the
    arithmetic of the skeleton's forward kinematics (``_fk_pose``) node for node.

    ``top``: the 4x4 world transform of the chain's parent (the same for every
    candidate); ``nodes``: the chain's node indices, each the parent of the next;
    ``rotvecs`` (N, 3 * (len(nodes) - 1)): the rotation vectors of all but the last;
    ``out`` (N, len(nodes) - 1, 3): the positions of all but the first (its
    position is fixed by ``top``; the last node's rotation moves nothing read)."""
    R = np.empty((3, 3))
    G = np.empty((3, 4))
    H = np.empty((3, 4))
    m = nodes.shape[0]
    for k in range(rotvecs.shape[0]):
        for a in range(3):
            for b in range(4):
                G[a, b] = top[a, b]
        for c in range(m - 1):
            i = nodes[c]
            ox, oy, oz = offsets[i, 0], offsets[i, 1], offsets[i, 2]
            rodrigues_into(rotvecs[k, 3 * c], rotvecs[k, 3 * c + 1], rotvecs[k, 3 * c + 2], R)
            for a in range(3):
                g0, g1, g2 = G[a, 0], G[a, 1], G[a, 2]
                for b in range(3):
                    H[a, b] = g0 * R[0, b] + g1 * R[1, b] + g2 * R[2, b]
                H[a, 3] = G[a, 3] + (g0 * ox + g1 * oy + g2 * oz)
            for a in range(3):
                for b in range(4):
                    G[a, b] = H[a, b]
            # the next node's position: this node's transform applied to its offset
            j = nodes[c + 1]
            px, py, pz = offsets[j, 0], offsets[j, 1], offsets[j, 2]
            for a in range(3):
                out[k, c, a] = G[a, 3] + (G[a, 0] * px + G[a, 1] * py + G[a, 2] * pz)


@numba.njit(cache=True)
def _capsule_setup(pts, k, radii, h, w, box, bx0, bx1, by0, by1, sa):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Candidate ``k``'s box (x0, y0, x1, y1, clipped to the image) into ``box``, and
    per segment its capsule box and (start, direction, squared length, squared
    radius) into ``sa``; False when a point is not finite."""
    x0 = w
    x1 = -1
    y0 = h
    y1 = -1
    for j in range(4):
        px = pts[k, j, 0]
        py = pts[k, j, 1]
        if not (px == px and py == py):
            return False
        x0 = min(x0, int(np.floor(px - radii[0])))
        x1 = max(x1, int(np.ceil(px + radii[0])))
        y0 = min(y0, int(np.floor(py - radii[0])))
        y1 = max(y1, int(np.ceil(py + radii[0])))
    box[0] = max(x0, 0)
    box[1] = max(y0, 0)
    box[2] = min(x1, w - 1)
    box[3] = min(y1, h - 1)
    for j in range(3):
        r = radii[j]
        sa[j, 0] = pts[k, j, 0]
        sa[j, 1] = pts[k, j, 1]
        sa[j, 2] = pts[k, j + 1, 0] - sa[j, 0]
        sa[j, 3] = pts[k, j + 1, 1] - sa[j, 1]
        sa[j, 4] = sa[j, 2] * sa[j, 2] + sa[j, 3] * sa[j, 3]
        sa[j, 5] = r * r
        bx0[j] = int(np.floor(min(pts[k, j, 0], pts[k, j + 1, 0]) - r))
        bx1[j] = int(np.ceil(max(pts[k, j, 0], pts[k, j + 1, 0]) + r))
        by0[j] = int(np.floor(min(pts[k, j, 1], pts[k, j + 1, 1]) - r))
        by1[j] = int(np.ceil(max(pts[k, j, 1], pts[k, j + 1, 1]) + r))
    return True


@numba.njit(cache=True)
def _row_span(y, box, bx0, bx1, by0, by1):  # type: ignore[no-untyped-def]  # pragma: no cover
    """The columns of row ``y`` a candidate's pixels can be in: the span of the
    capsule boxes holding the row, within the candidate's box (empty: lo > hi)."""
    rx0 = box[2] + 1
    rx1 = box[0] - 1
    for j in range(3):
        if by0[j] <= y <= by1[j]:
            rx0 = min(rx0, bx0[j])
            rx1 = max(rx1, bx1[j])
    return max(rx0, box[0]), min(rx1, box[2])


@numba.njit(cache=True)
def _capsule_sum(box, bx0, bx1, by0, by1, sa, cost, body):  # type: ignore[no-untyped-def]  # pragma: no cover
    """One candidate's sum (set up by :func:`_capsule_setup`): each pixel tested only
    against the segments whose box holds it, a row only over their boxes' span (the
    same pixels in the same order as the whole box, so the same sum)."""
    s = 0.0
    for y in range(box[1], box[3] + 1):
        rx0, rx1 = _row_span(y, box, bx0, bx1, by0, by1)
        for x in range(rx0, rx1 + 1):
            if body[y, x]:
                continue
            inside = False
            for j in range(3):
                if not (bx0[j] <= x <= bx1[j] and by0[j] <= y <= by1[j]):
                    continue
                ax, ay, bx, by, ll = sa[j, 0], sa[j, 1], sa[j, 2], sa[j, 3], sa[j, 4]
                t = 0.0
                if ll > 1e-12:
                    t = ((x - ax) * bx + (y - ay) * by) / ll
                    t = min(1.0, max(0.0, t))
                dx = x - ax - t * bx
                dy = y - ay - t * by
                if dx * dx + dy * dy <= sa[j, 5]:
                    inside = True
                    break
            if inside:
                s += cost[y, x]
    return s


@numba.njit(cache=True)
def _capsule_costs_bounded(pts, radii, cost, body, extra, order, negative, out):  # type: ignore[no-untyped-def]  # pragma: no cover
    """Per candidate that can still be the cheapest: the sum of ``cost`` over pixels
    within radius of one of its three segments (pts[k, 0..3] the chain shoulder,
    elbow, wrist, finger tips) and not in ``body`` (:func:`_capsule_sum`; 1e9 for a
    candidate with a point not finite). In ``order``, a candidate whose lower bound
    plus ``extra[k]`` exceeds the least ``out + extra`` so far is skipped
    (``out[k]`` = inf). The bound: over its rows' spans, the sum of
    ``negative`` (per row, the running sum of min(cost, 0) outside ``body``, a
    column longer than ``cost``), which no covered pixel set can undercut; skipping
    asks it to exceed the best by a margin far above the rounding of either sum,
    so a skipped candidate was never the cheapest (nor tied with it)."""
    h, w = cost.shape
    box = np.empty(4, np.int64)
    bx0 = np.empty(3, np.int64)
    bx1 = np.empty(3, np.int64)
    by0 = np.empty(3, np.int64)
    by1 = np.empty(3, np.int64)
    sa = np.empty((3, 6))
    best = np.inf
    for i in range(order.shape[0]):
        k = order[i]
        if not _capsule_setup(pts, k, radii, h, w, box, bx0, bx1, by0, by1, sa):
            out[k] = 1e9
        else:
            low = 0.0
            for y in range(box[1], box[3] + 1):
                rx0, rx1 = _row_span(y, box, bx0, bx1, by0, by1)
                if rx0 <= rx1:
                    low += negative[y, rx1 + 1] - negative[y, rx0]
            if low + extra[k] > best + 1e-6 * (1.0 + abs(best) + abs(low)):
                out[k] = np.inf
                continue
            out[k] = _capsule_sum(box, bx0, bx1, by0, by1, sa, cost, body)
        best = min(best, out[k] + extra[k])


@numba.njit(cache=True)
def _draw(pts, radii, mask):  # type: ignore[no-untyped-def]  # pragma: no cover
    h, w = mask.shape
    r = max(radii[0], radii[1], radii[2])
    x0 = max(0, int(np.floor(min(pts[0, 0], pts[1, 0], pts[2, 0], pts[3, 0]) - r)))
    x1 = min(w - 1, int(np.ceil(max(pts[0, 0], pts[1, 0], pts[2, 0], pts[3, 0]) + r)))
    y0 = max(0, int(np.floor(min(pts[0, 1], pts[1, 1], pts[2, 1], pts[3, 1]) - r)))
    y1 = min(h - 1, int(np.ceil(max(pts[0, 1], pts[1, 1], pts[2, 1], pts[3, 1]) + r)))
    for y in range(y0, y1 + 1):
        for x in range(x0, x1 + 1):
            for j in range(3):
                ax = pts[j, 0]
                ay = pts[j, 1]
                bx = pts[j + 1, 0] - ax
                by = pts[j + 1, 1] - ay
                ll = bx * bx + by * by
                t = 0.0
                if ll > 1e-12:
                    t = min(1.0, max(0.0, ((x - ax) * bx + (y - ay) * by) / ll))
                dx = x - ax - t * bx
                dy = y - ay - t * by
                if dx * dx + dy * dy <= radii[j] * radii[j]:
                    mask[y, x] = 1
                    break


@dataclass(frozen=True, eq=False)
class ArmFit:
    """The refined pose (template frame, like the leaf's) and, per arm (left,
    right), whether the atlas arm replaced the leaf's and the cost gained."""

    pose: NDArray[np.float64]
    replaced: tuple[bool, bool]
    gain: tuple[float, float]


class ArmFitter:
    """Refines the arms of one body's poses against the distance maps of one level.

    ``atlas``: left-arm configurations (rows of the left arm's pose columns: the
    clavicle, shoulder, elbow and wrist rotation vectors); the right arm uses their
    mirror images. ``body``: what the arms are scored against, ``"torso"`` the leaf
    rendered without its arms (:mod:`.armless`) or ``"template"`` its template less
    the arms' capsules (see the module docstring).
    """

    def __init__(self, skeleton: Skeleton, geometry: WindowGeometry,
                 atlas: NDArray[np.float64], level: int = 1, stay: float = 1.0,
                 margin: float = 10.0, body: str = "torso") -> None:
        if body not in ARM_BODIES:
            raise ConfigError(f"the arms' body must be one of {ARM_BODIES}, got {body!r}")
        self.armless = ArmlessBody(skeleton, geometry) if body == "torso" else None
        self.skeleton = skeleton
        self.level = level
        self.stay = stay
        self.margin = margin
        self.debug: list[tuple[object, ...]] | None = None  # set to a list to record fits
        self.view = geometry.template_view(level)
        self.size = geometry.size(level)
        self.mpp = geometry.mpp(level)
        self.radii = np.array(_RADII) / self.mpp
        self.cols = tuple(np.concatenate([np.arange(3 + 3 * skeleton.node_index(n),
                                                    6 + 3 * skeleton.node_index(n))
                                          for n in LIMB_GROUPS[g]]) for g in (1, 2))
        left = np.tile(skeleton.rest_pose(), (len(atlas), 1))
        left[:, self.cols[0]] = atlas
        from bodyplay.trackers.silhouette.poses import mirror_poses

        right = mirror_poses(skeleton, left)
        self.atlas = (np.asarray(atlas, np.float64), right[:, self.cols[1]].copy())
        self.chain = tuple(tuple(NODE_NAMES.index(f"{s}_{n}") for n in
                                 ("shoulder", "elbow", "wrist")) for s in ("l", "r"))
        # the candidates' arm chains (clavicle to wrist) hang from the neck: only
        # those nodes are moved per candidate (:func:`_chain_positions`)
        self._arm_nodes = tuple(np.array([NODE_NAMES.index(f"{s}_{n}") for n in
                                          ("clavicle", "shoulder", "elbow", "wrist")], np.int64)
                                for s in ("l", "r"))
        self._arm_top = tuple(NODE_PARENTS[int(n[0])] for n in self._arm_nodes)
        self._arm_rot = tuple(np.ascontiguousarray(a[:, :9]) for a in self.atlas)
        self.joints = tuple(tuple(JOINT_INDEX[f"{s}_{n}"] for n in ("shoulder", "elbow", "wrist"))
                            for s in ("l", "r"))
        self.hand = _HAND

    def _pixels(self, chain: NDArray[np.float64], shift: tuple[float, float]
                ) -> NDArray[np.float64]:
        """Window pixels (N, 4, 2) of arm chains (N, 3, 3): shoulder, elbow, wrist, and
        the finger tips, ``hand`` metres on along the forearm."""
        fore = chain[:, 2] - chain[:, 1]
        tip = chain[:, 2] + self.hand * fore / np.maximum(
            np.linalg.norm(fore, axis=1, keepdims=True), 1e-9)
        pts = np.concatenate([chain, tip[:, None]], axis=1)
        return self.view.project(pts, distort=False) + np.asarray(shift)

    def fit(self, pose: NDArray[np.float64], origin: NDArray[np.float64],
            template: NDArray[np.uint8], cost: NDArray[np.float32],
            shift: tuple[float, float], reference: NDArray[np.float64],
            armless: NDArray[np.uint8] | None = None) -> ArmFit:
        """Refine both arms of ``pose`` (the leaf's pose vector; its template ``template``
        at this level, already moved by ``shift``, the fitted position in this
        level's pixels; ``origin`` what the template frame subtracts from world
        nodes: the pose's root less its anchor offset) against ``cost``, A of the
        observation. ``reference``: (17, 3) the joints the tracker would report
        otherwise, template frame: an atlas arm must beat them by ``margin``, paying
        ``stay`` per pixel its elbow and wrist move from them. The body without the
        arms: ``armless`` (the leaf rendered without its arms at this level, placed
        as ``template``; :class:`.armless.ArmlessBody`) when given, with the
        silhouette within :data:`MISFIT_BAND` of it credited to no arm; else the
        template less the capsules of the leaf's and the reference's arms."""
        sk = self.skeleton
        q = np.asarray(pose, np.float64).copy()
        body = (np.asarray(template if armless is None else armless) > 0).astype(np.uint8)
        frames = sk.forward(q[None])[0]
        own_nodes = frames[:, :3, 3] - origin
        refs = []
        for s in (0, 1):
            ref = np.asarray(reference)[list(self.joints[s])][None]
            own = own_nodes[list(self.chain[s][:3])][None]
            refs.append(ref)
            for chain in (own, ref) if armless is None else ():  # capsules 1 px wider
                px = self._pixels(chain, shift)
                if np.isfinite(px).all():
                    arm = np.zeros_like(body)
                    _draw(px[0], self.radii + 1.0, arm)
                    body &= 1 - arm
        replaced, gains = [False, False], [0.0, 0.0]
        cost64 = np.ascontiguousarray(cost, np.float64)
        if armless is not None:  # silhouette along the body's outline is its own misfit
            cost64 = np.where(self._misfit_band(body) & (cost64 < 0), 0.0, cost64)
        negative = np.zeros((cost64.shape[0], cost64.shape[1] + 1))
        np.cumsum(np.where(body > 0, 0.0, np.minimum(cost64, 0.0)), axis=1, out=negative[:, 1:])
        for s in (0, 1):
            nodes = np.empty((len(self.atlas[s]), 3, 3))
            _chain_positions(frames[self._arm_top[s]], self._arm_rot[s], sk.offsets,
                             self._arm_nodes[s], nodes)
            nodes -= origin
            chains = np.concatenate([refs[s], nodes])
            px = self._pixels(chains, shift)
            move = np.linalg.norm(chains[:, 1:] - chains[:1, 1:], axis=2).sum(axis=1) / self.mpp
            extra = self.stay * move
            # candidates that cannot be the cheapest are skipped (their sum: inf);
            # the reported arm first, then by their stay cost
            sums = np.empty(len(chains))
            _capsule_costs_bounded(np.ascontiguousarray(px), self.radii, cost64, body, extra,
                                   np.argsort(extra, kind="stable"), negative, sums)
            total = sums + extra
            k = int(np.argmin(total))
            gain = float(total[0] - total[k])
            if self.debug is not None:  # (arm, body mask, tree's arm px, best px, costs, move)
                self.debug.append((s, body.copy(), px[0].copy(), px[k].copy(), sums[0], sums[k],
                                   move[k]))
            if k > 0 and gain > self.margin:
                q[self.cols[s]] = self.atlas[s][k - 1]
                replaced[s] = True
                gains[s] = gain
        return ArmFit(q, (replaced[0], replaced[1]), (gains[0], gains[1]))

    def _misfit_band(self, body: NDArray[np.uint8]) -> NDArray[np.bool_]:
        """The pixels within :data:`MISFIT_BAND` of ``body`` and not on it."""
        r = max(1, int(round(MISFIT_BAND / self.mpp)))
        disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
        grown = np.asarray(cv2.dilate(body, disc), np.uint8)
        return (grown > 0) & (body == 0)

    def _at_level(self, mask: NDArray[np.uint8]) -> NDArray[np.uint8]:
        """A level-3 (320x240) window mask at this fitter's level (a 2x2 block is on
        when at least half of it is)."""
        if self.level == 2:
            return mask
        return (cv2.resize(mask.astype(np.float32), self.size, interpolation=cv2.INTER_AREA)
                >= 0.5).astype(np.uint8)

    def refine_reported(self, leaf_pose: NDArray[np.float64], leaf_offset: NDArray[np.float64],
                        placed: NDArray[np.uint8], shift: tuple[int, int],
                        cost: NDArray[np.float32], joints: NDArray[np.float64],
                        pose: NDArray[np.float64], R_align: NDArray[np.float64],
                        at: NDArray[np.float64]
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Both arms of a reported pose refined (:meth:`fit`); a replaced arm's joints
        take the place of the reported ones, hanging from the reported shoulder.

        ``leaf_pose``: the MAP leaf's pose vector (scaled to the body), ``leaf_offset``
        its anchor offset; ``placed``: its level-3 (320x240) template moved by
        ``shift``, the fitted position in level-3 pixels; ``cost``: A at this
        fitter's level; ``joints`` (17, 3) and ``pose``: what the tracker reports
        otherwise, in the world, turned from the template frame by ``R_align`` and
        standing at ``at``."""
        f = 2.0 ** (self.level - 2)
        sh = (shift[0] * f, shift[1] * f)
        origin = leaf_pose[0:3] - leaf_offset
        armless = None
        if self.armless is not None:  # rendered as the template was, placed as it is
            armless = self._at_level(shifted(self.armless.mask(leaf_pose, origin), shift))
        # fit() reads the template only without the armless body
        tmpl = self._at_level(placed) if armless is None else armless
        reference = (joints - at) @ R_align  # the reported joints, template frame
        fit = self.fit(leaf_pose, origin, tmpl, cost, sh, reference, armless)
        if not any(fit.replaced):
            return joints, pose
        J = (self.skeleton.joint_positions(fit.pose) - origin) @ R_align.T + at
        joints = joints.copy()
        pose = pose.copy()
        for s, side in enumerate("lr"):
            if fit.replaced[s]:
                top = JOINT_INDEX[f"{side}_shoulder"]
                for n in ("elbow", "wrist"):
                    j = JOINT_INDEX[f"{side}_{n}"]
                    joints[j] = joints[top] + J[j] - J[top]
                pose[self.cols[s]] = fit.pose[self.cols[s]]
        return joints, pose
