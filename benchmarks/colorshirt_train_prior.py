"""Train the color-shirt IK priors on synthetic ground truth and write the shipped asset.

Tracks synthetic renders of the built-in CMU clips (two cameras, steady light) and
fits the diagonal covariances of the IK energy (``PriorModel.fit``). The shipped
``bodyplay/assets/colorshirt/ik_prior.json`` keeps the trained articulation
stds (floored at 0.05 rad) and hand-set root and pelvis stds and centroid std:
trained as-is, the root and centroid terms let one-camera depth drift by tens of
centimetres (measured with benchmarks/colorshirt_bench.py, see docs/benchmarks.md).

    .venv/bin/python benchmarks/colorshirt_train_prior.py [--out FILE] [--raw FILE]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from bodyplay.trackers.colorshirt.training import train_prior_model

ASSET = Path(__file__).resolve().parents[1] / "sdk" / "bodyplay" / "assets" / "colorshirt"


def main() -> int:
    """Train, print the stds and write the hybrid prior."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default=str(ASSET / "ik_prior.json"))
    ap.add_argument("--raw", help="also write the fully trained prior here")
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--clips", default="13_29,131_02,131_03",
                    help="comma-separated clip names or .bvh paths to train on")
    args = ap.parse_args()
    t0 = time.perf_counter()
    pm = train_prior_model(clips=tuple(args.clips.split(",")), seconds=args.seconds)
    raw = pm.to_dict()
    print(json.dumps(raw))
    if args.raw:
        Path(args.raw).write_text(json.dumps(raw, indent=1))
    blend = [0.05] * 3 + [0.15] * 3 + [max(v, 0.05) for v in pm.blend[6:]]
    prev = [0.05] * 3 + [0.1] * 3 + [max(v, 0.05) for v in pm.previous[6:]]
    Path(args.out).write_text(json.dumps({"centroid": 0.02, "blend": blend, "previous": prev},
                                         indent=1))
    print(f"wrote {args.out} in {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
