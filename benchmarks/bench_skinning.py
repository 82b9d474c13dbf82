"""Skinning speed: forward kinematics + linear blend skinning per pose, for the generic
tracker mesh and the actor, in batches as used when building pose databases; and
``Skeleton.forward`` alone for batches of 1, 100 and 10000 poses (single poses dominate
live tracking and IK, large batches database builds).

Run: ``.venv/bin/python benchmarks/bench_skinning.py`` (prints medians, machine, date).
"""

from __future__ import annotations

import datetime
import time
from collections.abc import Callable

import numpy as np

from _machine import machine
from bodyplay.body import Skeleton, body_mesh, load_actor


def _poses(skeleton: Skeleton, n: int) -> np.ndarray:
    rng = np.random.default_rng(0)
    lo, hi = skeleton.limits
    q = np.tile(skeleton.rest_pose(), (n, 1))
    q[:, 3:] = rng.uniform(np.maximum(lo[3:], -1.0), np.minimum(hi[3:], 1.0), (n, q.shape[1] - 3))
    return q


def _median_seconds(fn: Callable[[], object], repeats: int) -> float:
    """Median wall time of ``fn()`` over ``repeats`` calls, after one warm-up call."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def forward_table() -> None:
    """Print the median time of one ``Skeleton.forward`` call per batch size."""
    sk = Skeleton()
    for batch, repeats in ((1, 2000), (100, 500), (10000, 15)):
        q = _poses(sk, batch)
        arg = q[0] if batch == 1 else q
        t = _median_seconds(lambda arg=arg: sk.forward(arg), repeats)
        print(f"Skeleton.forward batch={batch:5d}: {1e3 * t:8.4f} ms/call "
              f"({1e6 * t / batch:8.3f} us/pose), median of {repeats}")


def main() -> None:
    """Print the median time per pose over several repeats."""
    print(f"machine: {machine()}; date: {datetime.date.today().isoformat()}")
    forward_table()
    generic_skel = Skeleton()
    actor = load_actor("m")
    for name, mesh, skel in (("generic", body_mesh(generic_skel), generic_skel),
                             ("actor", actor.mesh, actor.skeleton)):
        for batch in (1, 2000):
            q = _poses(skel, batch)
            mesh.pose(skel, q[:2])  # compile
            fk, total = [], []
            for _ in range(7):
                t0 = time.perf_counter()
                skel.forward(q)
                t1 = time.perf_counter()
                mesh.pose(skel, q)
                t2 = time.perf_counter()
                fk.append((t1 - t0) / batch)
                total.append((t2 - t1) / batch)
            print(f"{name:8s} V={mesh.num_vertices:6d} F={mesh.num_faces:6d} batch={batch:5d}: "
                  f"FK+skinning {1e3 * np.median(total):.4f} ms/pose "
                  f"(FK alone {1e3 * np.median(fk):.4f} ms/pose)")


if __name__ == "__main__":
    main()
