"""Physics bridge cost: milliseconds of ``PhysicsWorld.on_pose`` per 30 fps pose frame.

Run: ``.venv/bin/python benchmarks/physics_bench.py`` (``--quick`` for a smoke run).
A scripted player waves and punches (noise 1 cm) for ``--seconds``; its joints are
computed once, then each pose event is fed to a fresh world while a "game" keeps
``--balls`` balls flying at the player (each replaced when it has flown past). Timed:
only ``on_pose`` (moving 12 kinematic parts, the fixed sub-steps, contact events
into a list), at the default dt of 1/120 s (4 sub-steps per frame) and at 1/240 s.
Prints medians over frames and repeats, with the machine and the date.
"""

from __future__ import annotations

import argparse
import datetime
import os
import statistics
import time

import numpy as np

from _machine import machine
from bodyplay.events.types import Event, PoseEvent
from bodyplay.physics import PhysicsOptions, PhysicsWorld
from bodyplay.testing import ScriptedPlayer, Timeline

FPS = 30.0


def poses(seconds: float) -> list[PoseEvent]:
    """The pose events of a waving, punching player for ``seconds``."""
    timeline = Timeline()
    while timeline.duration < seconds:
        timeline.gesture("wave_right").gesture("punch_left").gesture("raise_both_hands")
    player = ScriptedPlayer(timeline, FPS, duration=seconds, noise=0.01, seed=1)
    return [PoseEvent(t=s.t, emitted_t=s.t, frame=s.frame, joints=s.joints, state=s.state,
                      confidence=s.confidence) for s in player]


def run(events: list[PoseEvent], dt: float, balls: int, seed: int) -> tuple[list[float], int]:
    """Per-frame on_pose times (s) and the number of contact events."""
    log: list[Event] = []
    world = PhysicsWorld(PhysicsOptions(dt=dt), emit=log.append)
    rng = np.random.default_rng(seed)
    times = []
    for ev in events:
        for obj in list(world):
            if abs(obj.body.position.x) > 3.0 or obj.body.position.y < -1.0:
                world.remove(obj)
        while len(world.objects) < balls:
            side = rng.choice([-1.0, 1.0])
            world.add_ball((2.5 * side, rng.uniform(0.4, 1.8)),
                           (-rng.uniform(5.0, 12.0) * side, rng.uniform(0.0, 3.0)))
        t0 = time.perf_counter()
        world.on_pose(ev)
        times.append(time.perf_counter() - t0)
    world.close()
    return times, len(log)


def main() -> None:
    """Print the median ms per pose frame for a few ball counts and step sizes."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    if a.quick:
        a.seconds, a.repeats = 3.0, 1
    print(f"date {datetime.date.today().isoformat()}; machine {machine()}, "
          f"load average {os.getloadavg()[0]:.1f}")
    events = poses(a.seconds)
    for dt in (1.0 / 120.0, 1.0 / 240.0):
        for balls in (0, 5, 20):
            all_times: list[float] = []
            contacts = 0
            for r in range(a.repeats):
                times, n = run(events, dt, balls, seed=r)
                all_times.extend(times[1:])
                contacts += n
            ms = np.array(all_times) * 1e3
            steps = round(1 / (dt * FPS))
            print(f"dt 1/{round(1 / dt)} s ({steps} steps/frame), {balls:2d} balls: "
                  f"median {statistics.median(ms):.3f} ms per pose frame "
                  f"(p95 {np.percentile(ms, 95):.3f}, {len(ms)} frames, "
                  f"{contacts / a.repeats:.0f} contact events per run)")


if __name__ == "__main__":
    main()
