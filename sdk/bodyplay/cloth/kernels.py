"""numba kernels of the cloth solver (private; :mod:`bodyplay.cloth.cloth` drives them).

XPBD with small steps (Macklin et al. 2019): every substep integrates velocities,
predicts positions, projects each distance constraint once (graph-coloured order,
so one colour's constraints touch disjoint particles and may run in parallel with
the same result), then the long-range attachments (Kim et al. 2012), the
self-collision pairs, the body capsules (with friction) and the floor, and derives
the velocities from the positions.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__: list[str] = []


@njit(cache=True)
def color_constraints(ci, cj, n):  # pragma: no cover
    """Greedy colours (< 64) such that no two constraints of a colour share a particle."""
    masks = np.zeros(n, dtype=np.uint64)
    colors = np.empty(len(ci), dtype=np.int64)
    one = np.uint64(1)
    for k in range(len(ci)):
        used = masks[ci[k]] | masks[cj[k]]
        c = 0
        while c < 63 and (used >> np.uint64(c)) & one:
            c += 1
        colors[k] = c
        bit = one << np.uint64(c)
        masks[ci[k]] |= bit
        masks[cj[k]] |= bit
    return colors


@njit(cache=True)
def vertex_normals(x, faces):  # pragma: no cover
    """Area-weighted unit vertex normals (N, 3)."""
    n = np.zeros_like(x)
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        u0 = x[b, 0] - x[a, 0]
        u1 = x[b, 1] - x[a, 1]
        u2 = x[b, 2] - x[a, 2]
        w0 = x[c, 0] - x[a, 0]
        w1 = x[c, 1] - x[a, 1]
        w2 = x[c, 2] - x[a, 2]
        cx = u1 * w2 - u2 * w1
        cy = u2 * w0 - u0 * w2
        cz = u0 * w1 - u1 * w0
        n[a, 0] += cx
        n[a, 1] += cy
        n[a, 2] += cz
        n[b, 0] += cx
        n[b, 1] += cy
        n[b, 2] += cz
        n[c, 0] += cx
        n[c, 1] += cy
        n[c, 2] += cz
    for i in range(n.shape[0]):
        length = math.sqrt(n[i, 0] ** 2 + n[i, 1] ** 2 + n[i, 2] ** 2)
        if length > 1e-12:
            n[i] /= length
    return n


@njit(cache=True, inline="always")
def _closest_t(p, a, b):  # pragma: no cover
    ab0, ab1, ab2 = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    den = ab0 * ab0 + ab1 * ab1 + ab2 * ab2
    if den < 1e-12:
        return 0.0
    t = ((p[0] - a[0]) * ab0 + (p[1] - a[1]) * ab1 + (p[2] - a[2]) * ab2) / den
    return min(max(t, 0.0), 1.0)


@njit(cache=True)
def _segment_distance(p, a, b):  # pragma: no cover
    t = _closest_t(p, a, b)
    d = 0.0
    for k in range(3):
        e = p[k] - (a[k] + t * (b[k] - a[k]))
        d += e * e
    return math.sqrt(d)


@njit(cache=True)
def capsule_candidates(x, a0, b0, a1, b1, radius, margin, cand, ncand):  # pragma: no cover
    """For each particle, the capsules (at most cand.shape[1]) it may touch this step."""
    kmax = cand.shape[1]
    nc = a0.shape[0]
    # bounding sphere of each capsule's sweep: centre and reach
    centre = np.empty((nc, 3))
    reach = np.empty(nc)
    for c in range(nc):
        r2 = 0.0
        for k in range(3):
            centre[c, k] = 0.25 * (a0[c, k] + b0[c, k] + a1[c, k] + b1[c, k])
        for pt in (a0[c], b0[c], a1[c], b1[c]):
            d2 = (pt[0] - centre[c, 0]) ** 2 + (pt[1] - centre[c, 1]) ** 2 \
                + (pt[2] - centre[c, 2]) ** 2
            r2 = max(r2, d2)
        reach[c] = math.sqrt(r2) + radius[c] + margin
    for i in range(x.shape[0]):
        m = 0
        for c in range(nc):
            d2 = (x[i, 0] - centre[c, 0]) ** 2 + (x[i, 1] - centre[c, 1]) ** 2 \
                + (x[i, 2] - centre[c, 2]) ** 2
            if d2 > reach[c] * reach[c]:
                continue
            d = min(_segment_distance(x[i], a0[c], b0[c]), _segment_distance(x[i], a1[c], b1[c]))
            if d < radius[c] + margin and m < kmax:
                cand[i, m] = c
                m += 1
        ncand[i] = m


@njit(cache=True)
def self_pairs(x, rest, search, min_dist):  # pragma: no cover
    """Particle pairs (i < j) closer than ``search`` now, with their kept distance.

    A dense grid over the cloth's bounding box (cells at least ``search`` wide, at most
    64k of them; a counting sort files the particles) finds them in deterministic
    order. Pairs already that close in the rest shape are left to the mesh's own
    constraints; the others are to be kept ``min_dist`` apart.
    """
    n = x.shape[0]
    lo = np.empty(3)
    hi = np.empty(3)
    for k in range(3):
        lo[k] = x[:, k].min()
        hi[k] = x[:, k].max()
    cell = search
    vol = (hi[0] - lo[0] + search) * (hi[1] - lo[1] + search) * (hi[2] - lo[2] + search)
    if vol / cell ** 3 > 65536.0:
        cell = (vol / 65536.0) ** (1.0 / 3.0)
    dims = np.empty(3, dtype=np.int64)
    for k in range(3):
        dims[k] = int((hi[k] - lo[k]) / cell) + 1
    ncell = dims[0] * dims[1] * dims[2]
    cells = np.empty((n, 3), dtype=np.int64)
    keys = np.empty(n, dtype=np.int64)
    for i in range(n):
        for k in range(3):
            cells[i, k] = min(int((x[i, k] - lo[k]) / cell), dims[k] - 1)
        keys[i] = (cells[i, 0] * dims[1] + cells[i, 1]) * dims[2] + cells[i, 2]
    start = np.zeros(ncell + 1, dtype=np.int64)
    for i in range(n):
        start[keys[i] + 1] += 1
    for h in range(ncell):
        start[h + 1] += start[h]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        order[fill[keys[i]]] = i
        fill[keys[i]] += 1
    cap = 16 * n
    pi = np.empty(cap, dtype=np.int64)
    pj = np.empty(cap, dtype=np.int64)
    ph = np.empty(cap, dtype=np.float64)
    count = 0
    s2 = search * search
    for i in range(n):
        for cx in range(max(cells[i, 0] - 1, 0), min(cells[i, 0] + 2, dims[0])):
            for cy in range(max(cells[i, 1] - 1, 0), min(cells[i, 1] + 2, dims[1])):
                for cz in range(max(cells[i, 2] - 1, 0), min(cells[i, 2] + 2, dims[2])):
                    h = (cx * dims[1] + cy) * dims[2] + cz
                    for idx in range(start[h], start[h + 1]):
                        j = order[idx]
                        if j <= i:
                            continue
                        d2 = (x[i, 0] - x[j, 0]) ** 2 + (x[i, 1] - x[j, 1]) ** 2 \
                            + (x[i, 2] - x[j, 2]) ** 2
                        if d2 < s2 and count < cap:
                            r2 = (rest[i, 0] - rest[j, 0]) ** 2 + (rest[i, 1] - rest[j, 1]) ** 2 \
                                + (rest[i, 2] - rest[j, 2]) ** 2
                            if r2 < s2:  # neighbours in the mesh: its constraints hold them
                                continue
                            pi[count] = i
                            pj[count] = j
                            ph[count] = min_dist
                            count += 1
    return pi[:count], pj[:count], ph[:count]


def _substeps_impl(x, v, w, xp, ci, cj, rest, compliance, cstart,
                   pins, pin0, pin1, a0, b0, a1, b1, radius, cand, ncand,
                   si, sj, sh, ti, tsrc, tlen, normals, gravity, wind, drag, damping, h, nsub,
                   max_speed, friction, floor_y):  # pragma: no cover
    n = x.shape[0]
    decay = math.exp(-damping * h)
    for s in range(nsub):
        al = (s + 1) / nsub
        # integrate: gravity, air drag along the normal (wind), damping
        for i in prange(n):
            for k in range(3):
                xp[i, k] = x[i, k]
            if w[i] > 0.0:
                vn = 0.0
                for k in range(3):
                    vn += (wind[k] - v[i, k]) * normals[i, k]
                for k in range(3):
                    v[i, k] = (v[i, k] + h * (gravity[k] + drag * vn * normals[i, k])) * decay
                    x[i, k] += h * v[i, k]
        for p in prange(pins.shape[0]):
            for k in range(3):
                x[pins[p], k] = pin0[p, k] + al * (pin1[p, k] - pin0[p, k])
        # distance constraints (stretch, bending), one colour at a time
        hh = h * h
        for c in range(cstart.shape[0] - 1):
            for q in prange(cstart[c], cstart[c + 1]):
                i = ci[q]
                j = cj[q]
                wsum = w[i] + w[j]
                if wsum == 0.0:
                    continue
                d0 = x[i, 0] - x[j, 0]
                d1 = x[i, 1] - x[j, 1]
                d2 = x[i, 2] - x[j, 2]
                length = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                if length < 1e-12:
                    continue
                dl = -(length - rest[q]) / (wsum + compliance[q] / hh) / length
                x[i, 0] += w[i] * dl * d0
                x[i, 1] += w[i] * dl * d1
                x[i, 2] += w[i] * dl * d2
                x[j, 0] -= w[j] * dl * d0
                x[j, 1] -= w[j] * dl * d1
                x[j, 2] -= w[j] * dl * d2
        # long-range attachments: no particle further from its pin than along the cloth
        for q in prange(ti.shape[0]):
            i = ti[q]
            p = tsrc[q]
            d0 = x[i, 0] - x[p, 0]
            d1 = x[i, 1] - x[p, 1]
            d2 = x[i, 2] - x[p, 2]
            length = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            if length > tlen[q]:
                f = tlen[q] / length
                x[i, 0] = x[p, 0] + d0 * f
                x[i, 1] = x[p, 1] + d1 * f
                x[i, 2] = x[p, 2] + d2 * f
        # self-collision: keep pairs apart (serial, pairs share particles)
        for q in range(si.shape[0]):
            i = si[q]
            j = sj[q]
            wsum = w[i] + w[j]
            if wsum == 0.0:
                continue
            d0 = x[i, 0] - x[j, 0]
            d1 = x[i, 1] - x[j, 1]
            d2 = x[i, 2] - x[j, 2]
            length = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            if length >= sh[q] or length < 1e-9:
                continue
            corr = (sh[q] - length) / (wsum * length)
            x[i, 0] += w[i] * corr * d0
            x[i, 1] += w[i] * corr * d1
            x[i, 2] += w[i] * corr * d2
            x[j, 0] -= w[j] * corr * d0
            x[j, 1] -= w[j] * corr * d1
            x[j, 2] -= w[j] * corr * d2
        # body capsules (moving with the substep) with friction, then the floor
        for i in prange(n):
            if w[i] == 0.0:
                continue
            for m in range(2 * ncand[i]):  # twice: a push out of one may enter another
                c = cand[i, m % ncand[i]]
                pa0 = a0[c, 0] + al * (a1[c, 0] - a0[c, 0])
                pa1 = a0[c, 1] + al * (a1[c, 1] - a0[c, 1])
                pa2 = a0[c, 2] + al * (a1[c, 2] - a0[c, 2])
                ab0 = b0[c, 0] + al * (b1[c, 0] - b0[c, 0]) - pa0
                ab1 = b0[c, 1] + al * (b1[c, 1] - b0[c, 1]) - pa1
                ab2 = b0[c, 2] + al * (b1[c, 2] - b0[c, 2]) - pa2
                den = ab0 * ab0 + ab1 * ab1 + ab2 * ab2
                t = 0.0
                if den > 1e-12:
                    t = ((x[i, 0] - pa0) * ab0 + (x[i, 1] - pa1) * ab1
                         + (x[i, 2] - pa2) * ab2) / den
                    t = min(max(t, 0.0), 1.0)
                q0 = pa0 + t * ab0
                q1 = pa1 + t * ab1
                q2 = pa2 + t * ab2
                e0 = x[i, 0] - q0
                e1 = x[i, 1] - q1
                e2 = x[i, 2] - q2
                dist = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                r = radius[c]
                if dist >= r:
                    continue
                if dist < 1e-9:  # on the axis: leave the way it came in
                    e0 = xp[i, 0] - q0
                    e1 = xp[i, 1] - q1
                    e2 = xp[i, 2] - q2
                    dist = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
                    if dist < 1e-9:
                        e0, e1, e2, dist = 0.0, 1.0, 0.0, 1.0
                n0 = e0 / dist
                n1 = e1 / dist
                n2 = e2 / dist
                push = r - dist
                x[i, 0] += n0 * push
                x[i, 1] += n1 * push
                x[i, 2] += n2 * push
                # friction: remove part of the sliding relative to the moving surface
                g0 = (1.0 - t) * (a1[c, 0] - a0[c, 0]) + t * (b1[c, 0] - b0[c, 0])
                g1 = (1.0 - t) * (a1[c, 1] - a0[c, 1]) + t * (b1[c, 1] - b0[c, 1])
                g2 = (1.0 - t) * (a1[c, 2] - a0[c, 2]) + t * (b1[c, 2] - b0[c, 2])
                inv = 1.0 / nsub
                r0 = x[i, 0] - xp[i, 0] - g0 * inv
                r1 = x[i, 1] - xp[i, 1] - g1 * inv
                r2 = x[i, 2] - xp[i, 2] - g2 * inv
                rn = r0 * n0 + r1 * n1 + r2 * n2
                x[i, 0] -= friction * (r0 - rn * n0)
                x[i, 1] -= friction * (r1 - rn * n1)
                x[i, 2] -= friction * (r2 - rn * n2)
            if x[i, 1] < floor_y:
                x[i, 1] = floor_y
        # velocities from positions, capped
        for i in prange(n):
            sp = 0.0
            for k in range(3):
                v[i, k] = (x[i, k] - xp[i, k]) / h
                sp += v[i, k] * v[i, k]
            sp = math.sqrt(sp)
            if sp > max_speed:
                for k in range(3):
                    v[i, k] *= max_speed / sp


substeps_serial = njit(cache=True)(_substeps_impl)
substeps_parallel = njit(cache=True, parallel=True)(_substeps_impl)


@njit(cache=True)
def penetration(x, a, b, radius):  # pragma: no cover
    """(N,) depth of each point inside the deepest capsule (0 outside)."""
    out = np.zeros(x.shape[0])
    for i in range(x.shape[0]):
        for c in range(a.shape[0]):
            d = radius[c] - _segment_distance(x[i], a[c], b[c])
            if d > out[i]:
                out[i] = d
    return out


@njit(cache=True)
def _depth_and_exit(p, a, b, r, out):  # pragma: no cover
    """Depth of ``p`` inside capsule (a, b, r) (<= 0 outside) and its exit point in ``out``."""
    t = _closest_t(p, a, b)
    e0 = p[0] - (a[0] + t * (b[0] - a[0]))
    e1 = p[1] - (a[1] + t * (b[1] - a[1]))
    e2 = p[2] - (a[2] + t * (b[2] - a[2]))
    d = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    if d < 1e-9:
        e0, e1, e2, d = 0.0, 1.0, 0.0, 1.0
    f = r / d
    out[0] = a[0] + t * (b[0] - a[0]) + e0 * f
    out[1] = a[1] + t * (b[1] - a[1]) + e1 * f
    out[2] = a[2] + t * (b[2] - a[2]) + e2 * f
    return r - d


_CREASE = 1e-3  # m: a capsule whose surface is this near counts as touching
_MAX_EXIT = 0.05  # m: the longest move out of a crease


@njit(cache=True)
def resolve_union(x, w, a, b, radius, cand, ncand):  # pragma: no cover
    """Move free particles left inside overlapping capsules out of all of them.

    For a particle inside one or more candidate capsules, each capsule's exit point is
    tried; the nearest one outside every candidate wins (else the one least deep), up
    to three times. A particle still inside (pinched in the crease where an arm
    presses on the torso: each capsule's exit lies inside the other) leaves along the
    shortest of the rays out of each capsule and out of their crease
    (:func:`_union_exit`). Only positions change (a projection, no velocity).
    """
    trial = np.empty(3)
    best = np.empty(3)
    for i in range(x.shape[0]):
        if w[i] == 0.0 or ncand[i] == 0:
            continue
        for _ in range(3):
            inside = False
            for m in range(ncand[i]):
                c = cand[i, m]
                if radius[c] - _segment_distance(x[i], a[c], b[c]) > 1e-6:
                    inside = True
                    break
            if not inside:
                break
            best_cost = 1e30
            for m in range(ncand[i]):
                c = cand[i, m]
                if _depth_and_exit(x[i], a[c], b[c], radius[c], trial) <= 0.0:
                    continue
                worst = 0.0
                for m2 in range(ncand[i]):
                    c2 = cand[i, m2]
                    worst = max(worst, radius[c2] - _segment_distance(trial, a[c2], b[c2]))
                move = math.sqrt((trial[0] - x[i, 0]) ** 2 + (trial[1] - x[i, 1]) ** 2
                                 + (trial[2] - x[i, 2]) ** 2)
                cost = move + 100.0 * worst
                if cost < best_cost:
                    best_cost = cost
                    best[0], best[1], best[2] = trial[0], trial[1], trial[2]
            x[i, 0], x[i, 1], x[i, 2] = best[0], best[1], best[2]
        if _union_depth(x[i], a, b, radius, cand[i], ncand[i]) > 1e-6:
            _union_exit(x[i], a, b, radius, cand[i], ncand[i])


@njit(cache=True)
def _union_depth(p, a, b, radius, cand, n):  # pragma: no cover
    """Depth of ``p`` inside the union of the capsules ``cand[:n]`` (<= 0 outside)."""
    depth = -1e30
    for m in range(n):
        c = cand[m]
        depth = max(depth, radius[c] - _segment_distance(p, a[c], b[c]))
    return depth


@njit(cache=True)
def _union_exit(p, a, b, radius, cand, n):  # pragma: no cover
    """Move ``p`` out of the union of the capsules ``cand[:n]`` along the shortest ray.

    The rays tried are the outward normals at ``p`` of the capsules it is inside or
    on (within ``_CREASE``), and the sums of two of them and of all: where an arm
    presses on the torso each normal points into the other capsule, and their sum
    runs out along the crease. Along a ray the point steps by the union's depth until
    it is outside (the distance to a capsule changes by at most the step). The
    shortest way out within ``_MAX_EXIT`` wins; ``p`` is left unchanged if none is.
    """
    normals = np.zeros((n, 3))
    near = np.zeros(n, dtype=np.bool_)
    out = np.empty(3)
    for m in range(n):
        c = cand[m]
        if _depth_and_exit(p, a[c], b[c], radius[c], out) < -_CREASE:
            continue
        length = math.sqrt((out[0] - p[0]) ** 2 + (out[1] - p[1]) ** 2 + (out[2] - p[2]) ** 2)
        if length < 1e-12:  # on the surface: the normal from the axis
            t = _closest_t(p, a[c], b[c])
            for k in range(3):
                out[k] = p[k] + (p[k] - (a[c, k] + t * (b[c, k] - a[c, k])))
            length = math.sqrt((out[0] - p[0]) ** 2 + (out[1] - p[1]) ** 2
                               + (out[2] - p[2]) ** 2)
            if length < 1e-12:
                continue
        near[m] = True
        for k in range(3):
            normals[m, k] = (out[k] - p[k]) / length
    rays = np.zeros((n + n * n + 1, 3))
    count = 0
    for m in range(n):
        if not near[m]:
            continue
        rays[count] = normals[m]
        rays[n + n * n] += normals[m]
        count += 1
        for m2 in range(m + 1, n):
            if near[m2]:
                rays[count] = normals[m] + normals[m2]
                count += 1
    rays[count] = rays[n + n * n]
    count += 1
    best_move = _MAX_EXIT
    best = np.empty(3)
    q = np.empty(3)
    found = False
    for r in range(count):
        length = math.sqrt(rays[r, 0] ** 2 + rays[r, 1] ** 2 + rays[r, 2] ** 2)
        if length < 1e-9:
            continue
        s = 0.0
        while s < best_move:
            for k in range(3):
                q[k] = p[k] + s * rays[r, k] / length
            depth = _union_depth(q, a, b, radius, cand, n)
            if depth <= 1e-6:
                best_move = s
                best[0], best[1], best[2] = q[0], q[1], q[2]
                found = True
                break
            s += depth + 1e-6
    if found:
        p[0], p[1], p[2] = best[0], best[1], best[2]
