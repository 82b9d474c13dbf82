"""The cloth: a garment simulated with XPBD, pinned to and colliding with a moving body.

``Cloth(garment, options).step(dt, joints)`` advances the cloth by ``dt`` seconds
while the body moves to ``joints`` (17, 3) (NaN rows or ``None``: lost). It returns
a :class:`ClothStep` with the figures a game or a test checks. The same garment,
options and sequence of (dt, joints) always give the same cloth, bit for bit.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS
from bodyplay.cloth import kernels
from bodyplay.cloth.body import (
    CAPSULE_NAMES,
    BodyCapsules,
    body_capsules,
    body_frames,
    body_height,
)
from bodyplay.cloth.garments import Garment
from bodyplay.cloth.options import ClothOptions
from bodyplay.errors import ConfigError

__all__ = ["Cloth", "ClothStep"]

_MAX_CANDIDATES = 6
_HEIGHT_POSES = 30  # poses whose torso sizes the body (median)
_TORSO_CAPSULES = (CAPSULE_NAMES.index("torso_l"), CAPSULE_NAMES.index("torso_r"))
_LIMB_JOINTS = tuple((JOINT_INDEX[j], CAPSULE_NAMES.index(c)) for j, c in (
    ("l_elbow", "l_upper_arm"), ("l_wrist", "l_forearm"), ("r_elbow", "r_upper_arm"),
    ("r_wrist", "r_forearm"), ("l_knee", "l_thigh"), ("l_ankle", "l_shin"),
    ("r_knee", "r_thigh"), ("r_ankle", "r_shin")))
_REQUIRED = tuple(JOINT_INDEX[n] for n in ("pelvis", "neck", "l_shoulder", "r_shoulder"))


@dataclass(frozen=True)
class ClothStep:
    """What one :meth:`Cloth.step` did.

    ``t``: simulated seconds since the cloth was made; ``substeps`` run this step;
    ``dressed``: the cloth is on the body (False until the first usable pose);
    ``lost``: the pose (or some joints) was missing and held; ``teleported``: the
    body jumped and was moved rigidly with its cloth; ``max_strain`` / ``mean_strain``:
    relative stretch error |l - l0| / l0 of the stretch constraints (the constraint
    error); ``max_penetration`` / ``mean_penetration`` (m): depth of free (unpinned)
    particles inside the body capsules (their surface, not counting the thickness
    gap), over all and over the particles inside; ``penetrating``: particles more than 1 mm inside;
    ``pin_error`` (m): largest distance of a pinned particle from where the tracked
    (not speed-limited) joints put it; ``kinetic_energy``, ``potential_energy`` (J,
    height above the floor); ``seconds``: wall time of the step.
    """

    t: float
    substeps: int
    dressed: bool
    lost: bool
    teleported: bool
    max_strain: float
    mean_strain: float
    max_penetration: float
    mean_penetration: float
    penetrating: int
    pin_error: float
    kinetic_energy: float
    potential_energy: float
    seconds: float


class Cloth:
    """A garment simulated on a body driven by tracked joints (see the module doc)."""

    def __init__(self, garment: Garment, options: ClothOptions | None = None) -> None:
        if not isinstance(garment, Garment):
            raise ConfigError(f"Cloth needs a Garment (e.g. bodyplay.cloth.robe()), "
                              f"got {type(garment).__name__}")
        if options is None:
            options = ClothOptions()
        if not isinstance(options, ClothOptions):
            raise ConfigError(f"Cloth options must be ClothOptions, got {type(options).__name__}")
        self.garment = garment
        self.options = options
        rest = garment.vertices
        faces = garment.faces
        edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]),
                        axis=1)
        edges, inverse, counts = np.unique(edges, axis=0, return_inverse=True,
                                           return_counts=True)
        bend = _bend_pairs(faces, edges, inverse.reshape(-1), counts)
        ci = np.concatenate([edges[:, 0], bend[:, 0]]).astype(np.int64)
        cj = np.concatenate([edges[:, 1], bend[:, 1]]).astype(np.int64)
        kind = np.concatenate([np.zeros(len(edges), np.int64), np.ones(len(bend), np.int64)])
        colors = kernels.color_constraints(ci, cj, len(rest))
        order = np.argsort(colors, kind="stable")
        self._ci, self._cj, self._kind = ci[order], cj[order], kind[order]
        self._rest = np.linalg.norm(rest[self._ci] - rest[self._cj], axis=1)
        self._compliance = np.where(self._kind == 0, options.stretch_compliance,
                                    options.bend_compliance).astype(np.float64)
        self._cstart = np.searchsorted(colors[order], np.arange(colors.max() + 2)).astype(np.int64)
        self._stretch = self._kind == 0
        area = 0.5 * np.linalg.norm(np.cross(rest[faces[:, 1]] - rest[faces[:, 0]],
                                             rest[faces[:, 2]] - rest[faces[:, 0]]), axis=1)
        mass = np.zeros(len(rest))
        np.add.at(mass, faces.reshape(-1), np.repeat(area / 3.0, 3))
        self._mass = np.maximum(mass * options.density, 1e-6)
        self._w = 1.0 / self._mass
        self._w[garment.pins] = 0.0
        self._pins = garment.pins.astype(np.int64)
        self._ti, self._tsrc, self._tlen = _tethers(len(rest), edges, rest, self._pins,
                                                    options.tether_slack, options.tethers)
        self._pin_frames = garment.pin_frames
        self._pin_local = garment.pin_offsets()
        frames = np.bincount(garment.pin_frames, minlength=2)
        self._frame = int(np.argmax(frames)) if len(garment.pins) else 0
        self._x = rest.astype(np.float64).copy()
        self._v = np.zeros_like(self._x)
        self._xp = np.zeros_like(self._x)
        self._faces = faces.astype(np.int64)
        self._driven: NDArray[np.float64] | None = None
        self._height = options.body_height
        self._heights: list[float] = []
        self._t = 0.0
        self._solver = kernels.substeps_parallel if options.parallel else kernels.substeps_serial

    # ---- state -----------------------------------------------------------------------
    @property
    def positions(self) -> NDArray[np.float64]:
        """(N, 3) particle positions, metres (a read-only view)."""
        x = self._x.view()
        x.setflags(write=False)
        return x

    @property
    def velocities(self) -> NDArray[np.float64]:
        """(N, 3) particle velocities, m/s (a read-only view)."""
        v = self._v.view()
        v.setflags(write=False)
        return v

    @property
    def faces(self) -> NDArray[np.int64]:
        """(F, 3) triangles of the cloth mesh."""
        return self.garment.faces

    @property
    def num_particles(self) -> int:
        """Number of particles."""
        return int(len(self._x))

    @property
    def num_constraints(self) -> tuple[int, int]:
        """(stretch, bending) constraint counts."""
        s = int(self._stretch.sum())
        return s, int(len(self._stretch) - s)

    @property
    def num_colors(self) -> int:
        """Colours of the constraint graph (passes per substep)."""
        return int(len(self._cstart) - 1)

    @property
    def body_joints(self) -> NDArray[np.float64] | None:
        """(17, 3) the joints that drive the cloth now (speed-limited, lost joints held)."""
        return None if self._driven is None else self._driven.copy()

    @property
    def height(self) -> float | None:
        """Body height (m) that sizes the capsules (None before the first pose)."""
        return self._height

    def capsules(self) -> BodyCapsules | None:
        """The body's collision capsules now (their true surface), or None before dressing."""
        if self._driven is None or self._height is None:
            return None
        return body_capsules(self._driven, self._height, self.options.radius_scale)

    def normals(self) -> NDArray[np.float64]:
        """(N, 3) unit vertex normals of the cloth now."""
        return kernels.vertex_normals(self._x, self._faces)

    def energy(self) -> tuple[float, float]:
        """(kinetic, potential) energy of the free particles, joules."""
        free = self._w > 0
        m = self._mass[free]
        ke = 0.5 * float(np.sum(m * np.einsum("ij,ij->i", self._v[free], self._v[free])))
        pe = float(np.sum(m * self._x[free, 1])) * -float(self.options.gravity[1])
        return ke, pe

    # ---- stepping --------------------------------------------------------------------
    def step(self, dt: float, joints: ArrayLike | None) -> ClothStep:
        """Advance by ``dt`` seconds with the body at ``joints`` (17, 3) (None: lost).

        The first pose whose torso (pelvis, neck, shoulders) is known dresses the body
        (see ClothOptions.dress_seconds); before it the cloth does not move. Lost
        joints, glitches and jumps are handled as ClothOptions describes.
        """
        t0 = time.perf_counter()
        if not (isinstance(dt, int | float) and not isinstance(dt, bool)
                and math.isfinite(dt) and 0.0 < dt <= 0.1):
            raise ConfigError(f"cloth step dt must be a number of seconds in (0, 0.1], got {dt!r}")
        target = self._read_joints(joints)
        lost = target is None or not np.all(np.isfinite(target))
        teleported = False
        nsub = 0
        if self._driven is None:
            if target is None or not np.all(np.isfinite(target[list(_REQUIRED)])):
                return self._result(dt, 0, lost, False, None, t0)
            target = self._fill(target)
            self._measure_height(target)
            target = self._limbs_out(target)
            nsub = self._dress(dt, target)
        else:
            if target is not None and np.all(np.isfinite(target[list(_REQUIRED)])):
                self._measure_height(target)
            target = self._fill(self._driven.copy() if target is None else target)
            target = self._limbs_out(target)
            jump = float(np.linalg.norm(target[0] - self._driven[0]))
            if jump > self.options.teleport_distance:
                self._teleport(target)
                teleported = True
            delta = target - self._driven
            dist = np.linalg.norm(delta, axis=1, keepdims=True)
            limit = self.options.max_joint_speed * dt
            scale = np.minimum(1.0, limit / np.maximum(dist, 1e-12))
            limited = self._driven + delta * scale
            if np.any(scale < 1.0):
                # faster than a body moves: a tracking glitch; carry the cloth with the
                # body's frame (no velocity gained) and simulate only the limbs' motion
                self._teleport(limited)
            nsub = self._advance(dt, limited)
        self._t += dt
        return self._result(dt, nsub, lost, teleported, target, t0)

    def _read_joints(self, joints: ArrayLike | None) -> NDArray[np.float64] | None:
        if joints is None:
            return None
        try:
            j = np.array(joints, dtype=np.float64)
        except (TypeError, ValueError):
            raise ConfigError("cloth joints must be a (17, 3) array of metres (NaN = lost)"
                              ) from None
        if j.shape != (NUM_JOINTS, 3):
            raise ConfigError(f"cloth joints must have shape ({NUM_JOINTS}, 3), got {j.shape}")
        if np.any(np.isinf(j)):
            raise ConfigError("cloth joints must be finite metres (NaN = a lost joint), got inf")
        return None if np.all(np.isnan(j)) else j

    def _fill(self, j: NDArray[np.float64]) -> NDArray[np.float64]:
        """Lost joints keep their place relative to the torso (as last driven, or as in
        the rest pose before the first pose); without a torso they all hold still."""
        bad = ~np.all(np.isfinite(j), axis=1)
        if not bad.any():
            return j
        j = j.copy()
        ref = self.garment.rest_joints if self._driven is None else self._driven
        if np.all(np.isfinite(j[list(_REQUIRED)])):
            o0, r0 = body_frames(ref)
            j_torso = j.copy()
            j_torso[bad] = ref[bad]  # only the torso joints matter for the torso frame
            o1, r1 = body_frames(j_torso)
            moved = (ref - o0[0]) @ r0[0] @ r1[0].T + o1[0]
            j[bad] = moved[bad]
        else:
            j[bad] = ref[bad]
        return j

    def _limbs_out(self, j: NDArray[np.float64]) -> NDArray[np.float64]:
        """Elbows, wrists, knees and ankles a tracker put inside the torso are moved out
        until their limb capsule only touches it (ClothOptions.separate_limbs)."""
        if not self.options.separate_limbs or self._height is None:
            return j
        caps = body_capsules(j, self._height, self.options.radius_scale)
        out = j.copy()
        for joint, limb in _LIMB_JOINTS:
            p = out[joint]
            need_extra = caps.radius[limb]
            for c in _TORSO_CAPSULES:
                a, b = caps.a[c], caps.b[c]
                ab = b - a
                t = float(np.clip((p - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0))
                e = p - (a + t * ab)
                d = float(np.linalg.norm(e))
                need = float(caps.radius[c]) + need_extra
                if d < need:
                    if d < 1e-9:
                        continue
                    p = p + e * ((need - d) / d)
            out[joint] = p
        return out

    def _measure_height(self, joints: NDArray[np.float64]) -> None:
        """Body height: the median of the first poses' estimates (a tracker's first pose
        may be far off), unless ClothOptions.body_height fixes it."""
        if self.options.body_height is not None or len(self._heights) >= _HEIGHT_POSES:
            return
        self._heights.append(body_height(joints))
        self._height = float(np.median(self._heights))

    def _dress(self, dt: float, target: NDArray[np.float64]) -> int:
        """Put the garment on the body: rigidly to the target's frame, then blend the pose."""
        rest = self.garment.rest_joints
        o0, r0 = body_frames(rest)
        o1, r1 = body_frames(target)
        f = self._frame
        rot = r1[f] @ r0[f].T
        self._x = (self._x - o0[f]) @ rot.T + o1[f]
        start = (rest - o0[f]) @ rot.T + o1[f]
        self._driven = start
        n = int(math.ceil(self.options.dress_seconds / dt - 1e-9))
        nsub = 0
        for k in range(n):
            nsub += self._advance(dt, start + (target - start) * ((k + 1) / n))
        if n == 0:
            self._driven = target.copy()
            self._place_pins(target)
        return nsub

    def _teleport(self, target: NDArray[np.float64]) -> None:
        """Move the body and its cloth rigidly from the driving pose to ``target``'s frame."""
        assert self._driven is not None
        o0, r0 = body_frames(self._driven)
        o1, r1 = body_frames(target)
        f = self._frame
        rot = r1[f] @ r0[f].T
        self._x = (self._x - o0[f]) @ rot.T + o1[f]
        self._v = self._v @ rot.T
        self._driven = (self._driven - o0[f]) @ rot.T + o1[f]

    def _pin_targets(self, joints: NDArray[np.float64]) -> NDArray[np.float64]:
        origins, rots = body_frames(joints)
        f = self._pin_frames
        return origins[f] + np.einsum("pij,pj->pi", rots[f], self._pin_local)

    def _place_pins(self, joints: NDArray[np.float64]) -> None:
        self._x[self._pins] = self._pin_targets(joints)

    def _advance(self, dt: float, new: NDArray[np.float64]) -> int:
        """Simulate ``dt`` while the driving skeleton moves from its pose to ``new``."""
        assert self._driven is not None and self._height is not None
        o = self.options
        old = self._driven
        c0 = body_capsules(old, self._height, o.radius_scale)
        c1 = body_capsules(new, self._height, o.radius_scale)
        radius = c0.radius + o.thickness
        pin0 = self._pin_targets(old)
        pin1 = self._pin_targets(new)
        nsub = max(1, int(math.ceil(dt / o.substep - 1e-9)))
        h = dt / nsub
        phase = 2.0 * math.pi * o.gust_hz * self._t
        wind = np.asarray(o.wind) * (1.0 + o.gust * math.sin(phase))
        wind = wind + np.linalg.norm(o.wind) * o.gust * 0.5 * np.array(
            [math.sin(1.7 * phase), 0.0, math.cos(1.3 * phase)])
        speed = float(np.sqrt(np.max(np.einsum("ij,ij->i", self._v, self._v))))
        move = float(max(np.max(np.linalg.norm(c1.a - c0.a, axis=1)),
                         np.max(np.linalg.norm(c1.b - c0.b, axis=1))))
        margin = 0.02 + min(speed, o.max_speed) * dt + move
        cand = np.zeros((len(self._x), _MAX_CANDIDATES), dtype=np.int64)
        ncand = np.zeros(len(self._x), dtype=np.int64)
        kernels.capsule_candidates(self._x, c0.a, c0.b, c1.a, c1.b, radius, margin, cand, ncand)
        if o.self_collision:
            search = 2.0 * o.self_distance
            si, sj, sh = kernels.self_pairs(self._x, self.garment.vertices, search,
                                            o.self_distance)
        else:
            si = sj = np.zeros(0, dtype=np.int64)
            sh = np.zeros(0)
        normals = kernels.vertex_normals(self._x, self._faces)
        self._solver(self._x, self._v, self._w, self._xp, self._ci, self._cj, self._rest,
                     self._compliance, self._cstart, self._pins, pin0, pin1,
                     c0.a, c0.b, c1.a, c1.b, radius, cand, ncand, si, sj, sh,
                     self._ti, self._tsrc, self._tlen, normals,
                     np.asarray(o.gravity, dtype=np.float64), wind, o.drag, o.damping,
                     h, nsub, o.max_speed, o.friction, o.thickness)
        # overlapping capsules (an arm against the torso) can trap a particle that the
        # substeps pushed from one into the other: move it out of all of them
        kernels.resolve_union(self._x, self._w, c1.a, c1.b, radius, cand, ncand)
        self._driven = new.copy()
        return nsub

    def _result(self, dt: float, nsub: int, lost: bool, teleported: bool,
                target: NDArray[np.float64] | None, t0: float) -> ClothStep:
        dressed = self._driven is not None
        max_strain = mean_strain = max_pen = mean_pen = pin_error = 0.0
        penetrating = 0
        if dressed:
            x = self._x
            lengths = np.linalg.norm(x[self._ci[self._stretch]] - x[self._cj[self._stretch]],
                                     axis=1)
            strain = np.abs(lengths - self._rest[self._stretch]) / self._rest[self._stretch]
            max_strain, mean_strain = float(strain.max()), float(strain.mean())
            caps = self.capsules()
            assert caps is not None
            pen = kernels.penetration(x, caps.a, caps.b, caps.radius)
            pen[self._pins] = 0.0  # sewn to the body: a limb may pass through the seam
            inside = pen > 0.0
            max_pen = float(pen.max())
            mean_pen = float(pen[inside].mean()) if inside.any() else 0.0
            penetrating = int(np.count_nonzero(pen > 1e-3))
            if target is not None and len(self._pins):
                pin_error = float(np.max(np.linalg.norm(
                    x[self._pins] - self._pin_targets(target), axis=1)))
        ke, pe = self.energy()
        return ClothStep(t=self._t, substeps=nsub, dressed=dressed, lost=lost,
                         teleported=teleported, max_strain=max_strain, mean_strain=mean_strain,
                         max_penetration=max_pen, mean_penetration=mean_pen,
                         penetrating=penetrating, pin_error=pin_error, kinetic_energy=ke,
                         potential_energy=pe, seconds=time.perf_counter() - t0)


def _tethers(n: int, edges: NDArray[np.int64], rest: NDArray[np.float64],
             pins: NDArray[np.int64], slack: float, enabled: bool
             ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """Long-range attachments: each free particle, its nearest pin along the mesh, and
    that geodesic distance (times 1 + slack)."""
    empty = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))
    if not enabled or len(pins) == 0:
        return empty
    lengths = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1)
    graph = coo_matrix((lengths, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    dist, _, source = dijkstra(graph, directed=False, indices=pins, min_only=True,
                               return_predecessors=True)
    free = np.ones(n, dtype=bool)
    free[pins] = False
    free &= np.isfinite(dist) & (source >= 0)
    idx = np.flatnonzero(free).astype(np.int64)
    return idx, source[idx].astype(np.int64), dist[idx] * (1.0 + slack)


def _bend_pairs(faces: NDArray[np.int64], edges: NDArray[np.int64],
                inverse: NDArray[np.int64], counts: NDArray[np.int64]) -> NDArray[np.int64]:
    """For every edge shared by two triangles, the two vertices opposite it."""
    base = int(faces.max()) + 1
    # inverse indexes the edge of (face f, corner pair k) at k * len(faces) + f
    opposite = np.concatenate([faces[:, 2], faces[:, 0], faces[:, 1]])
    order = np.argsort(inverse, kind="stable")
    sorted_edges = inverse[order]
    starts = np.searchsorted(sorted_edges, np.flatnonzero(counts == 2))
    a = opposite[order[starts]]
    b = opposite[order[starts + 1]]
    pairs = np.sort(np.stack([a, b], axis=1), axis=1)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    if len(pairs) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    pairs = np.unique(pairs, axis=0)
    # a pair that is already an edge (a tight fold of the mesh) needs no bending constraint
    edge_keys = edges[:, 0] * base + edges[:, 1]
    keys = pairs[:, 0] * base + pairs[:, 1]
    return pairs[~np.isin(keys, edge_keys)].astype(np.int64)
