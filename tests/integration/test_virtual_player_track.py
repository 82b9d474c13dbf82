"""End to end: a virtual keeper reaching for balls, filmed, tracked by the color shirt."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.runtime.session import create_session
from bodyplay.virtual import ReachController, VirtualPlayerSource

pytestmark = pytest.mark.gl

# (seen at, arrival, point): a ball to the keeper's left, then one to the right
BALLS = ((0.2, 0.75, (0.5, 1.35, 0.3)), (0.8, 1.35, (-0.55, 1.45, 0.3)))


def test_tracked_wrists_follow_the_virtual_keepers_reaches(synth_gl) -> None:
    keeper = ReachController()
    src = VirtualPlayerSource(keeper, cameras=2, seconds=1.5, seed=3)
    session = create_session(source=src, tracker="colorshirt")
    pending = list(BALLS)
    err, reach_err = [], []
    with session:
        while (ev := session.step()) is not None or not session.done:
            t = src.last.t if src.last is not None else 0.0
            while pending and pending[0][0] <= t + 1e-9:  # the game, between frames
                _, arrival, point = pending.pop(0)
                keeper.set_target(arrival, point, now=t)
            if ev is None or src.truth is None or not np.isfinite(ev.joints[[7, 10]]).all():
                continue  # the first frame: a start waits for motion (colorshirt.md)
            e = np.linalg.norm(ev.joints[[7, 10]] - src.truth[[7, 10]], axis=1)
            err.append(e)
            if any(abs(t - b[1]) < 0.05 for b in BALLS):
                reach_err.append(e)
    err_a = np.asarray(err)
    assert len(err_a) >= 40  # every frame tracked but the first
    assert float(np.median(err_a)) < 0.08, np.median(err_a, axis=0)
    # at each ball's arrival the reaching wrist is tracked where it is
    assert len(reach_err) >= 4
    assert float(np.median(np.max(reach_err, axis=1))) < 0.1, reach_err
