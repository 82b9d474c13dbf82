"""Pose-database figures: build time, and nearest-neighbour search speed and recall.

Builds (into a temporary cache, so the time is a real build) a database of --size
poses, then queries it with maps of poses rendered from a different seed:
exhaustive per-pixel mismatch (the paper's distance), the tracker's search
(pooled one-hot features on principal components, matrix-vector ranking, exact
re-ranking of the best candidates), and a scipy cKDTree over the same features
followed by the same re-ranking. Recall@10 is measured against the exhaustive
search. Prints medians, the machine and the date.

    .venv/bin/python benchmarks/colorshirt_db_bench.py --size 20000
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from bodyplay.body.skeleton import Skeleton
from bodyplay.trackers.colorshirt.database import (
    DatabaseOptions,
    build_database,
    mismatch,
    sample_database_poses,
)


def main() -> int:
    """Run and print the figures."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--size", type=int, default=20_000)
    ap.add_argument("--queries", type=int, default=100)
    args = ap.parse_args()
    sk = Skeleton()
    opts = DatabaseOptions(size=args.size)
    print(f"# colorshirt database benchmark, {datetime.datetime.now():%Y-%m-%d %H:%M}, "
          f"{platform.machine()}, {os.cpu_count()} cpus, load {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        rng = np.random.default_rng(opts.seed)
        poses = sample_database_poses(sk, opts.size, rng, opts)
        t1 = time.perf_counter()
        db = build_database(sk, opts, poses)
        t2 = time.perf_counter()
        db.save(Path(tmp) / "db.npz")
        t3 = time.perf_counter()
    print(f"{args.size} poses: sampling {t1 - t0:.1f} s, rendering + features {t2 - t1:.1f} s "
          f"({args.size / (t2 - t1):.0f} poses/s), saving {t3 - t2:.1f} s")
    qopts = DatabaseOptions(size=args.queries, seed=99)
    qs = build_database(sk, qopts, sample_database_poses(sk, args.queries,
                                                          np.random.default_rng(99), qopts)).ids
    tree = cKDTree(db.features)
    t_fast, t_exact, t_tree, rec_fast, rec_tree = [], [], [], [], []
    for q in qs:
        a = time.perf_counter()
        fast = db.query(q)
        b = time.perf_counter()
        exact = db.query(q, exact=True)
        c = time.perf_counter()
        _, cand = tree.query(db.query_features(q), k=opts.candidates)
        mis = mismatch(db.ids[cand], q[None])
        via_tree = cand[np.argsort(mis, kind="stable")[: opts.neighbours]]
        d = time.perf_counter()
        t_fast.append(b - a)
        t_exact.append(c - b)
        t_tree.append(d - c)
        ex = set(exact.index.tolist())
        rec_fast.append(len(ex & set(fast.index.tolist())) / len(ex))
        rec_tree.append(len(ex & set(via_tree.tolist())) / len(ex))
    ms = lambda v: 1000 * float(np.median(v))  # noqa: E731
    print(f"query, PCA ranking + exact re-rank: {ms(t_fast):.2f} ms, recall@10 "
          f"{np.mean(rec_fast):.3f}")
    print(f"query, cKDTree on the same features + re-rank: {ms(t_tree):.2f} ms, recall@10 "
          f"{np.mean(rec_tree):.3f}")
    print(f"query, exhaustive mismatch: {ms(t_exact):.2f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
