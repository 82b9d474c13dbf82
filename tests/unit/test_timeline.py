"""Specifications of scripted players: timelines of key poses, gestures and clips."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bodyplay.body import JOINT_INDEX, Skeleton
from bodyplay.errors import ConfigError
from bodyplay.events import PoseEvent
from bodyplay.testing import ScriptedPlayer, Timeline, key_pose, scripted_session, slerp_poses

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
RW, HEAD = JOINT_INDEX["r_wrist"], JOINT_INDEX["head"]


def test_held_key_pose_is_reproduced_exactly_after_its_blend() -> None:
    tl = Timeline(blend=0.2).hold("right_hand_up", 1.0)
    want = key_pose("right_hand_up", tl.skeleton)
    np.testing.assert_allclose(tl.pose_at(0.5), want, atol=1e-12)
    assert tl.joints_at(0.5)[RW, 1] > tl.joints_at(0.5)[HEAD, 1]


def test_segment_fades_in_from_the_pose_below() -> None:
    tl = Timeline(blend=0.4).hold("idle", 1.0).hold("right_hand_up", 1.0)
    ys = [tl.joints_at(t)[RW, 1] for t in (0.9, 1.1, 1.2, 1.3, 1.5)]
    assert ys[0] < ys[1] < ys[2] < ys[3] <= ys[4] + 1e-9


def test_gap_after_a_segment_holds_its_last_pose() -> None:
    tl = Timeline().hold("right_hand_up", 1.0).wait(2.0).hold("idle", 1.0)
    np.testing.assert_allclose(tl.pose_at(2.5), key_pose("right_hand_up", tl.skeleton))
    assert tl.duration == pytest.approx(4.0)


def test_named_gesture_raises_the_hand_above_the_head_then_lowers_it() -> None:
    tl = Timeline().hold("idle", 0.5).gesture("raise_right_hand")
    above = [tl.joints_at(t)[RW, 1] > tl.joints_at(t)[HEAD, 1] for t in (0.2, 1.25, 2.2)]
    assert above == [False, True, False]


def test_unknown_gesture_and_bad_keys_are_config_errors() -> None:
    with pytest.raises(ConfigError, match="unknown gesture 'moonwalk'.*raise_right_hand"):
        Timeline().gesture("moonwalk")
    with pytest.raises(ConfigError, match="increase"):
        Timeline().keys([(0.0, "idle"), (0.0, "t_pose")])
    with pytest.raises(ConfigError, match="unknown key pose"):
        Timeline().hold("splits", 1.0)


def test_custom_gesture_table_entries_are_key_pose_sequences() -> None:
    tl = Timeline(gestures={"salute": [(0.0, "idle"), (0.3, {"r_shoulder": (0, 0, -1.5)})]})
    tl.gesture("salute")
    assert tl.duration == pytest.approx(0.3)
    assert tl.joints_at(0.3)[RW, 1] > tl.joints_at(0.0)[RW, 1]


def test_slerp_of_poses_interpolates_rotations_on_the_shortest_path() -> None:
    sk = Skeleton()
    a, b = key_pose("idle", sk), key_pose("right_hand_up", sk)
    mid = slerp_poses(a, b, 0.5)
    i = 3 + 3 * sk.node_index("r_shoulder")
    assert mid[i + 2] == pytest.approx((1.4 - 1.5) / 2)
    np.testing.assert_allclose(slerp_poses(a, b, 0.0), a)
    np.testing.assert_allclose(slerp_poses(a, b, 1.0), b)


def test_scripted_player_samples_the_timeline_at_fixed_rate_with_pose_vectors() -> None:
    tl = Timeline().hold("idle", 1.0)
    player = ScriptedPlayer(tl, fps=10.0)
    samples = list(player)
    assert len(samples) == 11 and len(player) == 11
    assert [s.t for s in samples] == pytest.approx(np.arange(11) / 10.0)
    assert samples[0].pose is not None and samples[0].pose.shape == (tl.skeleton.pose_dim,)


def test_scripted_player_noise_is_seeded_and_upper_body_mode_loses_the_legs() -> None:
    tl = Timeline().hold("idle", 0.2)
    a = [s.joints for s in ScriptedPlayer(tl, noise=0.01, seed=3)]
    b = [s.joints for s in ScriptedPlayer(tl, noise=0.01, seed=3)]
    np.testing.assert_array_equal(a[2], b[2])
    ub = next(iter(ScriptedPlayer(tl, upper_body_only=True)))
    assert ub.state[:11] == ("tracked",) * 11 and ub.state[11:] == ("lost",) * 6
    assert "upper_body_only" in ub.capabilities


def test_scripted_session_drives_a_headless_session_with_a_fixed_clock() -> None:
    tl = Timeline().hold("idle", 0.5).gesture("raise_right_hand")
    s = scripted_session(tl, fps=20.0)
    poses: list[PoseEvent] = []
    s.subscribe("pose", poses.append)
    s.run()
    assert poses[-1].emitted_t == pytest.approx((len(poses) - 1) / 20.0)
    hand_up = [p.t for p in poses if p.joint("r_wrist")[1] > p.joint("head")[1]]
    assert hand_up and 0.7 < hand_up[0] < 1.3


def test_clip_segment_plays_a_mocap_clip_rooted_at_the_origin() -> None:
    bvh = DATA / "mocap" / "cmu" / "13_29.bvh"
    if not bvh.exists():
        pytest.skip("shared data not available")
    from bodyplay.motion.clip import load_clip

    clip = load_clip(bvh, fps=30.0).slice(0.0, 2.0)
    tl = Timeline(blend=0.0).clip(clip, clip_start=0.5, duration=1.0)
    q = tl.pose_at(0.0)
    assert q[0] == pytest.approx(0.0, abs=1e-9) and q[2] == pytest.approx(0.0, abs=1e-9)
    # rotations follow the clip half a second in
    np.testing.assert_allclose(tl.pose_at(0.5)[3:], clip.poses[30][3:], atol=1e-6)
