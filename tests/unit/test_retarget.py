"""Specifications of bodyplay.motion retargeting, the pose solver and MotionClip."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.motion import (
    BANDAI_MAPPING,
    CMU_MAPPING,
    CMU_MAX_MAPPING,
    BVHClip,
    EndSite,
    MotionClip,
    analyze_source,
    builtin_clip_path,
    guess_mapping,
    list_builtin_clips,
    load_clip,
    poses_from_joints,
    read_bvh,
    retarget,
    sample_poses,
)

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
MOCAP = DATA / "mocap"
SHARED_BVH = sorted(MOCAP.glob("*/*.bvh")) if MOCAP.is_dir() else []
LIMBS = [
    ("l_shoulder", "l_elbow"), ("l_elbow", "l_wrist"), ("r_shoulder", "r_elbow"),
    ("r_elbow", "r_wrist"), ("l_hip", "l_knee"), ("l_knee", "l_ankle"),
    ("r_hip", "r_knee"), ("r_knee", "r_ankle"),
]  # fmt: skip
# at most this many frames per clip (strided) keep the whole file fast
MAX_FRAMES = 300


def _angles(a: np.ndarray, b: np.ndarray, pair: tuple[str, str]) -> np.ndarray:
    i, j = JOINT_INDEX[pair[0]], JOINT_INDEX[pair[1]]
    u, v = a[:, j] - a[:, i], b[:, j] - b[:, i]
    cos = np.sum(u * v, -1) / np.linalg.norm(u, axis=-1) / np.linalg.norm(v, axis=-1)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _strided(clip: BVHClip) -> slice:
    return slice(None, None, max(1, clip.num_frames // MAX_FRAMES))


@pytest.mark.parametrize("path", SHARED_BVH, ids=lambda p: p.name)
def test_retarget_makes_limbs_point_like_the_source_with_feet_on_the_floor(path: Path) -> None:
    sk = Skeleton()
    clip = read_bvh(path)
    motion = retarget(clip, sk, frames=_strided(clip))
    J = motion.joints()
    assert motion.source_joints is not None
    for pair in LIMBS:
        assert np.median(_angles(J, motion.source_joints, pair)) < 10.0, pair
    assert np.median(_angles(J, motion.source_joints, ("pelvis", "neck"))) < 5.0
    # bone lengths are the skeleton's, frame after frame
    rest = sk.joint_positions(sk.rest_pose())
    for a, b in LIMBS:
        lengths = np.linalg.norm(J[:, JOINT_INDEX[b]] - J[:, JOINT_INDEX[a]], axis=-1)
        assert np.allclose(lengths, np.linalg.norm(rest[JOINT_INDEX[b]] - rest[JOINT_INDEX[a]]))
    # feet: ankles never below their rest height by more than a few cm, and they come down
    ankles = np.minimum(J[:, JOINT_INDEX["l_ankle"], 1], J[:, JOINT_INDEX["r_ankle"], 1])
    assert np.percentile(ankles, 5) == pytest.approx(0.08, abs=0.08)
    assert ankles.min() > -0.02
    # the normalized source stands on the floor too, at the skeleton's height
    src = motion.source_joints
    src_ankles = np.minimum(src[:, JOINT_INDEX["l_ankle"], 1], src[:, JOINT_INDEX["r_ankle"], 1])
    assert 0.0 < np.percentile(src_ankles, 5) < 0.2
    assert np.percentile(src[:, JOINT_INDEX["head"], 1], 95) == pytest.approx(1.6, abs=0.15)


def test_shared_mocap_present_for_retarget_tests() -> None:
    if not SHARED_BVH:
        pytest.skip("../shared/data/mocap is absent")
    assert len(SHARED_BVH) >= 4


def test_retarget_detects_units_from_standing_height_never_assuming_metres() -> None:
    bandai = MOCAP / "bandai_namco" / "dataset-2_wave-right-hand_normal_001.bvh"
    if not bandai.exists():
        pytest.skip("Bandai Namco clips absent")
    info = analyze_source(read_bvh(bandai))
    assert info.units == "cm" and 140 < info.height < 180 and info.up_axis == "+Y"
    assert info.mapping is BANDAI_MAPPING


def _z_up_and_scaled(clip: BVHClip, scale: float) -> BVHClip:
    """The same motion under a new root that turns Y up into Z up, in other units."""
    motion = clip.motion.copy()
    for j, chans in enumerate(clip.channels):
        for k, c in enumerate(chans):
            if c.endswith("position"):
                motion[:, clip.channel_offsets[j] + k] *= scale
    world = np.full((clip.num_frames, 1), 90.0)
    return BVHClip(
        names=("World", *clip.names),
        parents=(-1, *(p + 1 for p in clip.parents)),
        offsets=np.vstack([np.zeros(3), clip.offsets * scale]),
        channels=(("Xrotation",), *clip.channels),
        frame_time=clip.frame_time,
        motion=np.hstack([world, motion]),
        source="zup.bvh",
        end_sites=tuple(
            EndSite(e.parent + 1, tuple(np.asarray(e.offset) * scale)) for e in clip.end_sites
        ),
    )


def test_retarget_handles_a_z_up_source_in_other_units_identically() -> None:
    path = MOCAP / "cmu" / "131_03.bvh"
    if not path.exists():
        path = builtin_clip_path("131_03")
    clip = read_bvh(path)
    frames = slice(0, 400, 4)
    base = retarget(clip, frames=frames)
    turned = _z_up_and_scaled(clip, 2.54)
    info = analyze_source(turned)
    assert info.up_axis == "+Z"
    assert info.height == pytest.approx(2.54 * analyze_source(clip).height, rel=1e-6)
    other = retarget(turned, frames=frames)
    assert np.allclose(other.joints(), base.joints(), atol=1e-6)


def test_mappings_are_chosen_by_joint_names_and_the_guess_agrees() -> None:
    for name, mapping in (("13_29", CMU_MAPPING), ("131_01", CMU_MAX_MAPPING)):
        clip = read_bvh(builtin_clip_path(name))
        assert analyze_source(clip).mapping is mapping
        guessed = guess_mapping(clip)
        for key in ("l_shoulder", "l_elbow", "l_wrist", "r_hip", "r_knee", "r_ankle", "head"):
            assert guessed.joints[key] == mapping.joints[key]


def test_poses_from_joints_recovers_the_joints_of_real_poses() -> None:
    sk = Skeleton.from_shape("s")
    q = sample_poses(sk, 200, np.random.default_rng(5), clips=["131_03"], mode="clips")
    J = sk.joint_positions(q)
    J2 = sk.joint_positions(poses_from_joints(sk, J))
    err = np.linalg.norm(J2 - J, axis=-1)
    assert np.median(err) < 0.01 and np.percentile(err, 95) < 0.03


def test_poses_from_joints_tolerates_lost_joints() -> None:
    sk = Skeleton()
    q = sample_poses(sk, 30, np.random.default_rng(6), mode="upper_body", blend_share=0)
    J = sk.joint_positions(q)
    J[:, 11:] = np.nan  # an upper-body tracker: no legs
    J[10:13, JOINT_INDEX["l_wrist"]] = np.nan  # a wrist lost for three frames
    J[0, JOINT_INDEX["r_elbow"]] = np.nan
    out = poses_from_joints(sk, J)
    assert np.all(np.isfinite(out))
    got = sk.joint_positions(out)
    # upper arms still point where the tracked ones do
    assert np.max(_angles(got, J, ("l_shoulder", "l_elbow"))) < 1.0
    assert np.max(_angles(got[1:], J[1:], ("r_shoulder", "r_elbow"))) < 1.0
    # the lost wrist keeps the elbow bend of the last frame it was seen
    e = 3 + 3 * sk.node_index("l_elbow")
    assert np.allclose(out[10:13, e : e + 3], out[9, e : e + 3])


def test_poses_from_joints_rejects_bad_shapes() -> None:
    with pytest.raises(ConfigError, match="shape"):
        poses_from_joints(Skeleton(), np.zeros((5, 16, 3)))
    with pytest.raises(ConfigError, match="unknown extra"):
        poses_from_joints(Skeleton(), np.zeros((1, 17, 3)), extras={"nose": np.zeros((1, 3))})


# ---- MotionClip ----------------------------------------------------------------------


@pytest.fixture(scope="module")
def walk() -> MotionClip:
    return load_clip("131_01", fps=60)


def test_load_clip_finds_builtin_clips_by_name(walk: MotionClip) -> None:
    assert set(list_builtin_clips()) == {"13_29", "131_01", "131_02", "131_03"}
    assert walk.fps == 60.0 and walk.name == "131_01"
    assert walk.duration == pytest.approx(993 / 120, abs=1 / 60)
    with pytest.raises(ConfigError, match="no built-in motion clip"):
        load_clip("99_99")


def test_resample_keeps_duration_and_motion(walk: MotionClip) -> None:
    slow = walk.resample(24)
    assert slow.fps == 24 and slow.duration == pytest.approx(walk.duration, abs=1 / 24)
    assert np.allclose(slow.joints()[::2][:20], walk.joints()[::5][:20], atol=1e-6)
    assert slow.source_joints is not None and slow.source_joints.shape[0] == slow.num_frames


def test_at_interpolates_between_frames(walk: MotionClip) -> None:
    t = 1.0 + 0.5 / walk.fps
    mid = walk.skeleton.joint_positions(walk.at(t))
    a, b = walk.joints()[60], walk.joints()[61]
    assert np.allclose(mid, 0.5 * (a + b), atol=0.01)
    assert np.allclose(walk.at(1e6), walk.poses[-1])


def test_slice_takes_the_given_seconds(walk: MotionClip) -> None:
    part = walk.slice(2.0, 1.5)
    assert part.duration == pytest.approx(1.5)
    assert np.allclose(part.poses[0], walk.poses[120])
    with pytest.raises(ConfigError, match="outside the clip"):
        walk.slice(-1.0)
    with pytest.raises(ConfigError, match="positive"):
        walk.slice(0.0, 0.0)


def test_motion_clip_rejects_bad_arguments(walk: MotionClip) -> None:
    with pytest.raises(ConfigError, match="shape"):
        MotionClip(walk.skeleton, walk.poses[:, :10], 30.0)
    with pytest.raises(ConfigError, match="fps"):
        replace(walk, fps=0.0)
    with pytest.raises(ConfigError, match="fps"):
        walk.resample(-5)


def test_load_clip_reads_back_a_written_squatting_clip_with_the_feet_on_the_floor(
    tmp_path: Path,
) -> None:
    # bodyplay's own BVH ends each ankle in an End Site (no toe joint): the foot's
    # direction comes from it, as a wrist's End Site gives the hand; without it a
    # retargeted squat dug the toes 10 cm into the floor and lifting the clip out of
    # the floor left every standing frame 10-14 cm up in the air
    from bodyplay.motion import write_bvh
    from bodyplay.motion.retarget import _foot_low
    from bodyplay.testing import Timeline

    sk = Skeleton()
    tl = Timeline(sk, blend=0.15).hold("idle", 2.0)
    for _ in range(2):
        tl.gesture("squat", start=tl.cursor + 1.0)
    tl.hold("idle", 2.0)
    times = np.arange(0.0, tl.duration, 1.0 / 30.0)
    poses = tl.poses(times)
    rest = sk.joint_positions(sk.rest_pose())
    J = sk.joint_positions(poses)
    ankles = [JOINT_INDEX["l_ankle"], JOINT_INDEX["r_ankle"]]
    poses[:, 1] += rest[ankles, 1].min() - J[:, ankles, 1].min(axis=1)  # feet on the floor
    path = write_bvh(tmp_path / "squats.bvh", sk, poses, 30.0)
    clip = load_clip(str(path), sk)
    standing = np.abs(poses[:, 1] - sk.pelvis_height) < 1e-3
    assert standing.sum() > 20
    assert np.abs(clip.poses[standing, 1] - sk.pelvis_height).max() < 0.02
    assert np.median(np.abs(_foot_low(sk, clip.poses))) < 0.02
