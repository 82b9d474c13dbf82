"""Specification of the One Euro joint filter (bodyplay.filters.one_euro)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError, TimestampError
from bodyplay.filters import (
    JointFilter,
    OneEuroFilter,
    OneEuroOptions,
    make_filter,
    one_euro_filter,
)


def _still(value: float = 1.0) -> np.ndarray:
    return np.full((17, 3), value)


def test_one_euro_is_a_joint_filter():
    assert isinstance(one_euro_filter(), JointFilter)


def test_one_euro_first_frame_passes_through_unchanged():
    f = one_euro_filter()
    z = np.random.default_rng(0).normal(size=(17, 3))
    np.testing.assert_array_equal(f.filter(0.0, z), z)


def test_one_euro_matches_the_papers_scalar_recurrence_per_coordinate():
    o = OneEuroOptions(min_cutoff=1.2, beta=0.7, d_cutoff=1.5, speed="coordinate")
    f = OneEuroFilter(o)
    rng = np.random.default_rng(1)
    times = np.cumsum(rng.uniform(0.02, 0.05, 40))
    xs = np.cumsum(rng.normal(0, 0.05, (40, 17, 3)), axis=0)

    def alpha(fc: float, dt: float) -> float:
        tau = 1.0 / (2 * np.pi * fc)
        return 1.0 / (1.0 + tau / dt)

    # Reference: the scalar filter of Casiez et al. for coordinate (4, 1).
    x_hat, dx_hat, ref = xs[0, 4, 1], 0.0, [xs[0, 4, 1]]
    for k in range(1, 40):
        dt = times[k] - times[k - 1]
        dx = (xs[k, 4, 1] - x_hat) / dt
        dx_hat = dx_hat + alpha(o.d_cutoff, dt) * (dx - dx_hat)
        fc = o.min_cutoff + o.beta * abs(dx_hat)
        x_hat = x_hat + alpha(fc, dt) * (xs[k, 4, 1] - x_hat)
        ref.append(x_hat)
    out = [f.filter(t, x)[4, 1] for t, x in zip(times, xs, strict=True)]
    np.testing.assert_allclose(out, ref, rtol=1e-12)


def test_one_euro_reduces_jitter_of_a_still_joint():
    rng = np.random.default_rng(2)
    f = one_euro_filter(min_cutoff=1.0, beta=0.5)
    noisy = _still() + rng.normal(0, 0.02, (300, 17, 3))
    out = np.array([f.filter(i / 30, z) for i, z in enumerate(noisy)])
    assert np.std(out[60:]) < 0.4 * np.std(noisy[60:])


def test_one_euro_follows_fast_motion_with_less_lag_when_beta_is_higher():
    t = np.arange(90) / 30.0
    x = np.zeros((90, 17, 3))
    x[:, :, 0] = 2.0 * t[:, None]  # 2 m/s ramp
    errs = []
    for beta in (0.0, 5.0):
        f = one_euro_filter(min_cutoff=1.0, beta=beta)
        out = np.array([f.filter(ti, xi) for ti, xi in zip(t, x, strict=True)])
        errs.append(np.abs(out[-1, 0, 0] - x[-1, 0, 0]))
    assert errs[1] < 0.3 * errs[0]


def test_one_euro_lost_joint_comes_out_nan_and_resumes_from_its_history():
    f = one_euro_filter()
    f.filter(0.0, _still(1.0))
    z = _still(1.0)
    z[7] = np.nan
    out = f.filter(0.033, z)
    assert np.all(np.isnan(out[7])) and np.all(np.isfinite(np.delete(out, 7, axis=0)))
    state = ["tracked"] * 17
    state[3] = "lost"
    out = f.filter(0.066, _still(1.0), tuple(state))
    assert np.all(np.isnan(out[3]))
    out = f.filter(0.1, _still(1.2))
    assert 1.0 < out[7, 0] < 1.2  # smoothed, not restarted


def test_one_euro_restarts_a_joint_lost_longer_than_reset_after():
    f = one_euro_filter(reset_after=0.2)
    f.filter(0.0, _still(0.0))
    z = _still(0.0)
    z[2] = np.nan
    for k in range(1, 10):
        f.filter(k * 0.033, z)
    out = f.filter(0.4, _still(5.0))
    assert out[2, 0] == 5.0 and out[0, 0] < 5.0


def test_one_euro_rejects_time_that_does_not_advance():
    f = one_euro_filter()
    f.filter(1.0, _still())
    with pytest.raises(TimestampError):
        f.filter(1.0, _still())


def test_one_euro_reset_forgets_history_and_time():
    f = one_euro_filter()
    f.filter(5.0, _still(0.0))
    f.reset()
    np.testing.assert_array_equal(f.filter(0.0, _still(3.0)), _still(3.0))


@pytest.mark.parametrize(
    "kwargs", [{"min_cutoff": 0}, {"beta": -1}, {"d_cutoff": float("nan")}, {"speed": "x"},
               {"reset_after": 0}, {"unknown": 1}]
)
def test_one_euro_factory_rejects_invalid_options(kwargs):
    with pytest.raises(ConfigError):
        one_euro_filter(**kwargs)


def test_one_euro_rejects_wrong_joint_shape():
    with pytest.raises(ConfigError):
        one_euro_filter().filter(0.0, np.zeros((11, 3)))


def test_make_filter_builds_each_kind_and_rejects_unknown():
    assert isinstance(make_filter("one_euro"), OneEuroFilter)
    with pytest.raises(ConfigError):
        make_filter("median")
