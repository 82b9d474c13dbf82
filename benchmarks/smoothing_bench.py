"""Smoothing benchmark: jitter reduction, added lag and error of the joint filters.

By default takes real motion-capture clips (CMU from ../shared/data/mocap/cmu and a
few Bandai Namco clips read from ../shared), retargeted to the reference skeleton at
30 fps, and adds tracker-like noise: Gaussian jitter of ``--noise-cm`` per
coordinate plus, with probability ``--outlier-rate`` per joint and frame, an
outlier displaced by 15-30 cm. With ``--poses P --truth T`` it instead reads a
tracker's ``poses.jsonl`` and the matching ``truth.jsonl`` (DESIGN.md formats).

For raw input, One Euro (three settings) and Kalman CV/CA it prints, as medians
over clips:
  jitter   mean acceleration magnitude (m/s^2, second differences) and its
           reduction relative to the raw input;
  lag      added delay in ms: the shift that maximizes the cross-correlation of the
           filtered joint velocities with the true ones (wrists, elbows, ankles,
           knees, head), refined to sub-frame by a parabola;
  MPJPE    mean per-joint position error against the truth, mm;
  ms/frame filter time per frame.

    .venv/bin/python benchmarks/smoothing_bench.py [--seed 0] [--write-docs]
"""

from __future__ import annotations

import argparse
import datetime
import json
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from _machine import machine
from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES
from bodyplay.filters import JointFilter, kalman_filter, one_euro_filter

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
CLIPS = (
    "mocap/cmu/13_29.bvh",
    "mocap/cmu/131_01.bvh",
    "mocap/cmu/131_03.bvh",
    "mocap/bandai_namco/dataset-1_slash_normal_001.bvh",
    "mocap/bandai_namco/dataset-1_punch_normal_002.bvh",
    "mocap/bandai_namco/dataset-1_kick_normal_001.bvh",
)
MOVING = [JOINT_INDEX[n] for n in ("head", "l_elbow", "l_wrist", "r_elbow", "r_wrist",
                                   "l_knee", "l_ankle", "r_knee", "r_ankle")]

FILTERS: dict[str, Callable[[], JointFilter]] = {
    "One Euro (min_cutoff 0.5, beta 1)": lambda: one_euro_filter(min_cutoff=0.5, beta=1.0),
    "One Euro (default: 1.0, 2)": lambda: one_euro_filter(),
    "One Euro (2.0, 4)": lambda: one_euro_filter(min_cutoff=2.0, beta=4.0),
    "Kalman CV (default)": lambda: kalman_filter(model="cv"),
    "Kalman CA (default)": lambda: kalman_filter(model="ca"),
    "Kalman CV, filterpy backend": lambda: kalman_filter(model="cv", backend="filterpy"),
}

Sequence = tuple[str, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], list | None]


def add_noise(truth: NDArray[np.float64], rng: np.random.Generator, noise_cm: float,
              outlier_rate: float) -> NDArray[np.float64]:
    """Tracker-like noise: Gaussian jitter plus occasional 15-30 cm outliers."""
    noisy = truth + rng.normal(0.0, noise_cm / 100.0, truth.shape)
    mask = rng.random(truth.shape[:2]) < outlier_rate
    d = rng.normal(size=(int(mask.sum()), 3))
    d *= (rng.uniform(0.15, 0.30, len(d)) / np.linalg.norm(d, axis=1))[:, None]
    noisy[mask] += d
    return noisy


def read_jsonl(path: Path) -> tuple[NDArray[np.float64], NDArray[np.float64], list]:
    """Frames, joints (T, 17, 3) NaN where null, and per-frame state tuples."""
    times, joints, states = [], [], []
    for line in path.read_text().splitlines():
        if not line.strip():
            continue
        rec = json.loads(line)
        times.append(rec["t"])
        j = np.full((17, 3), np.nan)
        for i, n in enumerate(JOINT_NAMES):
            v = rec["joints"].get(n)
            if v is not None:
                j[i] = v
        joints.append(j)
        st = rec.get("state")
        states.append(tuple(st.get(n, "tracked") for n in JOINT_NAMES) if st else None)
    return np.asarray(times), np.asarray(joints), states


def load_sequences(args: argparse.Namespace) -> list[Sequence]:
    """(name, times, truth, measured, states) for every input."""
    if args.poses:
        t, meas, states = read_jsonl(Path(args.poses))
        _, truth, _ = read_jsonl(Path(args.truth))
        return [(Path(args.poses).parent.name, t, truth[: len(t)], meas, states)]
    from bodyplay.motion.clip import load_clip

    rng = np.random.default_rng(args.seed)
    out: list[Sequence] = []
    for rel in CLIPS:
        clip = load_clip(DATA / rel, fps=30)
        truth = clip.joints()
        out.append((Path(rel).stem, clip.times, truth,
                    add_noise(truth, rng, args.noise_cm, args.outlier_rate), None))
    return out


def jitter(x: NDArray[np.float64], t: NDArray[np.float64]) -> float:
    """Mean acceleration magnitude, m/s^2, by second differences."""
    dt = np.diff(t)
    v = np.diff(x, axis=0) / dt[:, None, None]
    a = np.diff(v, axis=0) / (0.5 * (dt[1:] + dt[:-1]))[:, None, None]
    return float(np.nanmean(np.linalg.norm(a, axis=-1)))


