"""Specifications of the color-shirt color model and Mahalanobis classifier."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from colorshirt_paint import clutter, paint_shirt

from bodyplay.body.shirt import NUM_COLORS, SHIRT_COLORS
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt.colors import (
    ColorModel,
    default_color_model,
    srgb_color_model,
)


def test_fit_recovers_means_and_covariances_of_labeled_pixels() -> None:
    rng = np.random.default_rng(1)
    mus = np.array([c.rgb for c in SHIRT_COLORS], float)
    labels = np.repeat(np.arange(NUM_COLORS), 2000)
    pixels = mus[labels] + rng.normal(0, 6.0, size=(labels.size, 3))
    model = ColorModel.fit(pixels, labels)
    assert np.allclose(model.means, mus, atol=0.6)
    assert np.allclose(np.sqrt(np.diagonal(model.covariances, axis1=1, axis2=2)), 6.3, atol=0.5)


def test_fit_rejects_a_color_with_too_few_pixels() -> None:
    pixels = np.zeros((30, 3))
    with pytest.raises(ConfigError, match="red"):
        ColorModel.fit(pixels, np.full(30, 3))


def test_classify_labels_painted_shirt_and_leaves_far_pixels_unclassified() -> None:
    rng = np.random.default_rng(2)
    img = clutter(120, 160, rng)
    labels = paint_shirt(img, 20, 5, 20, rng)
    cls = srgb_color_model().classify(img, threshold=3.0)
    on = labels >= 0
    assert np.mean(cls.ids[on] == labels[on] + 1) > 0.98
    # a pure black and a saturated non-shirt color are far from every Gaussian
    probe = np.array([[[0, 0, 0], [0, 255, 255]]], np.uint8)
    assert srgb_color_model().classify(probe).ids.tolist() == [[0, 0]]


def test_classify_matches_the_vectorized_mahalanobis_distance() -> None:
    rng = np.random.default_rng(3)
    img = rng.integers(0, 256, size=(17, 23, 3), dtype=np.uint8)
    model = srgb_color_model()
    W = np.array([[1.1, 0.05, 0.0], [0.0, 0.9, 0.02], [0.01, 0.0, 1.3]])
    cls = model.classify(img, W, threshold=4.0)
    # the reference: the distances vectorized, with the kernel's float32 inverse factors
    linv = np.linalg.inv(np.linalg.cholesky(model.covariances)).astype(np.float32)
    diff = (img.reshape(-1, 3) @ W.T)[:, None, :] - model.means[None]
    z = np.einsum("kij,nkj->nki", linv.astype(np.float64), diff)
    d = np.sqrt(np.sum(z * z, axis=-1))
    best = d.min(axis=1).reshape(17, 23)
    expect = np.where(best < 4.0, d.argmin(axis=1).reshape(17, 23) + 1, 0)
    assert np.array_equal(cls.ids, expect)


def test_background_mask_suppresses_classification() -> None:
    rng = np.random.default_rng(4)
    img = clutter(60, 80, rng)
    paint_shirt(img, 0, 0, 12, rng)
    mask = np.zeros(img.shape[:2], bool)
    mask[:, :24] = True
    cls = srgb_color_model().classify(img, mask=mask)
    assert not cls.ids[:, 24:].any()
    assert cls.ids[:, :24].any()
    assert 0 < cls.fraction_classified(mask) <= 1


def test_classify_near_penalty_changes_the_winning_color() -> None:
    px = np.array([[SHIRT_COLORS[2].rgb]], np.uint8)  # yellow
    model = srgb_color_model()
    assert model.classify(px).ids[0, 0] == 3
    # every color's patch at the pixel, but yellow's 100 px away
    dists = np.zeros((NUM_COLORS, 1, 1), np.float32)
    dists[2] = 100.0
    patch = np.arange(1, NUM_COLORS + 1, dtype=np.uint8)
    color = np.arange(NUM_COLORS, dtype=np.int64)
    ids, owner = model.classify_near(px, None, 1e9, None, dists, patch, color, 1.0)
    assert ids[0, 0] not in (0, 3) and owner[0, 0] == ids[0, 0]
    assert model.classify_near(px, None, 5.0, None, dists, patch, color, 1.0)[0][0, 0] == 0
    # no patches: every color pays ``far``; 0 is the plain classification
    none = (np.zeros((0, 1, 1), np.float32), patch[:0], color[:0])
    assert model.classify_near(px, None, 5.0, None, *none, 1.0, far=0.0)[0][0, 0] == 3


def test_model_round_trips_through_json(tmp_path) -> None:  # type: ignore[no-untyped-def]
    model = srgb_color_model()
    back = ColorModel.load(model.save(tmp_path / "m.json"))
    assert np.allclose(back.means, model.means) and np.allclose(back.covariances, model.covariances)


def test_default_model_classifies_nominal_colors_as_themselves() -> None:
    model = default_color_model()
    px = np.array([[c.rgb for c in SHIRT_COLORS]], np.uint8)
    assert model.classify(px, threshold=5.0).ids[0].tolist() == list(range(1, NUM_COLORS + 1))


def test_invalid_models_and_images_are_rejected() -> None:
    with pytest.raises(ConfigError):
        ColorModel(np.zeros((3, 3)), np.zeros((3, 3, 3)))
    with pytest.raises(ConfigError):
        ColorModel(np.zeros((10, 3)), np.zeros((10, 3, 3)))
    with pytest.raises(ConfigError):
        srgb_color_model().classify(np.zeros((4, 4), np.uint8))


def test_measurement_noise_widens_classes_only_where_white_balance_amplifies() -> None:
    base = srgb_color_model(noise=4.0, shading=0.0)
    noisy = ColorModel(base.means, base.covariances, measurement_noise=6.0)
    identity = np.eye(3, dtype=np.float32)
    assert np.allclose(noisy.effective_inverse(identity), base.effective_inverse(identity))
    # a dark blue pixel whose blue channel was recorded 7 units off: after a 3x blue
    # gain it lands 21 units from the mean, beyond T = 3 of the fitted covariance
    W = np.diag([1.0, 1.0, 3.0]).astype(np.float32)
    k = [c.name for c in SHIRT_COLORS].index("blue")
    target = base.means[k]
    raw = np.linalg.solve(W.astype(float), target) + np.array([0.0, 0.0, 7.0])
    img = np.clip(np.round(raw), 0, 255).astype(np.uint8).reshape(1, 1, 3)
    assert base.classify(img, W, 3.0).ids[0, 0] == 0
    assert noisy.classify(img, W, 3.0).ids[0, 0] == k + 1
    # gains below 1 never shrink a class
    shrink = np.diag([0.5, 0.5, 0.5]).astype(np.float32)
    assert np.allclose(noisy.effective_inverse(shrink), base.effective_inverse(shrink))


def test_measurement_noise_must_be_non_negative() -> None:
    base = srgb_color_model()
    with pytest.raises(ConfigError, match="measurement_noise"):
        ColorModel(base.means, base.covariances, measurement_noise=-1.0)


def test_classify_near_penalizes_each_color_by_its_nearest_patch() -> None:
    rng = np.random.default_rng(7)
    img = clutter(60, 56, rng)
    paint_shirt(img, 4, 4, 10, rng)
    model = dataclasses.replace(default_color_model(), measurement_noise=6.0)
    W = np.array([[1.1, 0.02, 0.0], [0.0, 0.95, 0.03], [0.01, 0.0, 1.2]])
    mask = rng.random(img.shape[:2]) > 0.2
    # patches 1..6 of colors (0, 0, 3, 5, 5, 9), with ties between a color's two maps
    patch = np.array([1, 2, 3, 4, 5, 6], np.uint8)
    color = np.array([0, 0, 3, 5, 5, 9], np.int64)
    dists = rng.integers(0, 30, size=(6, 60, 56)).astype(np.float32) * np.float32(0.5)
    strength = 0.37
    ids, owner = model.classify_near(img, W, 5.0, mask, dists, patch, color, strength)
    # the reference: one map per color, its patches' least distance, and each
    # color's nearer patch
    near = np.zeros((60, 56, NUM_COLORS), np.uint8)
    least = []
    for k in np.unique(color):
        js = np.nonzero(color == k)[0]
        least.append(dists[js].min(axis=0))
        near[..., k] = patch[js][np.argmax(dists[js] == least[-1][None], axis=0)]
    kinds = np.unique(color)
    ref = model.classify_near(img, W, 5.0, mask, np.stack(least), (kinds + 1).astype(np.uint8),
                              kinds, strength)[0]
    assert ids.any() and np.array_equal(ids, ref)
    k = np.maximum(ref.astype(np.int64) - 1, 0)
    want = np.where(ref > 0, np.take_along_axis(near, k[..., None], axis=2)[..., 0], 0)
    assert np.array_equal(owner, want)

