"""One camera's root depth error, split into bias and frame-to-frame noise (jitter).

The root's depth error is the reported pelvis's depth along the camera's axis minus
the truth's (cm; positive: too far). Per clip:

* ``bias``: its mean; ``sd``: its standard deviation about that mean;
* ``jitter``: the RMS of its change from one frame to the next (consecutive frames
  with a pose), the noise a game sees as motion that did not happen;
* ``drift 0.5 s``: the RMS of its change over 15 frames (0.5 s at 30 fps), the span
  over which the gestures' ``shift_*`` features measure travel: a side step must
  not travel more than 0.35-0.5 torso lengths (17-25 cm) forwards or back in it.

Two sources:

* ``--results FILE --tag TAG``: the rows of ``colorshirt_validation.py`` (one
  camera's rows keep ``per_frame_depth``: frame, depth error, reported
  ``depth_std``, the depth filter's own estimate's error); per setting, the
  median and worst clip of each figure for the reported root and for the
  filter's estimate, and the share of frames whose error is within twice the
  reported std;
* ``--ninja DIR``: the tracked joints ``ninja_gestures.py --cache DIR`` kept, with
  the truth and the camera recomputed from each script's seed; per script, and
  the median and worst; beside the depth, the error of the shoulders' turn about
  the vertical (the facing direction the gestures' ``shift_left`` and
  ``shift_forward`` are measured along) and its RMS change over 0.5 s.

    .venv/bin/python benchmarks/colorshirt_depth_noise.py --results R.jsonl --tag T
    .venv/bin/python benchmarks/colorshirt_depth_noise.py --ninja DIR --half tune --scripts 16
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

FPS = 30
SHIFT_FRAMES = 15
"""Frames of the gestures' shift window (0.5 s) at :data:`FPS`."""


def noise(frames: NDArray[np.int64], err: NDArray[np.float64]) -> dict[str, float]:
    """Bias, sd, jitter and 0.5 s drift (cm) of depth errors ``err`` at ``frames``
    (increasing frame numbers; frames without a pose are absent or NaN)."""
    ok = np.isfinite(err)
    frames, err = frames[ok], err[ok]
    if len(err) == 0:
        return {"frames": 0, "bias": np.nan, "sd": np.nan, "jitter": np.nan, "drift": np.nan}
    full = np.full(int(frames.max()) + 1, np.nan)
    full[frames] = err
    step = np.diff(full)
    drift = full[SHIFT_FRAMES:] - full[:-SHIFT_FRAMES]
    rms = lambda d: float(np.sqrt(np.mean(d[np.isfinite(d)] ** 2))) if np.isfinite(d).any() \
        else float("nan")  # noqa: E731
    return {"frames": len(err), "bias": float(err.mean()), "sd": float(err.std()),
            "jitter": rms(step), "drift": rms(drift)}


def _table(rows: list[tuple[str, dict[str, float]]], title: str, turn: bool = False
           ) -> list[str]:
    keys = ["bias", "sd", "jitter", "drift"]
    last = "turn error (deg) | turn swing 0.5 s (deg)" if turn else "honest"
    out = [f"| {title} | frames | bias (cm) | sd (cm) | jitter (cm) | drift 0.5 s (cm) | {last} |",
           "|---|---|---|---|---|---|---|" + ("---|" if turn else "")]
    for name, n in rows:
        tail = (f"{n['turn']:.1f} | {n['swing']:.1f}" if turn
                else f"{n.get('honest', float('nan')):.2f}")
        out.append(f"| {name} | {n['frames']} | " + " | ".join(f"{n[k]:+.1f}" if k == "bias"
                                                            else f"{n[k]:.1f}" for k in keys)
                   + f" | {tail} |")
    return out


def _turn(joints: NDArray[np.float64]) -> float:
    """The shoulders' turn about the vertical (deg), as the gestures' facing reads it."""
    v = joints[5] - joints[8]  # l_shoulder - r_shoulder
    return float(np.degrees(np.arctan2(-v[2], v[0])))


def _summary(rows: list[tuple[str, dict[str, float]]]) -> str:
    """Median / worst over clips: |bias|, sd, jitter, drift, honest (worst = lowest)."""
    a = {k: np.array([n[k] for _, n in rows], np.float64)
         for k in ("bias", "sd", "jitter", "drift", "honest")}
    f = {k: (float(np.nanmedian(np.abs(v))), float(np.nanmax(np.abs(v))))
         for k, v in a.items() if np.isfinite(v).any()}
    out = (f"median / worst clip: |bias| {f['bias'][0]:.1f} / {f['bias'][1]:.1f} cm, "
           f"sd {f['sd'][0]:.1f} / {f['sd'][1]:.1f}, jitter {f['jitter'][0]:.1f} / "
           f"{f['jitter'][1]:.1f}, drift 0.5 s {f['drift'][0]:.1f} / {f['drift'][1]:.1f}")
    if "honest" in f:
        out += (f"; honest {float(np.nanmedian(a['honest'])):.2f} / "
                f"{float(np.nanmin(a['honest'])):.2f}")
    return out


