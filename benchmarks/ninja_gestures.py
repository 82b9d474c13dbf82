"""The ninja's five motions on tracked input: precision, recall and latency.

Scripted players (Timelines of the five motions from the gesture tables, with other
motions between them as negatives: raising a hand, waving, punching, raising both
hands) are filmed by the synthetic camera and tracked (default: the color-shirt
tracker, one camera; the recognizer sees the tracker's joints, One Euro smoothed).
Each performed motion is a labeled span from its start to 0.8 s after the end of its
movement; a ``performed`` event in the span is a true positive, any other event of
the five a false positive. Latency is the event's time minus the end of the
movement (the arms folded, the squat reached, the feet together, the arm down: the
times in ``apps.ninja.game.player.MOTION_END``); negative when the threshold is
crossed before the movement ends.

Scripts differ by seed (order, speed 0.8-1.25, body size, pauses); seeds are split in
two halves: ``--half tune`` is what thresholds were checked on, ``--half test`` is
reported. ``--truth`` skips camera and tracker (the skeleton's joints).

``--tracker silhouette`` tracks with the options the ninja game gives that tracker
(its hierarchy built from the vendored clips plus the ninja's varied motions,
apps/ninja/game/training.py; ``--plain`` for the tracker's default hierarchy);
``--lead-in 1`` films one second of the empty room first, as the game does for
the silhouette tracker (default 0: the player is in view from the first frame).

    .venv/bin/python benchmarks/ninja_gestures.py [--half test] [--scripts 3] [--truth]
        [--tracker silhouette] [--lead-in 1] [--cache DIR]
"""

from __future__ import annotations

import argparse
import datetime
import json
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from _machine import machine

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # apps/ from a checkout
from apps.ninja.game.player import MOTION_END  # noqa: E402
from apps.ninja.game.simulate import ninja_recognizer  # noqa: E402

from bodyplay.body import Skeleton  # noqa: E402
from bodyplay.filters import one_euro_filter  # noqa: E402
from bodyplay.gestures.evaluation import GestureScore, score_events  # noqa: E402
from bodyplay.testing import GESTURE_MOTIONS, Timeline  # noqa: E402

FIVE = ("transfigure", "crouch", "step_left", "step_right", "hit", "double_hit")
NEGATIVES = ("raise_right_hand", "wave_right", "punch_right", "raise_both_hands", "wave_left")
SHAPES = ("m", "s", "l", "m_slim")
SPAN_AFTER = 0.8


@dataclass
class Script:
    """One scripted sequence: its timeline, body, and the motions it performs."""

    seed: int
    body: str
    timeline: Timeline
    motions: list[dict[str, Any]]


