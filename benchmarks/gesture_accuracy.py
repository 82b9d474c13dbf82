"""Precision and recall of the built-in gestures on the hand-labeled real clips.

Reads tests/fixtures/gestures/labels.toml and the BVH files under ../shared/data,
retargets each clip onto the reference skeleton at 30 fps, runs the recognizer on
the clean joints and on tracker-like noisy joints smoothed by the One Euro filter,
and prints a table per gesture.

    .venv/bin/python benchmarks/gesture_accuracy.py [--noise-cm 2.0] [--seed 0]
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path

import numpy as np

from _machine import machine
from bodyplay.filters import one_euro_filter
from bodyplay.gestures import GestureRecognizer, load_gestures
from bodyplay.gestures.evaluation import GestureScore, load_labels, run_recognizer, score_events
from bodyplay.motion.clip import load_clip

REPO = Path(__file__).resolve().parents[1]
DATA = REPO.parent / "shared" / "data"
LABELS = REPO / "tests" / "fixtures" / "gestures" / "labels.toml"


def evaluate(noise_cm: float = 0.0, seed: int = 0) -> dict[str, GestureScore]:
    """Score every labeled clip; with ``noise_cm`` > 0 add jitter and smooth it."""
    defs = load_gestures("builtin")
    names = [d.name for d in defs]
    rec = GestureRecognizer(defs)
    rng = np.random.default_rng(seed)
    total = {g: GestureScore() for g in names}
    for clip in load_labels(LABELS, DATA):
        mc = load_clip(clip.path, fps=30)
        joints = mc.joints()
        transform = None
        if noise_cm > 0:
            joints = joints + rng.normal(0.0, noise_cm / 100.0, joints.shape)
            filt = one_euro_filter()
            transform = filt.filter
        events = run_recognizer(rec, mc.times, joints, transform)
        for g, s in score_events(clip.name, events, clip.spans, names).items():
            total[g].add(s)
    return total


def table(scores: dict[str, GestureScore]) -> str:
    """A markdown table of spans, TP, FP, precision and recall per gesture and overall."""
    rows = [
        "| gesture | labeled spans | TP | FP | precision | recall |",
        "|---|---|---|---|---|---|",
    ]
    allg = GestureScore()
    for g, s in scores.items():
        allg.add(s)
        rows.append(f"| {g} | {s.spans} | {s.tp} | {s.fp} | {s.precision:.2f} | {s.recall:.2f} |")
    rows.append(
        f"| **all** | {allg.spans} | {allg.tp} | {allg.fp} | {allg.precision:.2f} "
        f"| {allg.recall:.2f} |"
    )
    return "\n".join(rows)


def main() -> None:
    """Print the tables (clean and noisy+smoothed) with machine and date."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--noise-cm", type=float, default=2.0)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    print(f"machine: {machine()}; date: {datetime.date.today()}")
    clean = evaluate(0.0)
    print("\nclean mocap joints:\n" + table(clean))
    for g, s in clean.items():
        for c, t in s.false_times:
            print(f"  false {g} in {c} at {t:.2f} s")
        for c, t0, t1 in s.missed:
            print(f"  missed {g} in {c} [{t0:.2f}, {t1:.2f}]")
    noisy = evaluate(a.noise_cm, a.seed)
    print(f"\n{a.noise_cm:g} cm Gaussian jitter, One Euro smoothed:\n" + table(noisy))
    for g, s in noisy.items():
        for c, t in s.false_times:
            print(f"  false {g} in {c} at {t:.2f} s")


if __name__ == "__main__":
    main()