def from_results(path: Path, tag: str, settings: list[str], half: str) -> list[str]:
    """The tables of one tag's one-camera rows, per setting."""
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    rows = [r for r in rows if r.get("tag") == tag and r.get("per_frame_depth")
            and (not half or r.get("half") == half)]
    if not rows:
        raise SystemExit(f"no one-camera rows with per_frame_depth for tag {tag!r} in {path} "
                         "(rows written before colorshirt_validation.py kept them have none)")
    out = []
    for setting in settings or sorted({r["setting"] for r in rows}):
        sel = sorted((r for r in rows if r["setting"] == setting), key=lambda r: r["clip"])
        if not sel:
            continue
        table, filt = [], []
        for r in sel:
            pf = np.array([[np.nan if v is None else v for v in (list(x) + [None])[:4]]
                           for x in r["per_frame_depth"]], np.float64)
            n = noise(pf[:, 0].astype(np.int64), pf[:, 1])
            n["honest"] = float(np.mean(np.abs(pf[:, 1]) < 2 * pf[:, 2])) \
                if np.isfinite(pf[:, 2]).any() else float("nan")
            table.append((r["clip"], n))
            nf = noise(pf[:, 0].astype(np.int64), pf[:, 3])
            nf["honest"] = float("nan")
            filt.append((r["clip"], nf))
        out += ["", f"{setting} (tag {tag}), reported root: {_summary(table)}"]
        if any(n["frames"] for _, n in filt):
            out += [f"{setting} (tag {tag}), depth filter's estimate: {_summary(filt)}"]
        out += [""] + _table(table, "clip")
    return out


def from_ninja(cache: Path, half: str, scripts: int, lead_in: float) -> list[str]:
    """The table of the ninja scripts' cached tracked joints (colour shirt)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bodyplay.body.actor import load_actor
    from bodyplay.synth.options import make_synthetic_camera_options
    from bodyplay.synth.rig import frame_rig, make_rig_options
    from ninja_gestures import make_script, seeds

    table = []
    for seed in seeds(half, scripts):
        tag = f"colorshirt{f'_lead{lead_in:g}' if lead_in > 0 else ''}"
        path = cache / f"{tag}_seed{seed}_{FPS}fps.npz"
        if not path.exists():
            continue
        z = np.load(path)
        script = make_script(seed)
        sk = load_actor(shape=script.body).skeleton
        tl = script.timeline
        times = np.arange(0.0, tl.duration, 1.0 / FPS)  # as ninja_gestures.frames_tracked
        frame_joints = np.stack([sk.joint_positions(tl.pose_at(float(t))) for t in times[::10]])
        o = make_synthetic_camera_options(cameras=1, fps=FPS, body=script.body, seed=seed)
        cam = frame_rig(frame_joints, make_rig_options(
            o.cameras, o.width, o.height, o.hfov_deg, o.distance, o.baseline, o.k1,
            o.seed)).cameras[0]
        err = np.full(len(z["t"]), np.nan)
        turn = np.full(len(z["t"]), np.nan)
        depth = np.zeros(len(z["t"]))
        for i, (t, j) in enumerate(zip(z["t"], z["joints"], strict=True)):
            truth = sk.joint_positions(tl.pose_at(float(t)))
            depth[i] = cam.world_to_camera(truth[0])[2]
            if np.isfinite(j[0]).all():
                err[i] = 100 * (cam.world_to_camera(j[0])[2] - depth[i])
                turn[i] = _turn(j) - _turn(truth)
        n = noise(np.arange(len(err)), err)
        n["honest"] = float("nan")
        ok = np.isfinite(turn)
        n["turn"] = float(np.mean(np.abs(turn[ok]))) if ok.any() else float("nan")
        swing = turn[SHIFT_FRAMES:] - turn[:-SHIFT_FRAMES]
        swing = swing[np.isfinite(swing)]
        n["swing"] = float(np.sqrt(np.mean(swing**2))) if len(swing) else float("nan")
        table.append((f"seed {seed} ({script.body}, {np.median(depth):.1f} m)", n))
    if not table:
        raise SystemExit(f"no cached colour-shirt scripts of the {half} half in {cache}")
    t = np.array([n["turn"] for _, n in table])
    w = np.array([n["swing"] for _, n in table])
    return [f"ninja scripts, {half} half, lead-in {lead_in:g} s: {_summary(table)}",
            f"shoulders' turn error (deg; the gestures' facing direction), median / worst "
            f"script: mean |error| {np.nanmedian(t):.1f} / {np.nanmax(t):.1f}, RMS change "
            f"over 0.5 s {np.nanmedian(w):.1f} / {np.nanmax(w):.1f}", ""] + \
        _table(table, "script", turn=True)


def main(argv: list[str] | None = None) -> int:
    """Print the tables (markdown)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", type=Path, help="colorshirt_validation.py's results (JSONL)")
    ap.add_argument("--tag", default="", help="the rows' tag (with --results)")
    ap.add_argument("--settings", default="", help="comma-separated; default: every one-camera")
    ap.add_argument("--half", default="", help="tune / report (default: any) or, with --ninja, "
                                               "tune / test (default test)")
    ap.add_argument("--ninja", type=Path, help="ninja_gestures.py's --cache directory")
    ap.add_argument("--scripts", type=int, default=12)
    ap.add_argument("--lead-in", type=float, default=0.0)
    a = ap.parse_args(argv)
    if (a.results is None) == (a.ninja is None):
        ap.error("give exactly one of --results and --ninja")
    if a.results is not None:
        if not a.tag:
            ap.error("--results needs --tag")
        lines = from_results(a.results, a.tag, [s for s in a.settings.split(",") if s], a.half)
    else:
        lines = from_ninja(a.ninja, a.half or "test", a.scripts, a.lead_in)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
