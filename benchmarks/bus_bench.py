"""Event bus throughput: events per second delivered to 10 subscribers.

Run: ``.venv/bin/python benchmarks/bus_bench.py`` (``--quick`` for a smoke run).
Prints the median of repeated timings with the machine and the date; the figures in
docs/benchmarks.md ("## Event bus") come from this script. The requirement is at
least 100,000 events/s to 10 subscribers. Subscribers are minimal callbacks (a
counter), so the figure is the bus's own overhead: synchronous delivery in
subscription order plus the pull queue.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import time

import numpy as np

from _machine import cpu_model
from bodyplay.events import EventBus, GestureEvent, PoseEvent


class _Counter:
    def __init__(self) -> None:
        self.n = 0

    def __call__(self, event: object) -> None:
        self.n += 1


def bench(events: list, subscribers: int, repeats: int, queue_size: int) -> list[float]:
    """Events/s of emitting ``events`` once per repeat to ``subscribers`` counters."""
    rates = []
    for _ in range(repeats):
        bus = EventBus(queue_size=queue_size)
        counters = [_Counter() for _ in range(subscribers)]
        name = events[0].name
        for c in counters:
            bus.subscribe(name, c)
        emit = bus.emit
        t0 = time.perf_counter()
        for e in events:
            emit(e)
        dt = time.perf_counter() - t0
        assert all(c.n == len(events) for c in counters)
        bus.drain()
        rates.append(len(events) / dt)
    return rates


def main() -> None:
    """Print the median events/s for gesture and pose events, with and without the queue."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--events", type=int, default=200_000)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--subscribers", type=int, default=10)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    if a.quick:
        a.events, a.repeats = 20_000, 3
    print(f"date {datetime.date.today().isoformat()}; machine {cpu_model()}, "
          f"{os.cpu_count()} cores, Python {platform.python_version()}, "
          f"load average {os.getloadavg()[0]:.1f}")
    gestures = [GestureEvent(t=i * 1e-3, emitted_t=i * 1e-3, gesture="wave", phase="performed",
                             progress=1.0, started_t=0.0) for i in range(a.events)]
    joints, conf, state = np.zeros((17, 3)), np.ones(17), ("tracked",) * 17
    poses = [PoseEvent(t=i * 1e-3, emitted_t=i * 1e-3, frame=i, joints=joints, state=state,
                       confidence=conf) for i in range(a.events)]
    for label, evs, q in (("gesture, pull queue on", gestures, 4096),
                          ("pose, pull queue on", poses, 4096),
                          ("gesture, pull queue off", gestures, 0)):
        rates = bench(evs, a.subscribers, a.repeats, q)
        print(f"{label:26s}: median {statistics.median(rates):,.0f} events/s to "
              f"{a.subscribers} subscribers (min {min(rates):,.0f}, max {max(rates):,.0f}, "
              f"{a.events:,} events x {a.repeats})")


if __name__ == "__main__":
    main()
