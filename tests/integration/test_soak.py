"""Long sessions: two simulated minutes with everything attached (the 30-minute run is
``benchmarks/soak_bench.py``; figures in docs/reliability.md)."""

from __future__ import annotations

import pytest

from bodyplay.testing.soak import run_soak


@pytest.fixture(scope="module")
def soak():  # type: ignore[no-untyped-def]
    return run_soak(seconds=120.0)


def test_two_minute_session_loses_no_event_and_records_every_one(soak) -> None:  # type: ignore[no-untyped-def]
    assert soak.frames == 3600 and soak.by_name["pose"] == 3600
    assert soak.emitted == soak.delivered == soak.recording_events
    assert soak.recorded_lines == soak.emitted + 1  # and the header
    assert soak.dropped == 0 and soak.drained + soak.queued == soak.emitted
    assert soak.by_name["gesture"] > 50 and soak.by_name["contact"] > 50  # all of it ran
    assert soak.balls_thrown == 60
    assert soak.frame_errors == 0 and soak.subscriber_errors == 0


def test_two_minute_session_neither_grows_in_memory_nor_slows_down(soak) -> None:  # type: ignore[no-untyped-def]
    assert soak.rss_growth <= 0.05, soak.lines()
    assert soak.ms_drift < 1.0, soak.lines()  # a shared machine: within 2x, not a trend


def test_a_full_pull_queue_drops_the_oldest_events_and_counts_them() -> None:
    r = run_soak(seconds=60.0, queue_size=100, drain_every=10.0)
    assert r.dropped > 0
    assert r.drained + r.dropped + r.queued == r.emitted == r.delivered == r.recording_events
