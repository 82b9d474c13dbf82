"""Virtual players: what a frame of the virtual keeper costs, and how well it is tracked.

Run: .venv/bin/python benchmarks/virtual_player_bench.py [--seconds 10] [--seed 1]
     [--cameras 1 2] [--no-track]

A ReachController keeper faces a shot every 1.2 s (targets drawn from a seeded
generator over the goal mouth the keeper can cover: 1.4 m either side, 0.25..2.0 m
high, announced 0.7 s before arrival). For 1 and 2 cameras at 640x480 it prints the
median and 90th percentile (wall ms, and CPU ms: the load-independent share) of:
the controller's pose (``pose_at``), the IK plan
(``set_target``, once per shot), the synthetic camera's frame (``capture``: skinning,
GL, sensor), and, through ``create_session(source=..., tracker="colorshirt")``, the
tracker's step and the tracked wrists' distance to the truth (median and worst,
at idle and within 0.1 s of a ball's arrival). Also the pose-level source's rate.
With ``--lookahead`` each camera count is played again with the next frame
rendered while the current one is tracked (the end-to-end time per frame then
counts the overlap). ``--gaze 0.3`` lets the keeper turn its head to watch each
ball. Nothing was tuned on these shots (the seed picks them).
"""

from __future__ import annotations

import argparse
import datetime
import os
import statistics
import time

import numpy as np

from _machine import machine
from bodyplay.body.actor import load_actor
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.session import create_session
from bodyplay.virtual import (
    IdleMotion,
    ReachController,
    ReachWeights,
    VirtualPlayerSource,
    VirtualPoseSource,
)

SHOT_EVERY = 1.2
WARNING = 0.7


def shots(seconds: float, seed: int) -> list[tuple[float, float, tuple[float, float, float]]]:
    """(seen, arrival, point) of each shot."""
    rng = np.random.default_rng(seed)
    out = []
    t = 0.5
    while t + WARNING < seconds:
        x = float(rng.uniform(-1.4, 1.4))
        y = float(rng.uniform(0.25, 2.0))
        out.append((t, t + WARNING, (x, y, 0.3)))
        t += SHOT_EVERY
    return out


def _q(values: list[float]) -> str:
    a = np.asarray(values)
    return f"median {np.median(a):6.2f}  p90 {np.percentile(a, 90):6.2f}"


def run(cameras: int, seconds: float, seed: int, track: bool, idle: IdleMotion,
        lookahead: bool = False, gaze: float = 0.0) -> None:
    """Render (and track) one scripted round; print the figures."""
    keeper = ReachController(idle.skeleton, idle=idle, weights=ReachWeights(gaze=gaze))
    src = VirtualPlayerSource(keeper, cameras=cameras, seconds=seconds, seed=seed,
                              lookahead=lookahead)
    plan_ms, pose_ms, render_ms, step_ms = [], [], [], []
    plan_cpu, pose_cpu, render_cpu = [], [], []
    err_idle, err_reach = [], []
    pending = shots(seconds, seed)
    arrivals = [s[1] for s in pending]
    session = create_session(source=src, tracker="colorshirt") if track else None
    it = iter(src)
    reachable = 0
    with src:
        while True:
            t0 = time.perf_counter()
            c0 = time.process_time()
            if session is not None:
                ev = session.step()
                if session.done:
                    break
            else:
                ev = None
                if next(it, None) is None:
                    break
                render_cpu.append(1000 * (time.process_time() - c0))
            step = time.perf_counter() - t0
            assert src.last is not None
            t = src.last.t
            render_ms.append(src.last_render_ms)
            step_ms.append(1000 * step - (0.0 if lookahead else src.last_render_ms))
            p0, c0 = time.perf_counter(), time.thread_time()
            keeper.pose_at(t)
            pose_ms.append(1000 * (time.perf_counter() - p0))
            pose_cpu.append(1000 * (time.thread_time() - c0))
            while pending and pending[0][0] <= t + 1e-9:
                _, arrival, point = pending.pop(0)
                p0, c0 = time.perf_counter(), time.thread_time()
                plan = keeper.set_target(arrival, point, now=t)
                plan_ms.append(1000 * (time.perf_counter() - p0))
                plan_cpu.append(1000 * (time.thread_time() - c0))
                reachable += plan.reachable
            if ev is not None and src.truth is not None and src.last.index >= 3:
                e = np.linalg.norm(ev.joints[[7, 10]] - src.truth[[7, 10]], axis=1)
                near = any(abs(t - a) <= 0.1 for a in arrivals)
                (err_reach if near else err_idle).extend(e[np.isfinite(e)].tolist())
    n = len(render_ms)
    print(f"cameras={cameras}  lookahead={'on' if lookahead else 'off'}  frames={n}  "
          f"shots={len(plan_ms)} (reachable {reachable})")
    print(f"  controller pose_at      ms {_q(pose_ms)}   cpu {_q(pose_cpu)}")
    print(f"  IK plan (set_target)    ms {_q(plan_ms)}   cpu {_q(plan_cpu)}   (once per shot)")
    print(f"  synthetic frame         ms {_q(render_ms)}   -> "
          f"{1000 / statistics.median(render_ms):.1f} frames/s"
          + (f"   cpu (all threads) {_q(render_cpu)}" if render_cpu else ""))
    if session is not None and lookahead:
        print(f"  end to end (overlapped) ms {_q(step_ms)}   -> "
              f"{1000 / statistics.median(step_ms):.1f} frames/s")
    elif session is not None:
        print(f"  colorshirt step         ms {_q(step_ms)}")
        total = np.asarray(render_ms) + np.asarray(step_ms)
        print(f"  end to end              ms {_q(total.tolist())}   -> "
              f"{1000 / float(np.median(total)):.1f} frames/s")
    for name, e in (("idle", err_idle), ("reach", err_reach)):
        if e:
            a = 100 * np.asarray(e)
            print(f"  wrist error {name:5s} cm  median {np.median(a):5.1f}  "
                  f"p90 {np.percentile(a, 90):5.1f}  worst {a.max():5.1f}  (n={len(a)})")


def main() -> int:
    """Print the figures for each camera count."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cameras", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--no-track", action="store_true", help="render only")
    ap.add_argument("--gaze", type=float, default=0.0,
                    help="ReachWeights.gaze: the keeper turns its head to the ball (0: off)")
    ap.add_argument("--lookahead", action="store_true",
                    help="also play each camera count with VirtualPlayerSource(lookahead=True)")
    args = ap.parse_args()
    print(f"# virtual_player_bench  {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC  "
          f"{machine()}  seconds={args.seconds} seed={args.seed}  "
          f"load average {os.getloadavg()[0]:.1f}")
    idle = IdleMotion(load_actor("m").skeleton)
    src = VirtualPoseSource(ReachController(idle.skeleton, idle=idle), seconds=30.0)
    t0 = time.perf_counter()
    n = create_session(source=src, clock=FixedClock(1 / 30)).run()
    print(f"pose-level VirtualPoseSource + session: {n / (time.perf_counter() - t0):.0f} "
          f"samples/s")
    for cams in args.cameras:
        run(cams, args.seconds, args.seed, not args.no_track, idle, gaze=args.gaze)
        if args.lookahead:
            run(cams, args.seconds, args.seed, not args.no_track, idle, lookahead=True,
                gaze=args.gaze)
    print(f"# load average at the end {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
