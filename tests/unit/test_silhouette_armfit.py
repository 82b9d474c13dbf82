"""Specifications of the per-arm refinement of the silhouette tracker (armfit)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.armfit import ArmFitter, arm_atlas
from bodyplay.trackers.silhouette.distance import distance_maps
from bodyplay.trackers.silhouette.options import SilhouetteOptions
from bodyplay.trackers.silhouette.window import WindowGeometry

L_WRIST, R_WRIST = 7, 10


def _pose(skeleton, left_z: float, right_z: float):  # type: ignore[no-untyped-def]
    """The rest pose with the shoulders turned about +z (left: -1.4 down, +1.2 up;
    right: the opposite signs)."""
    q = skeleton.rest_pose().copy()
    q[3 + 3 * skeleton.node_index("l_shoulder") + 2] = left_z
    q[3 + 3 * skeleton.node_index("r_shoulder") + 2] = right_z
    q[3 + 3 * skeleton.node_index("l_elbow") + 1] = -0.3
    q[3 + 3 * skeleton.node_index("r_elbow") + 1] = 0.3
    return skeleton.clamp(q[None])[0]


def _setup(skeleton, tree_pose, seen_pose):  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.templates import render_templates

    geo = WindowGeometry()
    r = render_templates(skeleton, np.stack([tree_pose, seen_pose]), geo, levels=(1,))
    masks = r.runs[0].masks()
    origin = tree_pose[0:3] - r.offset[0]
    # the seen pose drawn where the tree's pose stands (same anchor)
    seen_shift = r.offset[0] - r.offset[1]
    assert np.allclose(seen_shift, 0.0, atol=0.02)  # both stand on the same feet
    cost = distance_maps(masks[1], beta=5.0).cost
    reference = skeleton.joint_positions(tree_pose) - origin
    return geo, masks[0], cost, origin, reference


@pytest.fixture(scope="module")
def atlas(skeleton):  # type: ignore[no-untyped-def]
    return arm_atlas(skeleton, [], 1000, np.random.default_rng(0))  # the tracker's size


def test_arm_atlas_spreads_its_arms_over_where_elbow_and_wrist_can_be(skeleton) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.body.joints import JOINT_INDEX

    rng = np.random.default_rng(1)
    arms = arm_atlas(skeleton, [], 40, rng, candidates=2000)
    cols = np.concatenate([np.arange(3 + 3 * skeleton.node_index(n), 6 + 3 * skeleton.node_index(n))
                           for n in ("l_clavicle", "l_shoulder", "l_elbow", "l_wrist")])

    def places(a):  # type: ignore[no-untyped-def]
        q = np.tile(skeleton.rest_pose(), (len(a), 1))
        q[:, cols] = a
        J = skeleton.joint_positions(q)
        return np.concatenate([J[:, JOINT_INDEX["l_elbow"]], J[:, JOINT_INDEX["l_wrist"]]], axis=1)

    assert arms.shape == (40, len(cols))
    q = np.tile(skeleton.rest_pose(), (40, 1))
    q[:, cols] = arms
    assert skeleton.within_limits(q).all()
    probe = places(arm_atlas(skeleton, [], 400, np.random.default_rng(2), candidates=400))
    spread = places(arms)
    lucky = places(arm_atlas(skeleton, [], 40, np.random.default_rng(3), candidates=40))

    def worst_gap(p):  # type: ignore[no-untyped-def]
        return np.linalg.norm(probe[:, None] - p[None], axis=2).min(axis=1).max()

    # farthest-point selection leaves a smaller worst gap than 40 random arms
    assert worst_gap(spread) < worst_gap(lucky)
    with pytest.raises(ConfigError):
        arm_atlas(skeleton, [], 0, rng)


def test_arm_fitter_raises_the_arm_the_silhouette_shows_raised(skeleton, atlas) -> None:  # type: ignore[no-untyped-def]
    down = _pose(skeleton, -1.4, 1.4)
    raised = _pose(skeleton, 1.2, 1.4)  # the left arm up, the right arm still down
    geo, tmpl, cost, origin, ref = _setup(skeleton, down, raised)
    want = skeleton.joint_positions(raised)
    before = np.linalg.norm(skeleton.joint_positions(down)[L_WRIST] - want[L_WRIST])
    fitter = ArmFitter(skeleton, geo, atlas, stay=3.0, margin=100.0)
    cols = fitter.cols[0]
    # with the seen arm in the atlas, the silhouette alone (stay 0) finds it up to
    # what a silhouette cannot tell: depth, and 1.8 cm pixels
    exact = ArmFitter(skeleton, geo, np.vstack([atlas, raised[cols]]), stay=0.0, margin=100.0)
    fit = exact.fit(down, origin, tmpl, cost, (0.0, 0.0), ref)
    assert fit.replaced == (True, False)
    got = skeleton.joint_positions(fit.pose)
    assert np.linalg.norm((got[L_WRIST] - want[L_WRIST])[:2]) < 0.1
    np.testing.assert_allclose(got[R_WRIST], want[R_WRIST])
    # without it, the nearest atlas arm (about 15 cm apart in the atlas) gets it much nearer
    fit = fitter.fit(down, origin, tmpl, cost, (0.0, 0.0), ref)
    assert fit.replaced == (True, False)
    got = skeleton.joint_positions(fit.pose)
    assert before > 0.9 and np.linalg.norm(got[L_WRIST] - want[L_WRIST]) < 0.6 * before


def test_arm_fitter_keeps_the_arms_the_silhouette_agrees_with(skeleton, atlas) -> None:  # type: ignore[no-untyped-def]
    pose = _pose(skeleton, 0.3, -0.2)  # arms out to the sides
    geo, tmpl, cost, origin, ref = _setup(skeleton, pose, pose)
    fit = ArmFitter(skeleton, geo, atlas, stay=3.0, margin=100.0).fit(
        pose, origin, tmpl, cost, (0.0, 0.0), ref)
    assert fit.replaced == (False, False)
    np.testing.assert_array_equal(fit.pose, pose)


def test_silhouette_options_reject_negative_arm_settings() -> None:
    for bad in ({"arm_candidates": -1}, {"arm_stay": -1.0}, {"arm_margin": -5.0}):
        with pytest.raises(ConfigError):
            SilhouetteOptions(**bad)  # type: ignore[arg-type]


def _plain_capsule_costs(pts: np.ndarray, radii: np.ndarray, cost: np.ndarray,
                         body: np.ndarray, out: np.ndarray) -> None:
    """Every candidate's sum with no skipping: the kernel's own per-candidate steps
    (``_capsule_setup``, ``_capsule_sum``), 1e9 where a point is not finite."""
    from bodyplay.trackers.silhouette.armfit import _capsule_setup, _capsule_sum

    h, w = cost.shape
    box, sa = np.empty(4, np.int64), np.empty((3, 6))
    bx0, bx1, by0, by1 = (np.empty(3, np.int64) for _ in range(4))
    for k in range(len(pts)):
        if _capsule_setup(pts, k, radii, h, w, box, bx0, bx1, by0, by1, sa):
            out[k] = _capsule_sum(box, bx0, bx1, by0, by1, sa, cost, body)
        else:
            out[k] = 1e9


def test_capsule_costs_sum_every_pixel_a_capsule_covers_outside_the_body() -> None:
    """The kernel skips pixels outside each segment's box; the sums must equal a plain
    test of every pixel of the image against the three capsules."""
    rng = np.random.default_rng(3)
    h, w = 120, 160
    cost = rng.normal(0.0, 1.0, (h, w))
    body = (rng.random((h, w)) < 0.3).astype(np.uint8)
    pts = rng.uniform(-10.0, 170.0, (40, 4, 2))
    pts[:, :, 1] *= 0.75
    pts[5, 2] = pts[5, 1]  # a segment of length zero
    radii = np.array([5.0, 4.0, 3.5])
    out = np.empty(len(pts))
    _plain_capsule_costs(pts, radii, cost, body, out)
    ys, xs = np.mgrid[0:h, 0:w]
    for k in range(len(pts)):
        inside = np.zeros((h, w), bool)
        for j in range(3):
            a, b = pts[k, j], pts[k, j + 1]
            d = b - a
            ll = float(d @ d)
            along = ((xs - a[0]) * d[0] + (ys - a[1]) * d[1]) / max(ll, 1e-12)
            t = np.zeros((h, w)) if ll <= 1e-12 else np.clip(along, 0, 1)
            inside |= (xs - a[0] - t * d[0]) ** 2 + (ys - a[1] - t * d[1]) ** 2 <= radii[j] ** 2
        expected = cost[inside & (body == 0)].sum()
        assert out[k] == pytest.approx(expected, rel=1e-9, abs=1e-9)


def test_bounded_capsule_costs_skip_only_arms_that_cannot_be_the_cheapest() -> None:
    """The bounded kernel gives every candidate it scores the plain kernel's very sum,
    skips (inf) only candidates dearer than the cheapest, and so picks the same arm."""
    from bodyplay.trackers.silhouette.armfit import _capsule_costs_bounded

    rng = np.random.default_rng(5)
    h, w = 120, 160
    cost = np.where(rng.random((h, w)) < 0.2, -rng.random((h, w)) * 5.0,
                    rng.random((h, w)) * 20.0)
    body = (rng.random((h, w)) < 0.2).astype(np.uint8)
    negative = np.zeros((h, w + 1))
    np.cumsum(np.where(body > 0, 0.0, np.minimum(cost, 0.0)), axis=1, out=negative[:, 1:])
    shoulder = rng.uniform([40.0, 30.0], [120.0, 90.0], (300, 1, 2))
    pts = shoulder + np.cumsum(rng.normal(0.0, 12.0, (300, 4, 2)), axis=1) - rng.normal(
        0.0, 12.0, (300, 1, 2))
    pts[7, 1] = np.nan  # a candidate that cannot be drawn
    radii = np.array([2.8, 2.2, 1.9])
    extra = 3.0 * np.linalg.norm(pts[:, 1:] - pts[:1, 1:], axis=2).sum(axis=1)
    extra[7] = 0.0
    plain, bounded = np.empty(len(pts)), np.empty(len(pts))
    _plain_capsule_costs(pts, radii, cost, body, plain)
    _capsule_costs_bounded(pts, radii, cost, body, extra, np.argsort(extra, kind="stable"),
                           negative, bounded)
    scored = np.isfinite(bounded)
    assert 0 < scored.sum() < len(pts)  # it does skip, and scores some
    np.testing.assert_array_equal(bounded[scored], plain[scored])
    best = np.min(plain + extra)
    assert np.all(plain[~scored] + extra[~scored] > best)
    assert np.argmin(bounded + extra) == np.argmin(plain + extra)
