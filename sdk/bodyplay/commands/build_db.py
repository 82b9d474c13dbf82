"""``bodyplay build-db``: render and cache a tracker's pose database.

``--tracker colorshirt`` (default):
Samples upper-body poses (the built-in CMU clips, random configurations and
blends, facing the camera within +-80 degrees, ``--yaw`` for another range: the
tracker's ``database_yaw``), renders each as a 40x40 color id
map of the generic body mesh and caches the result under ``--cache`` (default
``~/.cache/bodyplay``), keyed by a hash of everything that shapes it. The tracker
builds it on first use anyway; this command does it ahead of time.

``--tracker silhouette``: the shape hierarchy of the silhouette tracker (poses of
the vendored CMU clips, or ``--clips`` BVH files, thinned by the 5-degree rule;
Algorithm 1 in three levels; templates for every body preset), cached the same way.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

__all__ = ["register", "run"]


def register(subparsers: Any) -> None:
    """Add the ``build-db`` sub-command."""
    p = subparsers.add_parser(
        "build-db", help="render and cache the color-shirt pose database", description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--tracker", default="colorshirt", choices=("colorshirt", "silhouette"))
    p.add_argument("--clips", nargs="+", metavar="BVH",
                   help="silhouette: motion clips to build from (default the vendored CMU clips)")
    p.add_argument("--size", type=int, default=20_000, help="poses (paper: 80000)")
    p.add_argument("--cache", help="cache folder (default ~/.cache/bodyplay)")
    p.add_argument("--body", default="m", help="body preset of the generic skeleton")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--yaw", type=float, default=80.0,
                   help="colorshirt: degrees the poses turn from facing the camera "
                        "(the tracker's database_yaw; 180: every way round)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Build (or find) the database and report its size and the time taken."""
    if args.tracker == "silhouette":
        return _run_silhouette(args)
    from bodyplay.body.skeleton import Skeleton
    from bodyplay.trackers.colorshirt.database import DatabaseOptions, load_or_build_database

    t0 = time.perf_counter()
    db = load_or_build_database(
        Skeleton.from_shape(args.body),
        DatabaseOptions(size=args.size, seed=args.seed, yaw_deg=args.yaw),
        Path(args.cache) if args.cache else None, progress=True,
    )
    print(f"pose database: {len(db)} poses of {db.options.map_size}x{db.options.map_size} "
          f"id maps, ready in {time.perf_counter() - t0:.1f} s")
    return 0


def _run_silhouette(args: argparse.Namespace) -> int:
    from bodyplay.trackers.silhouette import HierarchyOptions, load_or_build_tree

    t0 = time.perf_counter()
    opts = HierarchyOptions(clips=tuple(args.clips or ()), seed=args.seed)
    tree = load_or_build_tree(opts, Path(args.cache) if args.cache else None, progress=True)
    sizes = " / ".join(str(s) for s in tree.level_sizes)
    print(f"silhouette hierarchy: {len(tree.poses)} poses (from {tree.frames} frames, "
          f"{tree.dedup_deg:.1f}-degree rule), {sizes} nodes at levels 1/2/3, "
          f"{len(tree.bodies)} bodies, {tree.nbytes / 1e6:.1f} MB; built in "
          f"{tree.build_seconds:.0f} s, ready in {time.perf_counter() - t0:.1f} s")
    return 0
