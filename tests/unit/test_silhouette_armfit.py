"""Specifications of the per-arm refinement of the silhouette tracker (armfit)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.armfit import ARM_BODIES, ArmFitter, arm_atlas
from bodyplay.trackers.silhouette.armless import ArmlessBody
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


def _armless(skeleton, geo, pose, origin, body):  # type: ignore[no-untyped-def]
    """The body the arms are scored against at the fitter's level (None: the template
    less the arms' capsules)."""
    return ArmlessBody(skeleton, geo, level=1).mask(pose, origin) if body == "torso" else None


@pytest.mark.parametrize("body", ARM_BODIES)
def test_arm_fitter_raises_the_arm_the_silhouette_shows_raised(skeleton, atlas, body) -> None:  # type: ignore[no-untyped-def]
    down = _pose(skeleton, -1.4, 1.4)
    raised = _pose(skeleton, 1.2, 1.4)  # the left arm up, the right arm still down
    geo, tmpl, cost, origin, ref = _setup(skeleton, down, raised)
    armless = _armless(skeleton, geo, down, origin, body)
    want = skeleton.joint_positions(raised)
    before = np.linalg.norm(skeleton.joint_positions(down)[L_WRIST] - want[L_WRIST])
    fitter = ArmFitter(skeleton, geo, atlas, stay=3.0, margin=100.0, body=body)
    cols = fitter.cols[0]
    # with the seen arm in the atlas, the silhouette alone (stay 0) finds it up to
    # what a silhouette cannot tell: depth, and 1.8 cm pixels
    exact = ArmFitter(skeleton, geo, np.vstack([atlas, raised[cols]]), stay=0.0, margin=100.0,
                      body=body)
    fit = exact.fit(down, origin, tmpl, cost, (0.0, 0.0), ref, armless)
    assert fit.replaced == (True, False)
    got = skeleton.joint_positions(fit.pose)
    assert np.linalg.norm((got[L_WRIST] - want[L_WRIST])[:2]) < 0.1
    np.testing.assert_allclose(got[R_WRIST], want[R_WRIST])
    # without it, the nearest atlas arm (about 15 cm apart in the atlas) gets it much nearer
    fit = fitter.fit(down, origin, tmpl, cost, (0.0, 0.0), ref, armless)
    assert fit.replaced == (True, False)
    got = skeleton.joint_positions(fit.pose)
    assert before > 0.9 and np.linalg.norm(got[L_WRIST] - want[L_WRIST]) < 0.6 * before


@pytest.mark.parametrize("body", ARM_BODIES)
def test_arm_fitter_keeps_the_arms_the_silhouette_agrees_with(skeleton, atlas, body) -> None:  # type: ignore[no-untyped-def]
    pose = _pose(skeleton, 0.3, -0.2)  # arms out to the sides
    geo, tmpl, cost, origin, ref = _setup(skeleton, pose, pose)
    fit = ArmFitter(skeleton, geo, atlas, stay=3.0, margin=100.0, body=body).fit(
        pose, origin, tmpl, cost, (0.0, 0.0), ref, _armless(skeleton, geo, pose, origin, body))
    assert fit.replaced == (False, False)
    np.testing.assert_array_equal(fit.pose, pose)


def _across_the_torso(skeleton):  # type: ignore[no-untyped-def]
    """The left arm hanging in front of the torso, its forearm across the belly; the
    right arm down at the side."""
    q = _pose(skeleton, -1.4, 1.4).copy()
    q[3 + 3 * skeleton.node_index("l_shoulder")] = 0.8
    q[3 + 3 * skeleton.node_index("l_shoulder") + 1] = -1.0
    q[3 + 3 * skeleton.node_index("l_elbow") + 1] = -1.2
    return skeleton.clamp(q[None])[0]


def _refined(skeleton, atlas, tree_pose, seen_pose, **kwargs):  # type: ignore[no-untyped-def]
    """The tracker's call: ``tree_pose`` the MAP leaf (and the reported pose) at the
    origin of a level-3 window, ``seen_pose`` the observed silhouette; the reported
    joints after the refinement."""
    from bodyplay.trackers.silhouette.templates import render_templates

    geo = WindowGeometry()
    r = render_templates(skeleton, np.stack([tree_pose, seen_pose]), geo, levels=(1, 2))
    origin = tree_pose[0:3] - r.offset[0]
    cost = distance_maps(r.runs[0].masks()[1], beta=5.0).cost
    joints = skeleton.joint_positions(tree_pose) - origin
    fitter = ArmFitter(skeleton, geo, atlas, stay=3.0, margin=100.0, **kwargs)
    got, _ = fitter.refine_reported(tree_pose, r.offset[0], r.runs[1].masks()[0], (0, 0), cost,
                                    joints, tree_pose, np.eye(3), np.zeros(3))
    return got