def make_script(seed: int) -> Script:
    """A random order of every one of the five motions (each once, steps both ways)
    with negatives between them, at a random speed per motion, for one body size."""
    rng = np.random.default_rng(seed)
    body = SHAPES[(seed // 2) % len(SHAPES)]
    tl = Timeline(Skeleton.from_shape(body), blend=0.15)
    tl.hold("idle", 1.5)
    order = ["transfigure"] + [str(g) for g in rng.permutation(list(FIVE[1:]))]
    negs = [str(n) for n in rng.permutation(list(NEGATIVES))]
    x = 0.0
    motions = []
    for i, g in enumerate(order):
        speed = float(rng.uniform(0.8, 1.25))
        start = tl.cursor + float(rng.uniform(0.4, 0.9))
        tl.gesture(g, start=start, speed=speed, at=(x, 0.0))
        length = float(GESTURE_MOTIONS[g][-1][0]) / speed  # type: ignore[index]
        motions.append({"gesture": g, "start": start, "end": start + length,
                        "motion_end": start + MOTION_END[g] / speed})
        x += 0.5 if g == "step_left" else -0.5 if g == "step_right" else 0.0
        if i < len(negs):
            ns = tl.cursor + float(rng.uniform(0.4, 0.9))
            tl.gesture(negs[i], start=ns, speed=float(rng.uniform(0.8, 1.25)), at=(x, 0.0))
    tl.wait(1.0)
    return Script(seed, body, tl, motions)


def frames_truth(script: Script, fps: float) -> Iterator[tuple[float, np.ndarray]]:
    """(t, joints) of the script's skeleton at ``fps``."""
    for t in np.arange(0.0, script.timeline.duration, 1.0 / fps):
        yield float(t), script.timeline.joints_at(float(t))


def tracker_options(tracker_name: str, plain: bool = False) -> Any:
    """The options the ninja game gives ``tracker_name`` (its own silhouette hierarchy),
    or the tracker's defaults when ``plain``."""
    if plain:
        return None
    from apps.ninja.game.game import NinjaGame

    return NinjaGame().tracker_options(tracker_name)


def frames_tracked(script: Script, fps: float, tracker_name: str,
                   stats: dict[str, list[float]], plain: bool = False, lead_in: float = 0.0
                   ) -> Iterator[tuple[float, np.ndarray]]:
    """(t, joints) the tracker reports while the synthetic camera films the script
    (with the options the game gives it; its defaults when ``plain``), after
    ``lead_in`` s of the empty room (not yielded; the script's times are kept)."""
    from bodyplay.body.actor import load_actor
    from bodyplay.synth import SyntheticCamera
    from bodyplay.synth.options import make_synthetic_camera_options
    from bodyplay.trackers import create_tracker

    actor = load_actor(shape=script.body)
    times = np.arange(0.0, script.timeline.duration, 1.0 / fps)
    # The actor is posed by the script retargeted to its own skeleton: same rotations.
    sk = actor.skeleton
    tl = script.timeline
    frame_joints = np.stack([sk.joint_positions(tl.pose_at(float(t))) for t in times[::10]])
    opts = make_synthetic_camera_options(cameras=1, fps=fps, body=script.body,
                                         seed=script.seed)
    with SyntheticCamera(opts, frame_joints=frame_joints, actor=actor) as cam:
        tracker = create_tracker(tracker_name, cam.cameras,
                                 tracker_options(tracker_name, plain))
        empty = np.arange(0.0, lead_in - 1e-9, 1.0 / fps)
        for i, t in enumerate(empty):
            tracker.process(cam.capture_empty(float(t), index=i).frames)
        for i, t in enumerate(times, start=len(empty)):
            shot = cam.capture(float(t) + lead_in, tl.pose_at(float(t)), index=i)
            r = tracker.process(shot.frames)
            stats.setdefault("ms", []).append(float(r.ms))
            err = np.linalg.norm(r.joints[:11] - shot.joints[:11], axis=1)
            if np.all(np.isfinite(err)):
                stats.setdefault("err_cm", []).append(float(100 * err.mean()))
            yield float(t), r.joints


def cached(path: Path, frames: Iterator[tuple[float, np.ndarray]]
           ) -> Iterator[tuple[float, np.ndarray]]:
    """Replay the frames stored at ``path``, or consume ``frames`` and store them."""
    if path.exists():
        z = np.load(path)
        yield from zip(z["t"].tolist(), z["joints"], strict=True)
        return
    ts, js = [], []
    for t, j in frames:
        ts.append(t)
        js.append(j)
        yield t, j
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(path, t=np.array(ts), joints=np.stack(js))


def evaluate(script: Script, frames: Iterator[tuple[float, np.ndarray]]
             ) -> tuple[dict[str, GestureScore], dict[str, list[float]]]:
    """Score one script: per-gesture counts and the latencies of the found motions."""
    rec = ninja_recognizer()
    filt = one_euro_filter()
    events = []
    for t, j in frames:
        events.extend(rec.update(t, filt.filter(t, j)))
    spans: dict[str, list[tuple[float, float]]] = {}
    for m in script.motions:
        spans.setdefault(m["gesture"], []).append((m["start"], m["motion_end"] + SPAN_AFTER))
    scores = score_events(f"seed{script.seed}", events, spans, FIVE)
    lat: dict[str, list[float]] = {}
    done = [e for e in events if e.phase == "performed"]
    for m in script.motions:
        hit = [e for e in done if e.gesture == m["gesture"]
               and m["start"] <= e.t <= m["motion_end"] + SPAN_AFTER]
        if hit:
            lat.setdefault(m["gesture"], []).append(hit[0].t - m["motion_end"])
    return scores, lat


def seeds(half: str, n: int, skip: int = 0) -> list[int]:
    """Tune seeds are even, test seeds odd; ``skip`` leaves out the first ones."""
    first = 0 if half == "tune" else 1
    return [first + 2 * i for i in range(skip, skip + n)]


def main() -> None:
    """Print per-gesture precision, recall and latency (median, worst) as markdown."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--half", choices=("tune", "test"), default="test")
    ap.add_argument("--scripts", type=int, default=3)
    ap.add_argument("--skip", type=int, default=0, help="start after this many scripts")
    ap.add_argument("--tracker", default="colorshirt")
    ap.add_argument("--plain", action="store_true",
                    help="the tracker's default options, not the game's (for the silhouette "
                         "tracker: its default hierarchy instead of the ninja's)")
    ap.add_argument("--lead-in", type=float, default=0.0,
                    help="seconds of the empty room before the script (default 0: the "
                         "player is in view from the first frame)")
    ap.add_argument("--truth", action="store_true", help="skeleton joints, no camera")
    ap.add_argument("--fps", type=float, default=30.0)
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--cache", type=Path, default=None,
                    help="keep the tracked joints of each script here (re-scoring is instant)")
    a = ap.parse_args()
    print(f"machine: {machine()}; date: {datetime.date.today()}")
    total = {g: GestureScore() for g in FIVE}
    lat: dict[str, list[float]] = {g: [] for g in FIVE}
    stats: dict[str, list[float]] = {}
    t0 = time.perf_counter()
    for seed in seeds(a.half, a.scripts, a.skip):
        script = make_script(seed)
        frames = (frames_truth(script, a.fps) if a.truth
                  else frames_tracked(script, a.fps, a.tracker, stats, a.plain, a.lead_in))
        if a.cache is not None and not a.truth:
            tag = f"{a.tracker}{'_plain' if a.plain else ''}"
            tag += f"_lead{a.lead_in:g}" if a.lead_in > 0 else ""
            frames = cached(a.cache / f"{tag}_seed{seed}_{a.fps:g}fps.npz", frames)
        scores, l = evaluate(script, frames)
        for g in FIVE:
            total[g].add(scores[g])
            lat[g] += l.get(g, [])
        missed = [(g, round(x[1], 2)) for g in FIVE for x in scores[g].missed]
        false = [(g, round(x[1], 2)) for g in FIVE for x in scores[g].false_times]
        print(f"  seed {seed} body {script.body} {script.timeline.duration:.1f} s: "
              f"missed {missed} false {false}", flush=True)
    src = "skeleton joints (no camera)" if a.truth else f"{a.tracker} tracker, one camera"
    print(f"\n{src}, {a.half} half ({a.scripts} scripts, "
          f"{time.perf_counter() - t0:.0f} s):")
    if stats.get("err_cm"):
        print(f"tracker upper-body error median {np.median(stats['err_cm']):.1f} cm, "
              f"{np.median(stats['ms']):.0f} ms/frame")
    print("| gesture | motions | TP | FP | precision | recall | latency median (s) "
          "| latency worst (s) |")
    print("|---|---|---|---|---|---|---|---|")
    out = {}
    for g in FIVE:
        s = total[g]
        lm = f"{np.median(lat[g]):+.2f}" if lat[g] else "–"
        lw = f"{np.max(lat[g]):+.2f}" if lat[g] else "–"
        print(f"| {g} | {s.spans} | {s.tp} | {s.fp} | {s.precision:.2f} | {s.recall:.2f} "
              f"| {lm} | {lw} |")
        out[g] = {"spans": s.spans, "tp": s.tp, "fp": s.fp, "precision": s.precision,
                  "recall": s.recall, "latency": lat[g]}
    if a.json:
        a.json.write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
