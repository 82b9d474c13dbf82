"""Specifications of the white balance: least squares, scribbles, auto, references."""

from __future__ import annotations

import numpy as np
import pytest
from colorshirt_paint import clutter, paint_shirt

from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt.colors import default_color_model, srgb_color_model
from bodyplay.trackers.colorshirt.whitebalance import (
    ReferenceIlluminations,
    auto_white_balance,
    classification_score,
    fit_white_balance,
    white_balance_from_ids,
    white_balance_from_scribbles,
)


def _accuracy(model, img, labels, W, threshold=3.0):  # type: ignore[no-untyped-def]
    cls = model.classify(img, W, threshold)
    on = labels >= 0
    return float(np.mean(cls.ids[on] == labels[on] + 1))


def test_least_squares_recovers_a_known_color_transform() -> None:
    model = srgb_color_model()
    A = np.array([[1.3, 0.1, 0.0], [0.05, 0.9, 0.0], [0.0, 0.1, 0.55]])
    observed = model.means @ A.T
    W = fit_white_balance(observed, model.means, ridge=1e-6)
    assert np.allclose(W, np.linalg.inv(A), atol=1e-4)


def test_ridge_keeps_white_balance_near_the_prior_with_two_colors() -> None:
    model = srgb_color_model()
    W = fit_white_balance(model.means[:2] * 0.9, model.means[:2], prior=np.eye(3))
    assert np.all(np.isfinite(W)) and np.linalg.norm(W - np.eye(3)) < 0.5


def test_scribbles_white_balance_a_tungsten_image() -> None:
    rng = np.random.default_rng(5)
    model = srgb_color_model()
    img = clutter(200, 200, rng)
    labels = paint_shirt(img, 20, 10, 30, rng, gains=(1.25, 0.9, 0.5))
    assert _accuracy(model, img, labels, np.eye(3)) < 0.6
    scribbles = np.full(labels.shape, -1)
    scribbles[::7, ::7] = labels[::7, ::7]  # coarse dots on every patch
    W = white_balance_from_scribbles(img, scribbles, model)
    assert _accuracy(model, img, labels, W) > 0.97


def test_scribbles_on_fewer_than_three_colors_are_rejected() -> None:
    img = np.zeros((10, 10, 3), np.uint8)
    s = np.full((10, 10), -1)
    s[0, :5] = 1
    with pytest.raises(ConfigError, match="three"):
        white_balance_from_scribbles(img, s, srgb_color_model())


def test_refit_from_id_map_needs_enough_colors() -> None:
    img = np.full((10, 10, 3), 100, np.uint8)
    ids = np.zeros((10, 10), np.uint8)
    ids[:5] = 1
    assert white_balance_from_ids(img, ids, srgb_color_model()) is None


@pytest.mark.parametrize("gains", [(1.3, 0.95, 0.55), (0.75, 1.0, 1.35), (0.45, 0.45, 0.45)])
def test_auto_white_balance_recovers_classification_without_scribbles(gains) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(6)
    model = srgb_color_model()
    img = clutter(200, 200, rng)
    labels = paint_shirt(img, 20, 10, 30, rng, gains=gains)
    crop = img[:170, :150]
    W = auto_white_balance(crop, model)
    # the shirt covers 71% of the crop
    assert classification_score(model.classify(crop, W).ids) > 0.65
    assert _accuracy(model, img, labels, W) > 0.95


def test_auto_white_balance_in_view_does_not_paint_a_large_room_region_a_shirt_color() -> None:
    # a player in view (no room mask) before a dusk sky, dark grey-blue, 45% of the
    # window: a W that paints the sky one shirt color must not win over the shirt's
    # own colors (draw 1's wave-both-hands lost its arms so)
    rng = np.random.default_rng(8)
    model = default_color_model()
    img = clutter(100, 100, rng)
    labels = paint_shirt(img, 5, 25, 10, rng)  # 20% of the window
    sky = np.array([30, 60, 65]) + rng.normal(0, 3, size=(100, 45, 3))
    img[:, 55:] = np.clip(sky, 0, 255).astype(np.uint8)
    W = auto_white_balance(img, model)
    assert np.mean(model.classify(img, W).ids[:, 55:] > 0) < 0.05
    assert _accuracy(model, img, labels, W) > 0.95


def test_classification_score_caps_each_color() -> None:
    ids = np.ones((10, 10), np.uint8)
    assert classification_score(ids) == pytest.approx(0.1)
    ids = (np.arange(100) % 10 + 1).astype(np.uint8).reshape(10, 10)
    assert classification_score(ids) == pytest.approx(1.0)
    assert classification_score(ids, cap=0.05) == pytest.approx(0.5)


def test_reference_illuminations_store_only_distinct_matrices_and_pick_the_best() -> None:
    refs = ReferenceIlluminations()
    assert refs.add(np.eye(3))
    assert not refs.add(np.eye(3) * 1.1)  # Frobenius distance 0.17
    tungsten_W = np.diag([1 / 1.3, 1 / 0.95, 1 / 0.55])
    assert refs.add(tungsten_W)
    assert len(refs.matrices) == 2
    rng = np.random.default_rng(7)
    model = srgb_color_model()
    img = clutter(200, 200, rng)
    labels = paint_shirt(img, 20, 10, 30, rng, gains=(1.3, 0.95, 0.55))
    best = refs.best(img, model, labels >= 0, 3.0)
    assert best is not None and np.allclose(best[0], tungsten_W)
    assert best[1].fraction_classified(labels >= 0) > 0.9
