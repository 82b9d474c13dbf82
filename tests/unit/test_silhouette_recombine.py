"""Specifications of the recombined training motion of the silhouette hierarchy."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette.options import HierarchyOptions
from bodyplay.trackers.silhouette.recombine import LIMB_GROUPS, recombined_sequences


def _sources(skeleton, n: int = 2, frames: int = 40):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(1)
    lo, hi = skeleton.limits
    out = []
    for _ in range(n):
        q = np.tile(skeleton.rest_pose(), (frames, 1))
        q[:, 3:] = rng.uniform(np.maximum(lo[3:], -1.0), np.minimum(hi[3:], 1.0),
                               (frames, len(lo) - 3))
        out.append(q)
    return out


def _cols(skeleton, names):  # type: ignore[no-untyped-def]
    return np.concatenate([np.arange(3 + 3 * skeleton.node_index(n), 6 + 3 * skeleton.node_index(n))
                           for n in names])


def test_recombined_sequences_total_the_frames_asked_within_the_joint_limits(skeleton) -> None:  # type: ignore[no-untyped-def]
    seqs = recombined_sequences(skeleton, _sources(skeleton), 95, np.random.default_rng(0),
                                length=30)
    assert sum(len(s) for s in seqs) == 95
    assert all(len(s) <= 30 for s in seqs)
    assert all(skeleton.within_limits(s).all() for s in seqs)


def test_every_swapped_body_part_is_a_whole_real_frame_of_some_source(skeleton) -> None:  # type: ignore[no-untyped-def]
    src = _sources(skeleton, 3)
    seqs = recombined_sequences(skeleton, src, 300, np.random.default_rng(2), swap=1.0,
                                random_limb=0.0)
    allf = np.concatenate(src)
    mixed = 0
    for g in LIMB_GROUPS:
        c = _cols(skeleton, g)
        for s in seqs:
            for f in s:
                # the part's rotations equal those of one source frame, all joints at once
                assert np.isclose(allf[:, c], f[c], atol=1e-12).all(axis=1).any()
    for s in seqs:  # and the parts come from different frames: a new combination
        arms = [np.flatnonzero(np.isclose(allf[:, _cols(skeleton, g)], s[0, _cols(skeleton, g)],
                                          atol=1e-12).all(axis=1))[0] for g in LIMB_GROUPS[1:3]]
        mixed += arms[0] != arms[1]
    assert mixed >= len(seqs) // 2


def test_random_limbs_move_smoothly_and_keep_the_rest_of_the_base(skeleton) -> None:  # type: ignore[no-untyped-def]
    src = _sources(skeleton, 1, 1)  # one still frame: every change is the random limb
    seqs = recombined_sequences(skeleton, src, 600, np.random.default_rng(3), swap=0.0,
                                random_limb=1.0, length=20)
    legs = [_cols(skeleton, g) for g in LIMB_GROUPS[3:]]
    for s in seqs:
        step = np.abs(np.diff(s, axis=0)).max()
        assert step < 0.5  # from one configuration to another over 20 frames
        moved = [not np.allclose(s[:, c], src[0][0, c]) for c in legs]
        assert sum(moved) <= 1  # at most one leg leaves the base: the body stands on a foot
        np.testing.assert_allclose(s[:, :6], np.repeat(src[0][:1, :6], len(s), axis=0))


def test_recombination_rejects_impossible_settings(skeleton) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError):
        recombined_sequences(skeleton, [], 10, rng)
    with pytest.raises(ConfigError):
        recombined_sequences(skeleton, _sources(skeleton), 10, rng, swap=0.8, random_limb=0.4)
    with pytest.raises(ConfigError):
        HierarchyOptions(recombine_share=-1.0)
    with pytest.raises(ConfigError):
        HierarchyOptions(recombine_swap=0.9, recombine_random=0.2)


def test_hierarchy_cache_key_ignores_recombination_settings_while_it_is_off() -> None:
    off = dict(HierarchyOptions().key_items())
    assert not any(k.startswith("recombine") for k in off)
    assert dict(HierarchyOptions(recombine_random=0.3).key_items()) == off
    on = dict(HierarchyOptions(recombine_share=1.0).key_items())
    assert on["recombine_share"] == 1.0 and on != off


def test_pose_set_gains_recombined_sequences_faced_to_the_camera(skeleton) -> None:  # type: ignore[no-untyped-def]
    from scipy.spatial.transform import Rotation

    from bodyplay.trackers.silhouette.poses import training_poses

    base = HierarchyOptions(clips=("131_01",), yaw_offsets_deg=(-30.0, 30.0), random_share=0.0)
    plain = training_poses(skeleton, base)
    more = training_poses(skeleton, HierarchyOptions(**{**base.__dict__, "recombine_share": 1.0}))
    assert len(more.sequences) > len(plain.sequences)
    assert len(more.poses) > len(plain.poses)
    extra = np.concatenate([s[s >= 0] for s in more.sequences[len(plain.sequences):]])
    fwd = Rotation.from_rotvec(more.poses[extra, 3:6]).apply([0.0, 0.0, 1.0])
    assert np.abs(np.degrees(np.arctan2(fwd[:, 0], fwd[:, 2]))).max() <= base.max_yaw_deg
