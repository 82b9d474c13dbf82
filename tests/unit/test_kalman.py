"""Specification of the Kalman joint smoother (bodyplay.filters.kalman)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError, TimestampError
from bodyplay.filters import JointFilter, KalmanJointFilter, kalman_filter, make_filter


def _noisy_run(rng: np.random.Generator, n: int = 200):
    times = np.cumsum(rng.uniform(0.025, 0.045, n))
    truth = np.zeros((n, 17, 3))
    truth[:, :, 0] = np.sin(2 * times)[:, None] * np.linspace(0.2, 0.6, 17)[None]
    truth[:, :, 1] = 1.0 + 0.1 * np.cos(3 * times)[:, None]
    noisy = truth + rng.normal(0, 0.02, truth.shape)
    return times, truth, noisy


def test_kalman_is_a_joint_filter():
    assert isinstance(kalman_filter(), JointFilter)


@pytest.mark.parametrize("model", ["cv", "ca"])
def test_kalman_numpy_backend_matches_filterpy_per_joint_filters(model):
    rng = np.random.default_rng(0)
    times, _, noisy = _noisy_run(rng, 150)
    noisy[40, 3] = np.nan
    noisy[60:75, 5] = np.nan  # lost for a while
    noisy[90:110, 8] = np.nan  # lost longer than max_predict: restarts
    noisy[120, 7] += 0.8  # an outlier the gate rejects
    a = kalman_filter(model=model)
    b = kalman_filter(model=model, backend="filterpy")
    for k, (t, z) in enumerate(zip(times, noisy, strict=True)):
        state = tuple("lost" if (k == 30 and j == 2) else "tracked" for j in range(17))
        oa, ob = a.filter(t, z, state), b.filter(t, z, state)
        np.testing.assert_array_equal(np.isnan(oa), np.isnan(ob))
        np.testing.assert_allclose(oa, ob, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(a.velocities(), b.velocities(), atol=1e-9, equal_nan=True)


@pytest.mark.parametrize("model", ["cv", "ca"])
def test_kalman_reduces_error_against_truth(model):
    rng = np.random.default_rng(1)
    times, truth, noisy = _noisy_run(rng)
    f = kalman_filter(model=model, measurement_std=0.02)
    out = np.array([f.filter(t, z) for t, z in zip(times, noisy, strict=True)])
    err = np.linalg.norm(out[20:] - truth[20:], axis=-1).mean()
    raw = np.linalg.norm(noisy[20:] - truth[20:], axis=-1).mean()
    assert err < 0.8 * raw


def test_kalman_predicts_a_lost_joint_along_its_velocity():
    f = kalman_filter(model="cv", max_predict=0.5)
    for k in range(30):
        z = np.zeros((17, 3))
        z[:, 0] = 1.0 * k / 30  # 1 m/s along x
        f.filter(k / 30, z)
    lost = np.full((17, 3), np.nan)
    out = f.filter(30 / 30, lost)
    assert out[0, 0] == pytest.approx(1.0, abs=0.05)
    assert f.velocities()[0, 0] == pytest.approx(1.0, abs=0.1)


def test_kalman_lost_joint_becomes_nan_after_max_predict_and_restarts_when_seen():
    f = kalman_filter(max_predict=0.2)
    f.filter(0.0, np.zeros((17, 3)))
    z = np.zeros((17, 3))
    z[4] = np.nan
    for k in range(1, 10):
        out = f.filter(k / 30, z)
    assert np.all(np.isnan(out[4])) and np.all(np.isfinite(out[0]))
    seen = np.zeros((17, 3))
    seen[4] = 2.0
    out = f.filter(10 / 30, seen)
    np.testing.assert_allclose(out[4], 2.0)


def test_kalman_gate_skips_a_single_outlier_but_follows_a_real_jump():
    f = kalman_filter(gate=4.0, max_rejections=3)
    for k in range(30):
        f.filter(k / 30, np.zeros((17, 3)))
    z = np.zeros((17, 3))
    z[6] = 1.0
    out = f.filter(30 / 30, z)
    assert np.abs(out[6]).max() < 0.05  # outlier ignored
    for k in range(31, 34):
        out = f.filter(k / 30, z)
    np.testing.assert_allclose(out[6], 1.0)  # persistent: re-initialized


def test_kalman_rejects_time_that_does_not_advance():
    f = kalman_filter()
    f.filter(0.5, np.zeros((17, 3)))
    with pytest.raises(TimestampError):
        f.filter(0.4, np.zeros((17, 3)))


@pytest.mark.parametrize(
    "kwargs",
    [{"model": "cj"}, {"measurement_std": 0}, {"accel_std": -1}, {"gate": 0},
     {"max_rejections": 0}, {"backend": "torch"}, {"bogus": 1}],
)
def test_kalman_factory_rejects_invalid_options(kwargs):
    with pytest.raises(ConfigError):
        kalman_filter(**kwargs)


def test_make_filter_builds_kalman_models():
    cv, ca = make_filter("kalman_cv"), make_filter("kalman_ca")
    assert isinstance(cv, KalmanJointFilter) and cv.options.model == "cv"
    assert isinstance(ca, KalmanJointFilter) and ca.options.model == "ca"
    with pytest.raises(ConfigError):
        make_filter("kalman_cv", model="ca")
