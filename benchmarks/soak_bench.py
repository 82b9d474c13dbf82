"""Soak benchmark: a 30-minute session at 30 fps with everything attached.

``.venv/bin/python benchmarks/soak_bench.py [--minutes 30]`` plays CMU 13_29 in a loop
through a session with one-euro smoothing, the built-in gestures, a physics world
throwing a ball every 2 s and a recorder, on a fixed clock (simulated time: faster
than real time), and prints memory and frame time per minute and the event accounting
(:func:`bodyplay.testing.soak.run_soak`). Figures: docs/reliability.md.
"""

from __future__ import annotations

import argparse
import datetime

from _machine import machine
from bodyplay.testing.soak import run_soak


def main() -> None:
    """Run the soak and print its report."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--minutes", type=float, default=30.0)
    ap.add_argument("--fps", type=float, default=30.0)
    args = ap.parse_args()
    print(f"# soak benchmark, {datetime.date.today()}, {machine()}")
    r = run_soak(seconds=60.0 * args.minutes, fps=args.fps)
    print("\n".join(r.lines()))
    ok = (r.rss_growth <= 0.05 and r.dropped == 0
          and r.emitted == r.delivered == r.recording_events)
    print("PASS" if ok else "FAIL", "(RSS growth <= 5%, no event dropped, every event recorded)")


if __name__ == "__main__":
    main()
