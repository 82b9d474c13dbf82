"""Train the color-shirt IK priors on synthetic ground truth and write the shipped asset.

Tracks synthetic renders of the built-in CMU clips (two cameras, steady light) and
fits the diagonal covariances of the IK energy (:func:`fit_prior_model`). The shipped
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
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.rotations import matrix_to_rotvec, rotvec_to_matrix
from bodyplay.trackers.colorshirt.ik import PriorModel, ik_dofs

ASSET = Path(__file__).resolve().parents[1] / "sdk" / "bodyplay" / "assets" / "colorshirt"


def collect_training_data(
    clips: Sequence[str] = ("13_29", "131_02"),
    seconds: float = 6.0,
    cameras: int = 2,
    database_size: int = 20_000,
    lighting: str = "steady",
    seed: int = 0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Track synthetic renders of ``clips``: truth poses, blends, estimates, centroid errors.

    Centroid errors are the distances between the truth pose's rendered patch
    centroids and the classified ones, relative to the shirt's size in the crop.
    Rows of NaN separate the clips.
    """
    from bodyplay.motion import load_clip
    from bodyplay.synth.camera import SyntheticCamera
    from bodyplay.synth.options import make_synthetic_camera_options
    from bodyplay.trackers.colorshirt import ColorShirtOptions, create_colorshirt_tracker

    truths: list[NDArray[np.float64]] = []
    blends: list[NDArray[np.float64]] = []
    ests: list[NDArray[np.float64]] = []
    cerr: list[NDArray[np.float64]] = []
    for i, name in enumerate(clips):
        clip = load_clip(name)
        opts = make_synthetic_camera_options(cameras=cameras, lighting=lighting, seed=seed + i)
        with SyntheticCamera(opts, clip) as cam:
            tracker = create_colorshirt_tracker(
                ColorShirtOptions(database_size=database_size, body="m"), cam.cameras
            )
            seq_t, seq_b, seq_e = [], [], []
            for sf in cam.from_clip(seconds=seconds):
                r = tracker.process(sf.frames)
                diag = tracker.diagnostics
                if not r.found or "q_blend" not in diag:
                    continue
                seq_t.append(sf.pose)
                seq_b.append(np.asarray(diag["q_blend"]))
                seq_e.append(np.asarray(r.pose))
                verts = tracker.renderer.vertices(sf.pose)
                for view, counts, cents in diag["observed"]:  # type: ignore[attr-defined]
                    rend = tracker.renderer.render(verts, tracker.cameras[view.index], view.window)
                    ok = (counts > 3) & (rend.stats.count > 3)
                    ok[0] = False
                    d = np.linalg.norm(rend.stats.centroid[ok] - cents[ok], axis=1)
                    cerr.append(d / max(view.shirt_scale, 1.0))
            truths.append(np.array(seq_t))
            blends.append(np.array(seq_b))
            ests.append(np.array(seq_e))
    sep = np.full((1, truths[0].shape[1]), np.nan)

    def cat(parts: list[NDArray[np.float64]]) -> NDArray[np.float64]:
        return np.concatenate([x for p in parts for x in (p, sep)])

    return cat(truths), cat(blends), cat(ests), np.concatenate(cerr)


def fit_prior_model(
    truth: NDArray[np.float64],
    blended: NDArray[np.float64],
    centroid_errors: NDArray[np.float64],
    floor: float = 0.01,
    previous: NDArray[np.float64] | None = None,
) -> PriorModel:
    """Train the covariances as the paper does, from a ground-truth sequence.

    ``truth`` and ``blended`` are (T, pose_dim) true and database-blended poses
    (rows of NaN separate sequences), ``centroid_errors`` the centroid residuals at
    the true pose (relative units). Orientation differences are measured as the
    rotation between the two pelvis orientations. ``previous`` (T, pose_dim), the
    tracker's estimates, makes the previous-pose term ``truth(t) - previous(t-1)``
    (default: the truth itself, the paper's literal recipe).
    """
    dofs = ik_dofs()

    def diff(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
        ok = np.all(np.isfinite(a), axis=1) & np.all(np.isfinite(b), axis=1)
        a, b = a[ok], b[ok]
        d = a - b
        Ra = rotvec_to_matrix(a[:, 3:6])
        Rb = rotvec_to_matrix(b[:, 3:6])
        d[:, 3:6] = matrix_to_rotvec(np.einsum("nji,njk->nik", Rb, Ra))
        return d[:, dofs]

    d_b = diff(truth, blended)
    prev = truth if previous is None else previous
    d_p = diff(truth[1:], prev[:-1])
    c = np.asarray(centroid_errors, dtype=np.float64)
    return PriorModel(
        float(max(np.sqrt(np.mean(c**2)), 1e-3)),
        tuple(float(max(v, floor)) for v in np.sqrt(np.mean(d_b**2, axis=0))),
        tuple(float(max(v, floor)) for v in np.sqrt(np.mean(d_p**2, axis=0))),
    )


def train_prior_model(**kwargs: object) -> PriorModel:
    """:func:`collect_training_data` then :func:`fit_prior_model`, the previous-pose term
    on ``truth(t) - estimate(t - 1)`` (at run time ``q_h`` is the tracker's own)."""
    truth, blend, est, cerr = collect_training_data(**kwargs)  # type: ignore[arg-type]
    return fit_prior_model(truth, blend, cerr, previous=est)


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
