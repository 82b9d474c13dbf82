"""Specifications of the arm search: each arm chosen from a library by the classified pixels."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt import ColorShirtOptions
from bodyplay.trackers.colorshirt.armsearch import (
    ARM_ONLY_COLORS,
    ArmSearch,
    ArmView,
    arm_library,
    color_distance_maps,
)
from bodyplay.trackers.colorshirt.prediction import CropWindow, PoseRenderer

SK = Skeleton()
REN = PoseRenderer(SK)
WINDOW = CropWindow(160.0, 40.0, 0.4, 128, 160)


def _cams() -> tuple[Camera, ...]:
    out = []
    for i, x in enumerate((-0.6, 0.6)):
        R, t = look_at((x, 1.2, 3.0), (0, 1.1, 0))
        out.append(Camera.from_fov(f"cam{i}", 640, 480, 60, R, t))
    return tuple(out)


def _arms(l_shoulder: tuple[float, ...], l_bend: float,
          r_shoulder: tuple[float, ...], r_bend: float) -> np.ndarray:
    """Upright body at the origin; elbows bent by ``*_bend`` radians."""
    return SK.pose(root=(0.0, 0.95, 0.0), rotations={
        "l_shoulder": l_shoulder, "l_elbow": (0.0, -l_bend, 0.0),
        "r_shoulder": r_shoulder, "r_elbow": (0.0, r_bend, 0.0),
    })


GUARD = _arms((0.0, 0.0, 1.1), 2.0, (0.0, 0.0, -1.1), 0.05)
"""Left forearm up in front of the chest, right arm hanging."""
SPREAD = _arms((0.0, 0.0, 0.2), 0.0, (0.0, 0.0, -0.2), 0.0)
"""Both arms out to the sides."""


def _library(extra: list[np.ndarray]) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(3)
    poses = [SPREAD]
    for _ in range(60):
        poses.append(_arms(tuple(rng.uniform(-1.0, 1.0, 3)), float(rng.uniform(0.0, 2.4)),
                           tuple(rng.uniform(-1.0, 1.0, 3)), float(rng.uniform(0.0, 2.4))))
    P = np.array(poses + extra)
    return {"l": P, "r": P}


def _views(q: np.ndarray, cams: tuple[Camera, ...]) -> list[ArmView]:
    out = []
    for i, cam in enumerate(cams):
        ids = REN.render(REN.vertices(q), cam, WINDOW).color_ids()
        ys, xs = np.nonzero(ids)
        extent = float(max(np.ptp(xs), np.ptp(ys)))
        out.append(ArmView.from_ids(i, WINDOW, ids, 0.15 * extent))
    return out


def _arm_error(a: np.ndarray, b: np.ndarray) -> float:
    """Largest elbow or wrist distance, metres."""
    idx = [6, 7, 9, 10]
    return float(np.abs(SK.joint_positions(a)[idx] - SK.joint_positions(b)[idx]).max())


def test_search_replaces_wrong_arms_by_the_library_arms_that_match_the_pixels() -> None:
    cams = _cams()
    search = ArmSearch(SK, REN.mesh, _library([GUARD]))
    assert _arm_error(SPREAD, GUARD) > 0.3
    q, choices = search.search(SPREAD, cams, _views(GUARD, cams), temperature=0.0)
    assert _arm_error(q, GUARD) < 0.02
    assert {c.side for c in choices} == {"l", "r"}
    assert all(c.index >= 0 and c.score < c.kept_score for c in choices)


def test_search_keeps_the_blends_arms_when_they_already_explain_the_pixels() -> None:
    cams = _cams()
    search = ArmSearch(SK, REN.mesh, _library([]))  # GUARD itself is not in the library
    q, choices = search.search(GUARD, cams, _views(GUARD, cams), temperature=0.0)
    assert _arm_error(q, GUARD) < 1e-6
    assert [c.index for c in choices] == [-1, -1]


def test_search_leaves_the_torso_and_the_root_alone() -> None:
    cams = _cams()
    search = ArmSearch(SK, REN.mesh, _library([GUARD]))
    q, _ = search.search(SPREAD, cams, _views(GUARD, cams))
    for name in ("pelvis", "spine", "chest", "neck", "head"):
        j = ["pelvis", "spine", "chest", "neck", "head"].index(name)
        assert np.allclose(SK.joint_positions(q)[j], SK.joint_positions(SPREAD)[j])


def test_search_offers_the_previous_frames_arms_as_a_candidate() -> None:
    cams = _cams()
    search = ArmSearch(SK, REN.mesh, _library([]))
    q, choices = search.search(SPREAD, cams, _views(GUARD, cams), previous=GUARD,
                               temperature=0.0)
    assert _arm_error(q, GUARD) < 1e-6
    assert [c.index for c in choices] == [-2, -2]


def test_small_depth_pull_still_lets_the_pixels_replace_arms_of_another_outline() -> None:
    cam = _cams()[:1]
    search = ArmSearch(SK, REN.mesh, _library([GUARD]))
    q, choices = search.search(SPREAD, cam, _views(GUARD, cam), temperature=0.0, pull=0.01)
    assert _arm_error(q, GUARD) < 0.02
    assert all(c.index >= 0 for c in choices)


def test_strong_depth_pull_keeps_the_blends_arms_whatever_the_pixels_show() -> None:
    cam = _cams()[:1]
    search = ArmSearch(SK, REN.mesh, _library([GUARD]))
    q, choices = search.search(SPREAD, cam, _views(GUARD, cam), temperature=0.0, pull=100.0)
    assert _arm_error(q, SPREAD) < 1e-6
    assert [c.index for c in choices] == [-1, -1]


def test_search_without_views_returns_the_pose_unchanged() -> None:
    search = ArmSearch(SK, REN.mesh, _library([]))
    q, choices = search.search(GUARD, _cams(), [])
    assert np.array_equal(q, GUARD) and choices == []


def test_arm_library_spreads_the_arms_it_keeps() -> None:
    P = _library([GUARD])["l"]
    lib = arm_library(SK, P, 10)
    assert lib["l"].shape == (10, SK.pose_dim) and lib["r"].shape == (10, SK.pose_dim)
    wrists = SK.joint_positions(lib["l"])[:, 7]
    gaps = np.linalg.norm(wrists[:, None] - wrists[None], axis=2) + np.eye(10)
    assert gaps.min() > 0.05
    assert len(arm_library(SK, P[:4], 10)["r"]) == 4


def test_arm_view_keeps_a_sample_of_the_arm_only_pixels() -> None:
    ids = np.zeros((100, 100), np.uint8)
    ids[:50] = ARM_ONLY_COLORS[0] + 1
    ids[50:] = 1  # a torso color
    v = ArmView.from_ids(0, WINDOW, ids, 8.0, max_pixels=100)
    assert len(v.arm_pixels) == 100
    assert set(v.arm_pixels[:, 2].astype(int)) == {ARM_ONLY_COLORS[0]}
    assert v.arm_pixels[:, 1].max() < 50


def test_color_distance_maps_measure_pixels_to_the_nearest_pixel_of_each_color() -> None:
    ids = np.zeros((20, 30), np.uint8)
    ids[5, 10] = 3
    d = color_distance_maps(ids)
    assert d[2, 5, 10] == 0 and abs(d[2, 5, 20] - 10) < 0.5
    assert d[0].min() > 1000  # no pixel of color 0
    assert color_distance_maps(ids, (0,))[2].min() > 1000  # color 2 not asked for


@pytest.mark.parametrize("field, value", [("arm_library", 0), ("arm_tau", 0.0),
                                          ("arm_tau", float("nan")),
                                          ("arm_temperature", -0.1), ("arm_shortlist", 0),
                                          ("arm_depth_pull", -0.01),
                                          ("plate_mask_alone_cameras", -1),
                                          ("arm_depth_pull", float("inf"))])
def test_options_reject_arm_search_settings_out_of_range(field: str, value: float) -> None:
    with pytest.raises(ConfigError, match=field):
        ColorShirtOptions(**{field: value})  # type: ignore[arg-type]


def test_image_to_model_distance_is_the_nearest_visible_point_of_the_pixels_color() -> None:
    from bodyplay.trackers.colorshirt.armsearch import _group_by_color, _nearest_same_color

    rng = np.random.default_rng(5)
    uv = rng.random((6, 40, 2)) * 50.0
    vis = rng.random((6, 40)) < 0.5
    color = rng.integers(0, 10, 40)
    obs = np.column_stack([rng.random(30) * 50.0, rng.random(30) * 50.0,
                           rng.integers(0, 10, 30)]).astype(np.float64)
    tau = 8.0
    got = _nearest_same_color(uv, vis, *_group_by_color(color), obs, tau)
    want = np.full((6, 30), tau)
    for c in range(6):
        for o in range(30):
            pts = uv[c][vis[c] & (color == obs[o, 2])]
            if len(pts):
                want[c, o] = min(tau, float(np.sqrt(((pts - obs[o, :2]) ** 2).sum(axis=1)).min()))
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