def lag_ms(est: NDArray[np.float64], truth: NDArray[np.float64], t: NDArray[np.float64],
           max_shift: int = 12) -> float:
    """Delay of ``est`` behind ``truth`` by cross-correlating joint velocities."""
    ve = np.diff(est[:, MOVING], axis=0).reshape(len(est) - 1, -1)
    vt = np.diff(truth[:, MOVING], axis=0).reshape(len(truth) - 1, -1)
    ok = np.all(np.isfinite(ve), axis=1) & np.all(np.isfinite(vt), axis=1)
    ve, vt = np.where(ok[:, None], ve, 0.0), np.where(ok[:, None], vt, 0.0)
    ve, vt = ve - ve.mean(0), vt - vt.mean(0)
    shifts = np.arange(-2, max_shift + 1)
    n = len(ve)
    cc = np.array([np.sum(ve[s:] * vt[: n - s]) if s >= 0 else np.sum(ve[: n + s] * vt[-s:])
                   for s in shifts])
    k = int(np.argmax(cc))
    frac = 0.0
    if 0 < k < len(cc) - 1:
        den = cc[k - 1] - 2 * cc[k] + cc[k + 1]
        frac = 0.5 * (cc[k - 1] - cc[k + 1]) / den if den != 0 else 0.0
    return float((shifts[k] + frac) * np.median(np.diff(t)) * 1000.0)


def mpjpe_mm(est: NDArray[np.float64], truth: NDArray[np.float64]) -> float:
    """Mean per-joint position error in mm over finite joints."""
    return float(np.nanmean(np.linalg.norm(est - truth, axis=-1)) * 1000.0)


def run_filter(make: Callable[[], JointFilter], seq: Sequence) -> tuple[NDArray[np.float64], float]:
    """Filter a whole sequence; return the output and the median ms per frame."""
    _, t, _, meas, states = seq
    f = make()
    out = np.empty_like(meas)
    dts = np.empty(len(t))
    for i in range(len(t)):
        t0 = time.perf_counter()
        out[i] = f.filter(float(t[i]), meas[i], states[i] if states else None)
        dts[i] = time.perf_counter() - t0
    return out, float(np.median(dts) * 1000.0)


def measure(seqs: list[Sequence]) -> list[tuple[str, float, float, float, float, float]]:
    """Rows: name, jitter, jitter reduction, lag ms, MPJPE mm, ms/frame (medians over clips)."""
    rows = []
    truth_j = [jitter(s[2], s[1]) for s in seqs]
    raw = [(jitter(s[3], s[1]), lag_ms(s[3], s[2], s[1]), mpjpe_mm(s[3], s[2])) for s in seqs]
    rows.append(("truth (reference)", float(np.median(truth_j)), float("nan"), 0.0, 0.0, 0.0))
    rows.append(("raw (noisy input)", float(np.median([r[0] for r in raw])), 1.0,
                 float(np.median([r[1] for r in raw])), float(np.median([r[2] for r in raw])), 0.0))
    for name, make in FILTERS.items():
        res = []
        for s, r in zip(seqs, raw, strict=True):
            out, ms = run_filter(make, s)
            j = jitter(out, s[1])
            res.append((j, r[0] / j, lag_ms(out, s[2], s[1]) - r[1], mpjpe_mm(out, s[2]), ms))
        j, red, lag, err, ms = (float(v) for v in np.median(np.array(res), axis=0))
        rows.append((name, j, red, lag, err, ms))
    return rows


def table(rows: list[tuple[str, float, float, float, float, float]]) -> str:
    """Markdown table of the rows."""
    out = ["| input / filter | jitter (m/s²) | jitter reduction | added lag (ms) | MPJPE (mm) "
           "| ms/frame |", "|---|---|---|---|---|---|"]
    for name, j, red, lag, err, ms in rows:
        red_s = "" if not np.isfinite(red) else f"{red:.1f}x"
        ms_s = f"{ms:.3f}" if ms else ""
        err_s = f"{err:.1f}" if err else ""
        out.append(f"| {name} | {j:.1f} | {red_s} | {abs(lag) if abs(lag) < 0.5 else lag:.0f} "
                   f"| {err_s} | {ms_s} |")
    return "\n".join(out)


def write_docs(text: str) -> None:
    """Replace (or append) the '## Smoothing' section of docs/benchmarks.md."""
    path = REPO / "docs" / "benchmarks.md"
    doc = path.read_text() if path.exists() else "# Benchmarks\n"
    start = doc.find("\n## Smoothing")
    section = "\n## Smoothing\n\n" + text.strip() + "\n"
    if start < 0:
        doc = doc.rstrip("\n") + "\n" + section
    else:
        end = doc.find("\n## ", start + 5)
        doc = doc[:start] + section + (doc[end:] if end >= 0 else "")
    path.write_text(doc)


def main() -> None:
    """Parse arguments, measure, print (and optionally write docs/benchmarks.md)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", help="a tracker's poses.jsonl (then --truth is required)")
    ap.add_argument("--truth", help="the matching truth.jsonl")
    ap.add_argument("--noise-cm", type=float, default=2.0)
    ap.add_argument("--outlier-rate", type=float, default=0.01)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--write-docs", action="store_true", help="update docs/benchmarks.md")
    args = ap.parse_args()
    if bool(args.poses) != bool(args.truth):
        ap.error("--poses and --truth go together")
    seqs = load_sequences(args)
    rows = measure(seqs)
    src = (f"`{args.poses}` against `{args.truth}`" if args.poses else
           f"{len(seqs)} real clips ({', '.join(s[0] for s in seqs)}) at 30 fps with "
           f"{args.noise_cm:g} cm Gaussian jitter and {args.outlier_rate:.0%} outliers of "
           f"15-30 cm (seed {args.seed})")
    text = (f"Medians over clips; input: {src}.\n"
            f"Machine: {machine()}; date: "
            f"{datetime.date.today()}. Command: `.venv/bin/python benchmarks/smoothing_bench.py"
            f"{' --write-docs' if args.write_docs else ''}`.\n\n" + table(rows) + "\n")
    print(text)
    if args.write_docs:
        write_docs(text)


if __name__ == "__main__":
    main()
