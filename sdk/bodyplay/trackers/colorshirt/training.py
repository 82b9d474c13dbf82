"""Training the IK priors (:class:`PriorModel`) on synthetic ground truth, as the paper
trains them on Vicon data."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from bodyplay.trackers.colorshirt.ik import PriorModel

__all__ = ["collect_training_data", "train_prior_model"]


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


def train_prior_model(**kwargs: object) -> PriorModel:
    """:func:`collect_training_data` then :meth:`PriorModel.fit`, the previous-pose term
    on ``truth(t) - estimate(t - 1)`` (at run time ``q_h`` is the tracker's own)."""
    truth, blend, est, cerr = collect_training_data(**kwargs)  # type: ignore[arg-type]
    return PriorModel.fit(truth, blend, cerr, previous=est)
