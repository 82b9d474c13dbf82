"""Specifications of the start-up body-preset choice (``ColorShirtOptions(body="auto")``)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from colorshirt_paint import clutter, webcam_rig

from bodyplay.body import Skeleton
from bodyplay.body.mesh import body_mesh
from bodyplay.body.shirt import patch_colors_rgb
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import Frame, FrameSet
from bodyplay.errors import ConfigError
from bodyplay.motion import sample_poses
from bodyplay.render.idmap import render_idmaps
from bodyplay.trackers.colorshirt import (
    ColorShirtOptions,
    DatabaseOptions,
    create_colorshirt_tracker,
)
from bodyplay.trackers.colorshirt.bodyselect import (
    ARM_SCALES,
    BodySelection,
    arm_variants,
    with_arm_scale,
)
from bodyplay.trackers.colorshirt.database import build_database

REF = Skeleton.from_shape("m")


@pytest.fixture(scope="module")
def db():  # type: ignore[no-untyped-def]
    poses = sample_poses(REF, 2000, np.random.default_rng(0), yaw_range=(-1.3, 1.3))
    return build_database(REF, DatabaseOptions(size=2000), poses)


def _capture(shape: str, n: int, cams: tuple[Camera, ...], arms: float = 1.0
             ) -> list[FrameSet]:
    """``n`` frame sets of a person of preset ``shape`` (arms ``arms`` times as long)
    moving from one pose to another."""
    sk = with_arm_scale(Skeleton.from_shape(shape), arms)
    mesh = body_mesh(sk)
    q0, q1 = sample_poses(sk, 2, np.random.default_rng(5), mode="clips",
                          yaw_range=(-0.4, 0.4), blend_share=0.0)
    fid = np.where(mesh.face_part > 0, mesh.face_part, 21).astype(np.uint8)
    pal = np.zeros((256, 3), float)
    pal[:21] = patch_colors_rgb()
    pal[21] = (222, 171, 140)
    rng = np.random.default_rng(3)
    backgrounds = [clutter(480, 640, rng).astype(float) for _ in cams]
    out = []
    for i in range(n):
        a = i / max(n - 1, 1)
        q = (1 - a) * q0 + a * q1
        frames = []
        for k, cam in enumerate(cams):
            ids = render_idmaps(mesh.pose(sk, q)[None], mesh.faces, fid, cam)[0]
            img = backgrounds[k].copy()
            on = ids > 0
            img[on] = pal[ids[on]] * rng.uniform(0.85, 1.0, (on.sum(), 1))
            img += rng.normal(0, 3, img.shape)
            frames.append(Frame(np.clip(img, 0, 255).astype(np.uint8), i / 30.0, i, f"cam{k}"))
        out.append(FrameSet(tuple(frames), i / 30.0, i))
    return out


def _choosing(db, frames: int):  # type: ignore[no-untyped-def]
    """A two-camera tracker choosing among the presets over ``frames`` frames (no arm
    stage, no background model: the painted frames have no empty room)."""
    return create_colorshirt_tracker(
        ColorShirtOptions(body="auto", body_selection_frames=frames, arm_selection_frames=0,
                          background_subtraction=False),
        webcam_rig(), database=db)


def test_auto_body_picks_a_preset_close_to_a_small_person(db) -> None:  # type: ignore[no-untyped-def]
    cams = webcam_rig()
    tr = _choosing(db, 4)
    assert tr.body_name == "m"  # the reference body until the start-up frames are in
    results = [tr.process(fs) for fs in _capture("xs", 5, cams)]
    assert all(r.found for r in results)
    assert tr.body_name in {"xs", "s"}
    assert tr.diagnostics["body"] == tr.body_name
    means = tr.diagnostics["body_residuals"]
    assert isinstance(means, dict) and min(means, key=means.__getitem__) == tr.body_name
    # the small presets fit better than every large one (among the large ones the
    # order is noise: with the triangulated placement xl read 0.090, xxl 0.073)
    assert max(means["xs"], means["s"]) < min(means["l"], means["xl"], means["xxl"])


def test_before_the_choice_the_pose_comes_from_the_best_body_so_far(db) -> None:  # type: ignore[no-untyped-def]
    tr = _choosing(db, 6)
    for fs in _capture("xs", 3, webcam_rig()):
        assert tr.process(fs).found
    assert tr._selection is not None and tr._selection.chosen is None
    means = tr.diagnostics["body_residuals"]
    assert isinstance(means, dict)
    assert tr.body_name == min(means, key=means.__getitem__) != "m"


def test_body_option_rejects_unknown_preset_names() -> None:
    with pytest.raises(ConfigError, match="unknown body preset"):
        ColorShirtOptions(body="giant")
    with pytest.raises(ConfigError):
        ColorShirtOptions(body="auto", body_selection_frames=0)
    assert ColorShirtOptions(body="auto").body == "auto"


def test_with_arm_scale_changes_only_the_arm_bones() -> None:
    short = with_arm_scale(REF, 0.9)
    ratio = short.bone_lengths()[1:] / REF.bone_lengths()[1:]
    names = REF.node_names[1:]
    for name, r in zip(names, ratio, strict=True):
        expected = 0.9 if name.split("_")[-1] in ("elbow", "wrist", "hand") else 1.0
        assert r == pytest.approx(expected), name


def test_arm_variants_keep_the_preset_itself_under_its_name() -> None:
    from bodyplay.trackers.colorshirt.bodyselect import BodyModel

    base = BodyModel.build("m", webcam_rig())
    variants = arm_variants(base, webcam_rig(), (0.9, 1.0))
    assert set(variants) == {"m", "m*0.90"} and variants["m"] is base
    assert 1.0 in ARM_SCALES and min(ARM_SCALES) < 0.9


def test_auto_body_then_finds_that_the_arms_are_short(db) -> None:  # type: ignore[no-untyped-def]
    cams = webcam_rig()
    tr = create_colorshirt_tracker(
        ColorShirtOptions(body="auto", body_selection_frames=3, arm_selection_frames=4,
                          background_subtraction=False), cams, database=db)
    for fs in _capture("m", 9, cams, arms=0.86):
        assert tr.process(fs).found
    # 3 preset frames, then 4 arm frames starting on the next one: decided by frame 8
    assert "*" in tr.body_name
    assert float(tr.body_name.split("*")[1]) <= 0.92


def test_body_selection_drops_the_worse_half_early_and_decides_among_the_rest() -> None:
    names = tuple("abcdefgh")
    sel = BodySelection(names, frames=20, halvings=(0.25, 0.5))
    residual = {n: 0.01 * (i + 1) for i, n in enumerate(names)}  # a is best
    residual["h"] = 0.001  # h looks best at first, then turns bad
    for frame in range(20):
        if frame == 5:
            residual["h"] = 0.5
        sel.add({n: residual[n] for n in sel.active})
        if frame + 1 == 5:
            assert len(sel.active) == 4 and "h" in sel.active
        if frame + 1 == 10:
            assert len(sel.active) == 2
    assert sel.chosen == "a"
    assert sel.active == ["a", "b"]


def test_body_selection_never_halves_below_two_candidates() -> None:
    assert BodySelection(("x",), frames=20).halvings == (0.5,)  # the default: once
    sel = BodySelection(("x", "y", "z"), frames=4, halvings=(0.25, 0.5))
    for _ in range(4):
        sel.add({"x": 0.2, "y": 0.1, "z": 0.3})
    assert sel.active == ["y", "x"] and sel.chosen == "y"


def test_body_selection_with_a_tolerance_keeps_the_first_candidate_that_fits_nearly_best(
) -> None:
    names = ("short", "middle", "long")  # the arm stage's order: shortest first
    strict = BodySelection(names, frames=3, halvings=())
    tolerant = BodySelection(names, frames=3, halvings=(), tolerance=0.05)
    for _ in range(3):
        for sel in (strict, tolerant):
            sel.add({"short": 0.0212, "middle": 0.0204, "long": 0.0200})
    assert strict.chosen == "long"
    assert tolerant.chosen == "middle"  # 2% above the best; "short" is 6% above


def test_arm_variants_come_shortest_first_whatever_order_the_scales_are_given_in() -> None:
    from bodyplay.trackers.colorshirt.bodyselect import BodyModel

    base = BodyModel.build("m", webcam_rig())
    variants = arm_variants(base, webcam_rig(), (1.0, 0.9, 0.95))
    assert list(variants) == ["m*0.90", "m*0.95", "m"]


def test_arm_tolerance_option_rejects_values_outside_zero_to_a_half() -> None:
    with pytest.raises(ConfigError, match="arm_tolerance"):
        ColorShirtOptions(arm_tolerance=-0.1)
    with pytest.raises(ConfigError, match="arm_tolerance"):
        ColorShirtOptions(arm_tolerance=float("nan"))
    assert ColorShirtOptions(arm_tolerance=0.0).arm_tolerance == 0.0


def test_body_selection_skipped_frames_do_not_count_and_enough_of_them_choose_the_fallback(
) -> None:
    sel = BodySelection(("xs", "m"), frames=3, halvings=())
    sel.add({"xs": 0.01, "m": 0.02})
    for _ in range(5):
        sel.skip("m")
    assert sel.chosen is None and sel.seen == 1  # patience: twice the frames
    sel.skip("m")
    assert sel.chosen == "m"
    sel.add({"xs": 0.01, "m": 0.02})
    sel.add({"xs": 0.01, "m": 0.02})
    assert sel.chosen == "m"  # a choice, once made, stays


def test_one_camera_without_a_floor_cue_keeps_the_reference_body(db) -> None:  # type: ignore[no-untyped-def]
    cams = webcam_rig()[:1]
    opts = ColorShirtOptions(body="auto", body_selection_frames=3, arm_selection_frames=0,
                             background_subtraction=False)
    frames = [FrameSet(fs.frames[:1], fs.t, fs.index) for fs in _capture("xs", 7, webcam_rig())]
    tr = create_colorshirt_tracker(opts, cams, database=db)
    for fs in frames[:5]:
        tr.process(fs)
    assert tr._selection is not None and tr._selection.chosen is None
    assert len(tr.diagnostics["arms"]) == 2  # type: ignore[arg-type]  # reported pose: searched
    means = tr.diagnostics["body_residuals"]
    assert isinstance(means, dict) and all(not np.isfinite(v) for v in means.values())
    tr.process(frames[5])
    assert tr.body_name == "m"
    judged = create_colorshirt_tracker(
        dataclasses.replace(opts, body_choice_max_stagger=float("inf")), cams, database=db)
    for fs in frames[:3]:
        judged.process(fs)
    assert judged._selection is not None and judged._selection.chosen is not None


@pytest.mark.parametrize("value", [0.0, -0.1, float("nan")])
def test_body_choice_max_stagger_option_rejects_non_positive_values(value: float) -> None:
    with pytest.raises(ConfigError, match="body_choice_max_stagger"):
        ColorShirtOptions(body_choice_max_stagger=value)


def test_arm_stage_compares_the_arm_scales_of_the_options(db) -> None:  # type: ignore[no-untyped-def]
    cams = webcam_rig()
    tr = create_colorshirt_tracker(
        ColorShirtOptions(body="auto", body_selection_frames=2, arm_selection_frames=3,
                          background_subtraction=False, arm_scales=(0.76, 0.8, 1.0)),
        cams, database=db)
    frames = _capture("m", 4, cams, arms=0.8)
    for fs in frames[:3]:
        tr.process(fs)
    assert tr._arm_stage_started
    chosen = tr._reference
    assert list(tr._bodies) == [f"{chosen}*0.76", f"{chosen}*0.80", chosen]


def test_body_selection_halving_keeps_a_candidate_the_tolerance_could_still_choose() -> None:
    names = ("a84", "a88", "a92", "a96", "a100")  # the arm stage: shortest first
    residual = {"a84": 0.0202, "a88": 0.0203, "a92": 0.0190, "a96": 0.0188, "a100": 0.0189}
    tolerant = BodySelection(names, frames=4, halvings=(0.5,), tolerance=0.1)
    strict = BodySelection(names, frames=4, halvings=(0.5,))
    for _ in range(4):
        tolerant.add(residual)
        strict.add(residual)
    assert strict.active == ["a96", "a100", "a92"] and strict.chosen == "a96"
    assert "a84" in tolerant.active  # 7% above the best: within the tolerance
    assert tolerant.chosen == "a84"  # the shortest arm that fits nearly best


def test_once_a_frame_has_judged_an_inactive_reference_body_is_no_longer_fitted(db) -> None:  # type: ignore[no-untyped-def]
    tr = _choosing(db, 6)  # the worse half drops out after 3 judged frames
    fitted: list[list[str]] = []
    estimate = tr._estimate

    def counting(*args, **kwargs):  # type: ignore[no-untyped-def]
        fitted[-1].append(tr.body_name)
        return estimate(*args, **kwargs)

    tr._estimate = counting  # type: ignore[method-assign]
    for fs in _capture("xs", 5, webcam_rig()):
        fitted.append([])
        assert tr.process(fs).found
    sel = tr._selection
    assert sel is not None and sel.chosen is None and "m" not in sel.active
    assert "m" in fitted[0]  # before any judged frame it may be reported: fitted
    assert sorted(fitted[-1]) == sorted(sel.active)  # after the halving: the race only
