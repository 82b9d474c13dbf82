"""Tree-based Bayesian filtering over the shape hierarchy (paper section 2, eq. 1-5, 13-14).

The state is the leaf partition of the hierarchy: the posterior is a discrete
distribution over leaves, piecewise constant inside each (eq. 3-4).

Prediction (eq. 2, 5): the prior of a leaf mixes

* the transition histogram of the training motion (leaf to leaf, eq. 5),
* the first-order Gaussian model (eq. 13) around the likely previous leaves, on
  the body parts' positions with each part's standard deviation from the training
  motion, multiplied by m (eq. 14, m = 5) for parts the previous leaf's template
  shows occluded (no pixel assigned to them), so an occluded limb can be found
  anywhere when it reappears,
* a small uniform share over all leaves (recovery after a failure; the start),
* optionally (``fit_prior``, an addition to the paper) a share given, once the
  finest level is scored, to the scored leaves in proportion to their likelihood
  (an observation-driven proposal: a pose the prediction cannot reach wins when
  it fits clearly better).

Update (eq. 1) coarse to fine: every level-1 node is scored against the observed
silhouette at 80x60, at every position of a small grid around the floor point
(``shift_search``, the paper's global position in the state; each node keeps its
best), its children at twice that shift and one pixel around it; only the
children of nodes whose posterior is at least ``keep`` times the best (at most
``max_expand`` of them), plus the ``explore`` best-fitting ones whatever their
prior (so that a posterior stuck on a wrong pose can let go), are scored at the
next level, and so on; leaves of
pruned subtrees keep the likelihood of their deepest scored ancestor (piecewise
constant, as the paper's "the subtree of that node is not searched"). The
likelihood is eq. 6, exp(-d^2 / 2 sigma_l^2), with sigma_l a multiple of the
level's clustering threshold, taken relative to the best node of the level so that
levels of different resolution combine.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix

from bodyplay.trackers.silhouette.distance import DistanceMaps, score_runs_shifted
from bodyplay.trackers.silhouette.hierarchy import BodyTemplates, ShapeTree
from bodyplay.trackers.silhouette.options import SilhouetteOptions

__all__ = ["TreeFilter", "FilterStep"]


@dataclass(frozen=True, eq=False)
class FilterStep:
    """One filter update: the MAP leaf, its distance, the posterior's best leaves
    and how many distances each level evaluated; ``shift`` is where the MAP leaf's
    template fits best, in level-3 pixels (x right, y down)."""

    leaf: int
    distance: float
    top: NDArray[np.int64]
    weights: NDArray[np.float64]
    evaluations: tuple[int, int, int]
    shift: tuple[int, int] = (0, 0)


class TreeFilter:
    """The filter of one body's templates over a :class:`ShapeTree`."""

    def __init__(self, tree: ShapeTree, body: BodyTemplates, options: SilhouetteOptions) -> None:
        self.tree = tree
        self.body = body
        self.options = options
        n = tree.num_leaves
        rows = np.concatenate([tree.trans_src, np.arange(n)])
        cols = np.concatenate([tree.trans_dst, np.arange(n)])
        vals = np.concatenate([tree.trans_count, np.full(n, 0.5)])
        T = csr_matrix((vals, (rows, cols)), shape=(n, n))
        norm = np.asarray(T.sum(axis=1)).ravel()
        self._trans = csr_matrix(T.multiply(1.0 / norm[:, None]))
        if options.transition_frames > 1:  # the 1..n-frame transitions, averaged
            one, step, total = self._trans, self._trans, self._trans
            for _ in range(options.transition_frames - 1):
                step = csr_matrix(step @ one)
                total = total + step
            self._trans = csr_matrix(total / options.transition_frames)
        # the start: facing the camera is likelier (the paper's initialization pose)
        lh, rh = tree.leaf_joints[:, 11], tree.leaf_joints[:, 14]
        across = lh - rh
        yaw_cos = np.clip(across[:, 0] / np.maximum(np.linalg.norm(across[:, [0, 2]], axis=1),
                                                     1e-9), -1.0, 1.0)
        init = np.exp(1.0 * yaw_cos)
        self._init = init / init.sum()
        self.posterior: NDArray[np.float64] | None = None
        r = options.shift_search
        self._grid0 = np.array([(x, y) for y in range(-r[1], r[1] + 1)
                                for x in range(-r[0], r[0] + 1)], np.int64)
        self._grid = np.array([(x, 0) for x in (-1, 0, 1)] + ([(0, -1), (0, 1)] if r[1] else []),
                              np.int64)

    def reset(self) -> None:
        """Forget the posterior (the next step starts from the initial prior)."""
        self.posterior = None

    # ---- prediction -----------------------------------------------------------------
    def predict(self) -> NDArray[np.float64]:
        """The prior over leaves for the next frame (eq. 2, 5, 13, 14)."""
        o = self.options
        if self.posterior is None:
            return self._init.copy()
        p = self.posterior
        order = np.argsort(p)[::-1]
        csum = np.cumsum(p[order])
        k = min(32, int(np.searchsorted(csum, 0.99)) + 1)
        top = order[:k]
        w = p[top] / p[top].sum()
        hist = np.asarray(self._trans[top].T @ w).ravel()
        f = self.tree.part_features
        sig = self.tree.part_sigma[None, :] * 2.0 * np.where(
            self.tree.occluded[top], o.occlusion_m, 1.0)  # (k, parts)
        gauss = np.zeros(len(p))
        for i, leaf in enumerate(top):
            d2 = np.sum((f - f[leaf]) ** 2, axis=-1) / sig[i] ** 2  # (leaves, parts)
            g = np.exp(-0.5 * d2.sum(axis=1))
            gauss += w[i] * g / g.sum()
        lam = o.transition_weight
        prior = (1.0 - o.uniform) * (lam * hist + (1.0 - lam) * gauss) + o.uniform * self._init
        return prior / prior.sum()

    # ---- update -----------------------------------------------------------------------
    def step(self, maps: tuple[DistanceMaps, DistanceMaps, DistanceMaps]) -> FilterStep:
        """Predict, then update coarse to fine with the observed silhouette's maps."""
        o = self.options
        tree = self.tree
        prior = self.predict()
        anc = tree.leaf_ancestor
        n_leaf = tree.num_leaves
        loglik = np.zeros(n_leaf)
        evals = []
        expand: NDArray[np.int64] = np.arange(len(tree.node_pose[0]), dtype=np.int64)
        base = np.zeros((len(expand), 2), np.int64)
        best_leaf, best_d, best_shift = -1, np.inf, (0, 0)
        for lv in range(3):
            grid = self._grid0 if lv == 0 else self._grid
            ns = len(grid)
            cand = np.repeat(expand, ns)
            sh = np.repeat(base, ns, axis=0) + np.tile(grid, (len(expand), 1))
            dd = score_runs_shifted(maps[lv], self.body.runs[lv], cand, sh[:, 0], sh[:, 1])
            dd = dd.reshape(len(expand), ns)
            pick = np.argmin(dd, axis=1)
            d = dd[np.arange(len(expand)), pick]
            shift = sh.reshape(len(expand), ns, 2)[np.arange(len(expand)), pick]
            evals.append(len(cand))
            sig = o.sigma * tree.options.thresholds[lv]
            ll = -0.5 * (d / sig) ** 2
            ll -= ll.max()
            node_ll = np.full(len(tree.node_pose[lv]), np.nan)
            node_ll[expand] = ll
            # leaves under a scored node take its likelihood (deeper levels overwrite)
            under = node_ll[anc[lv]]
            scored = np.isfinite(under)
            if lv == 0:
                loglik = under.copy()
            else:
                loglik[scored] = under[scored]
            if lv == 2 and o.fit_prior > 0:  # the observation-driven share of the prior
                fit = np.exp(ll)
                seen = np.zeros(n_leaf)
                seen[expand] = fit / fit.sum()
                prior = (1.0 - o.fit_prior) * prior + o.fit_prior * seen
            node_prior = np.bincount(anc[lv], weights=prior, minlength=len(tree.node_pose[lv]))
            post = np.log(np.maximum(node_prior[expand], 1e-300)) + ll
            if lv == 2:
                i = int(np.argmax(post))
                best_leaf, best_d = int(expand[i]), float(d[i])
                best_shift = (int(shift[i, 0]), int(shift[i, 1]))
                break
            keep = post >= post.max() + np.log(o.keep)
            chosen = expand[keep]
            if keep.sum() > o.max_expand[lv]:
                chosen = expand[np.argsort(post)[::-1][: o.max_expand[lv]]]
            # the best-fitting nodes are searched whatever their prior, so that a
            # posterior stuck on a wrong pose can let go (recovery)
            fit = expand[np.argsort(d)[: o.explore]]
            chosen = np.concatenate([chosen, fit[~np.isin(fit, chosen)]])
            start, end = tree.children[lv]
            where = {int(n): k for k, n in enumerate(expand)}
            kids = [np.arange(start[c], end[c]) for c in chosen]
            base = 2 * np.concatenate([np.repeat(shift[where[int(c)]][None], len(k), axis=0)
                                       for c, k in zip(chosen, kids, strict=True)])
            expand = np.concatenate(kids).astype(np.int64)
        logpost = np.log(np.maximum(prior, 1e-300)) + loglik
        logpost -= logpost.max()
        post = np.exp(logpost)
        post /= post.sum()
        self.posterior = post
        top = np.argsort(post)[::-1][:5]
        return FilterStep(best_leaf, best_d, top, post[top], (evals[0], evals[1], evals[2]),
                          best_shift)