def test_a_raised_arm_is_raised_beside_a_torso_the_tree_hangs_that_arm_in_front_of(  # type: ignore[no-untyped-def]
        skeleton, atlas) -> None:
    tree = _across_the_torso(skeleton)
    raised = _pose(skeleton, 1.2, 1.4)
    want = skeleton.joint_positions(raised)[L_WRIST] - skeleton.joint_positions(tree)[0]
    got = _refined(skeleton, atlas, tree, raised)
    assert np.linalg.norm(got[L_WRIST] - got[0] - want) < 0.3
    # scored against the template less the arms' capsules, the tree's arm is credited
    # with the torso it hides and outweighs the raised arm's fit
    kept = _refined(skeleton, atlas, tree, raised, body="template")
    assert np.linalg.norm(kept[L_WRIST] - kept[0] - want) > 0.8


def test_an_arm_across_the_torso_the_silhouette_shows_is_kept(skeleton, atlas) -> None:  # type: ignore[no-untyped-def]
    tree = _across_the_torso(skeleton)
    got = _refined(skeleton, atlas, tree, tree)
    geo = WindowGeometry()
    from bodyplay.trackers.silhouette.templates import render_templates

    origin = tree[0:3] - render_templates(skeleton, tree[None], geo, levels=(2,)).offset[0]
    np.testing.assert_array_equal(got, skeleton.joint_positions(tree) - origin)


def test_armless_body_is_the_template_without_the_arms(skeleton) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.body.joints import JOINT_INDEX
    from bodyplay.trackers.silhouette.templates import render_templates

    geo = WindowGeometry()
    pose = _pose(skeleton, 0.3, -1.4)  # the left arm out to the side, the right one down
    r = render_templates(skeleton, pose[None], geo, levels=(2,))
    full = r.runs[0].masks()[0] > 0
    origin = pose[0:3] - r.offset[0]
    armless = ArmlessBody(skeleton, geo).mask(pose, origin) > 0
    assert armless.shape == full.shape
    assert not np.any(armless & ~full)  # nothing the template does not hold
    view = geo.template_view(2)
    J = skeleton.joint_positions(pose) - origin
    px = np.round(view.project(J, distort=False)).astype(int)
    for j, on in (("l_wrist", False), ("l_elbow", False), ("head", True), ("pelvis", True),
                  ("l_knee", True), ("r_ankle", True)):
        x, y = px[JOINT_INDEX[j]]
        assert full[y, x] and armless[y, x] == on, j
    # the arms are all it leaves out: about a sixth of the template
    assert 0.75 < armless.sum() / full.sum() < 0.92


def test_silhouette_options_reject_negative_arm_settings() -> None:
    for bad in ({"arm_candidates": -1}, {"arm_stay": -1.0}, {"arm_margin": -5.0},
                {"arm_body": "hole"}):
        with pytest.raises(ConfigError):
            SilhouetteOptions(**bad)  # type: ignore[arg-type]


def test_arm_fitter_refuses_an_unknown_body(skeleton, atlas) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError):
        ArmFitter(skeleton, WindowGeometry(), atlas, body="hole")


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


def test_silhouette_along_the_torsos_outline_credits_no_arm(skeleton, atlas) -> None:  # type: ignore[no-untyped-def]
    """The torso's own misfit (silhouette just outside the body without its arms)
    is not taken by an arm; silhouette beyond it is."""
    import cv2

    from bodyplay.trackers.silhouette.armfit import MISFIT_BAND

    pose = _pose(skeleton, 0.3, -0.2)  # arms out to the sides, over background
    geo, tmpl, _, origin, ref = _setup(skeleton, pose, pose)
    body = ArmlessBody(skeleton, geo, level=1).mask(pose, origin)
    band = int(round(MISFIT_BAND / geo.mpp(1)))

    def ring(inner: int, outer: int) -> np.ndarray:
        def grown(r: int) -> np.ndarray:
            disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
            return cv2.dilate(body, disc) > 0
        return grown(outer) & ~(grown(inner) if inner else body > 0)

    def best_data_term(silhouette: np.ndarray) -> float:
        cost = np.where(silhouette, -20.0, 5.0).astype(np.float32)  # background dear
        fitter = ArmFitter(skeleton, geo, atlas, stay=3.0, margin=100.0)
        fitter.debug = []
        fitter.fit(pose, origin, tmpl, cost, (0.0, 0.0), ref, body)
        return min(float(d[5]) for d in fitter.debug)  # the best arm's sum, either side

    assert band == 2
    assert best_data_term(ring(0, band)) >= 0.0  # no arm is credited with any of it
    assert best_data_term(ring(band, 2 * band + 1)) < -100.0
