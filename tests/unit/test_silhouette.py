"""Specifications of the silhouette tracker's stages (papers/single-camera-silhouette-mocap.txt)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.errors import CaptureError, ConfigError
from bodyplay.trackers.silhouette.background import BackgroundModel
from bodyplay.trackers.silhouette.distance import (
    distance_maps,
    encode_runs,
    score_dense,
    score_direct,
    score_runs,
)
from bodyplay.trackers.silhouette.options import BackgroundOptions, HierarchyOptions


def _room(rng: np.random.Generator) -> np.ndarray:
    base = rng.integers(40, 220, (60, 80, 3)).astype(np.uint8)
    return np.kron(base, np.ones((8, 8, 1), np.uint8))  # 480x640 blocky texture


def _with_player(room: np.ndarray, x: int) -> np.ndarray:
    img = room.copy()
    img[150:420, x : x + 80] = (200, 40, 40)
    return img


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_background_learns_with_the_player_in_view_from_frame_0(seed: int) -> None:
    # several rooms: the first frame's GrabCut guess differs with the texture
    rng = np.random.default_rng(seed)
    room = _room(rng)
    model = BackgroundModel(BackgroundOptions(learn_after=6))
    xs = [100 + 12 * (i % 30) if (i // 30) % 2 == 0 else 100 + 12 * (30 - i % 30)
          for i in range(150)]
    for x in xs:
        sil = model.apply(_with_player(room, x))
    truth = np.zeros((480, 640), np.uint8)
    truth[150:420, xs[-1] : xs[-1] + 80] = 1
    small = truth[::2, ::2]
    fg = sil.foreground > 0
    iou = (fg & (small > 0)).sum() / (fg | (small > 0)).sum()
    assert iou > 0.85
    # the copy of the player in the first frame (a ghost) is gone
    assert not fg[75:210, 50:90].any()


def test_background_finds_a_player_who_stands_still_but_for_an_arm() -> None:
    # in view from frame 0, the torso never moves: only the arm shows a change; the
    # still torso must still be foreground, the room beside it background
    rng = np.random.default_rng(2)
    room = _room(rng)
    model = BackgroundModel(BackgroundOptions())
    for i in range(60):
        img = room.copy()
        img[150:420, 280:360] = (200, 40, 40)  # the torso and legs, still
        y = 160 + 8 * (i % 20)  # an arm swinging up and down beside it
        img[y : y + 30, 360:440] = (40, 60, 200)
        sil = model.apply(img)
    fg = sil.foreground > 0
    torso = np.zeros_like(fg)
    torso[75:210, 140:180] = True
    assert fg[torso].mean() > 0.95  # the still torso is the player
    assert fg[75:210, 30:120].mean() < 0.02  # the room at its side is not
    assert sil.unknown[75:210, 30:200].sum() == 0  # nothing left "don't care" there


def _cabinet_room_foreground(options: BackgroundOptions, frames: int) -> np.ndarray:
    """A still red cabinet beside a still red player whose arm swings; from frame 10 the
    tracker's estimate (``protect``) covers the player, never the cabinet. The last
    frame's foreground."""
    rng = np.random.default_rng(2)
    room = _room(rng)
    room[150:420, 120:200] = (200, 40, 40)
    model = BackgroundModel(options)
    body = np.zeros((240, 320), bool)
    body[70:215, 135:225] = True
    for i in range(frames):
        img = room.copy()
        img[150:420, 280:360] = (200, 40, 40)
        y = 160 + 8 * (i % 20)
        img[y : y + 30, 360:440] = (40, 60, 200)
        sil = model.apply(img, body if i >= 10 else None)
    return np.asarray(sil.foreground > 0)


@pytest.mark.parametrize("expiry", [0, 30])
def test_background_forgets_guessed_player_pixels_the_tracker_never_puts_the_body_on(
        expiry: int) -> None:
    # the first frame's guess takes a still red cabinet beside the player along; the
    # tracker's estimate (``protect``) never covers it: after ``guess_expiry`` frames
    # it is background, while the still torso the estimate covers stays the player
    fg = _cabinet_room_foreground(BackgroundOptions(guess_expiry=expiry, resolve_outside=None),
                                  80)
    assert fg[75:210, 140:180].mean() > 0.95
    cabinet = fg[80:205, 65:95].mean()
    if expiry:
        assert cabinet < 0.05
    else:
        assert cabinet > 0.95  # the guess took it: without expiry it stays "the player"


@pytest.mark.parametrize("reach", [None, 10])
def test_background_resolution_takes_still_pixels_beyond_the_estimate_for_background(
        reach: int | None) -> None:
    # the first frame's guess takes a still red cabinet beside the player along; with
    # ``resolve_outside`` the next resolution after the tracker's estimate arrives
    # seeds the cabinet (still, farther than ``reach`` pixels from the estimate) as
    # sure background: it is background within a few frames, long before
    # ``guess_expiry``, while the still torso the estimate covers stays the player
    fg = _cabinet_room_foreground(BackgroundOptions(guess_expiry=0, resolve_outside=reach), 25)
    assert fg[75:210, 140:180].mean() > 0.95
    cabinet = fg[80:205, 65:95].mean()
    if reach is None:
        assert cabinet > 0.95  # off: the guess keeps it "the player"
    else:
        assert cabinet < 0.05


def test_background_options_reject_a_negative_resolve_outside() -> None:
    with pytest.raises(ConfigError, match="resolve_outside"):
        BackgroundOptions(resolve_outside=-1)


@pytest.mark.parametrize("away", [0, 12])
def test_background_learns_a_change_only_once_the_estimate_has_stayed_off_it(
        away: int) -> None:
    # a hand held still for 100 frames under the tracker's estimate; the estimate
    # then leaves it for one frame (a step): with ``learn_away`` the hand is not
    # learned as background at once, it is still the player's next frame
    room = _room(np.random.default_rng(4))
    model = BackgroundModel(BackgroundOptions(learn_after=5, learn_away=away))
    for _ in range(8):
        model.apply(room)
    img = room.copy()
    img[200:260, 300:340] = (40, 60, 200)
    protect = np.zeros((240, 320), bool)
    protect[90:140, 140:180] = True
    for _ in range(100):
        model.apply(img, protect)
    model.apply(img, np.zeros_like(protect))
    sil = model.apply(img, protect)
    hand = sil.foreground[102:128, 152:168].mean()
    if away:
        assert hand > 0.95
    else:
        assert hand < 0.05  # learned the frame the estimate left it


def test_background_motion_is_zero_while_nothing_moves() -> None:
    room = _room(np.random.default_rng(5))
    model = BackgroundModel()
    for _ in range(3):
        model.apply(_with_player(room, 300))
    assert model.motion == 0.0
    model.apply(_with_player(room, 340))
    assert model.motion > 0.002


def test_background_options_reject_a_negative_learn_away() -> None:
    with pytest.raises(ConfigError, match="learn_away"):
        BackgroundOptions(learn_away=-1)


def test_silhouette_options_reject_select_motion_outside_a_share() -> None:
    from bodyplay.trackers.silhouette import SilhouetteOptions

    with pytest.raises(ConfigError, match="select_motion"):
        SilhouetteOptions(select_motion=1.5)
    with pytest.raises(ConfigError, match="select_wait"):
        SilhouetteOptions(select_wait=-1.0)


def test_background_without_a_first_guess_resolves_nothing() -> None:
    # no GrabCut guess of the player (here turned off): the pixels not seen to change
    # stay unknown ("don't care") instead of being labelled the player
    room = _room(np.random.default_rng(3))
    model = BackgroundModel(BackgroundOptions(bootstrap=False))
    for i in range(30):
        x = 200 + 4 * i
        sil = model.apply(_with_player(room, x))
    assert model.player is None
    assert sil.foreground.mean() < 0.15  # the player, and its first-frame copy, at most


def test_background_empty_room_start_makes_every_pixel_known() -> None:
    room = _room(np.random.default_rng(1))
    model = BackgroundModel(BackgroundOptions(learn_after=5))
    for _ in range(8):
        model.apply(room)
    assert model.known is not None and model.known.all()
    sil = model.apply(_with_player(room, 300))
    assert sil.foreground[75:210, 150:190].mean() > 0.95
    assert sil.unknown.sum() == 0


def test_background_rejects_a_grey_frame() -> None:
    with pytest.raises(CaptureError, match="RGB"):
        BackgroundModel().apply(np.zeros((48, 64), np.uint8))


def _blob(shift: int = 0) -> np.ndarray:
    m = np.zeros((80, 60), np.uint8)
    m[10:70, 25 + shift : 35 + shift] = 1  # body
    m[20:25, 10 + shift : 50 + shift] = 1  # arms
    return m


def test_distance_is_zero_for_identical_masks() -> None:
    maps = distance_maps(_blob())
    assert score_direct(maps, _blob()) == pytest.approx(0.0, abs=1e-9)


def test_distance_grows_with_offset() -> None:
    maps = distance_maps(_blob())
    d = [score_direct(maps, _blob(s)) for s in (0, 1, 2, 4, 8)]
    assert all(b > a for a, b in zip(d, d[1:], strict=False))


def _figure_with_arm(arm_dx: int | None) -> np.ndarray:
    m = np.zeros((120, 80), np.uint8)
    m[40:110, 32:48] = 1  # torso and legs
    m[25:40, 36:44] = 1  # head
    if arm_dx is not None:
        m[8:45, 50 + arm_dx : 54 + arm_dx] = 1  # a thin arm raised beside the head
    return m


def test_default_beta_prefers_a_raised_arm_slightly_off_to_no_arm() -> None:
    from bodyplay.trackers.silhouette.options import SilhouetteOptions

    observed = _figure_with_arm(0)
    paper = distance_maps(observed, beta=1.0)
    # eq. 10-11 with the paper's beta = 1: leaving the thin arm out is the cheaper error
    assert score_direct(paper, _figure_with_arm(None)) < score_direct(paper, _figure_with_arm(2))
    ours = distance_maps(observed, beta=SilhouetteOptions().beta)
    assert score_direct(ours, _figure_with_arm(2)) < score_direct(ours, _figure_with_arm(None))


def test_matrix_product_and_runs_equal_direct_scoring() -> None:
    rng = np.random.default_rng(2)
    maps = distance_maps(_blob(), unknown=(rng.random((80, 60)) < 0.05).astype(np.uint8))
    masks = np.stack([_blob(s) for s in range(-5, 6)] + [rng.integers(0, 2, (80, 60))]
                     ).astype(np.uint8)
    direct = np.array([score_direct(maps, m) for m in masks])
    dense = score_dense(maps, masks.reshape(len(masks), -1).astype(np.float32))
    runs = score_runs(maps, encode_runs(masks))
    np.testing.assert_allclose(dense, direct, rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(runs, direct, rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(encode_runs(masks).masks(), masks)


def test_unknown_pixels_cost_nothing_to_cover() -> None:
    fg = _blob()
    unknown = np.zeros_like(fg)
    unknown[:, :] = 1 - fg
    maps = distance_maps(fg, unknown)
    wide = np.ones_like(fg)
    assert score_direct(maps, wide) == pytest.approx(0.0, abs=1e-9)


def test_dedup_keeps_poses_five_degrees_apart(skeleton) -> None:  # type: ignore[no-untyped-def]
    from scipy.spatial.transform import Rotation

    from bodyplay.trackers.silhouette.poses import _quats, dedup_poses

    rng = np.random.default_rng(3)
    base = skeleton.rest_pose()
    poses = np.tile(base, (60, 1))
    i = 3 + 3 * skeleton.node_index("l_elbow")
    poses[:, i + 2] = rng.uniform(0, 1.2, 60)
    kept, owner = dedup_poses(skeleton, poses, 5.0)
    q = _quats(skeleton, poses)

    def max_angle(a: int, b: int) -> float:
        ra, rb = Rotation.from_quat(q[a]), Rotation.from_quat(q[b])
        return float(np.degrees((ra.inv() * rb).magnitude()).max())

    for a in range(len(kept)):
        for b in range(a + 1, len(kept)):
            assert max_angle(kept[a], kept[b]) >= 5.0 - 1e-6
    for j in range(len(poses)):
        assert max_angle(j, kept[owner[j]]) < 5.0 + 1e-6


def test_mirror_pose_swaps_left_and_right_across_the_body(skeleton) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.body.joints import JOINT_NAMES
    from bodyplay.trackers.silhouette.poses import mirror_poses

    rng = np.random.default_rng(5)
    lo, hi = skeleton.limits
    poses = np.tile(skeleton.rest_pose(), (20, 1))
    poses[:, 3:] = rng.uniform(np.maximum(lo[3:], -1.0), np.minimum(hi[3:], 1.0), (20, len(lo) - 3))
    poses[:, 0] = rng.uniform(-0.5, 0.5, 20)
    mirrored = mirror_poses(skeleton, poses)
    swap = [JOINT_NAMES.index({"l": "r_", "r": "l_"}[n[0]] + n[2:]) if n[:2] in ("l_", "r_")
            else k for k, n in enumerate(JOINT_NAMES)]
    want = skeleton.joint_positions(poses)[:, swap] * np.array([-1.0, 1.0, 1.0])
    np.testing.assert_allclose(skeleton.joint_positions(mirrored), want, atol=1e-9)
    assert skeleton.within_limits(mirrored).all()  # the limits are left-right symmetric
    np.testing.assert_allclose(mirror_poses(skeleton, mirrored), poses, atol=1e-12)


@pytest.mark.parametrize("mirror", [True, False])
def test_pose_set_covers_the_mirror_of_every_training_frame_only_when_mirrored(
        skeleton, mirror: bool) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.poses import dedup_poses, mirror_poses, training_poses

    opts = HierarchyOptions(clips=("131_01",), yaw_offsets_deg=(0.0,), random_share=0.0,
                            dedup_deg=12.0, mirror=mirror)
    tp = training_poses(skeleton, opts)
    assert len(tp.sequences) == (2 if mirror else 1)
    first = tp.poses[tp.sequences[0][tp.sequences[0] >= 0]]
    # a kept pose within the rule's angle of every mirrored frame: adding the mirrors
    # to the kept poses keeps no new pose
    kept, _ = dedup_poses(skeleton, np.concatenate([tp.poses, mirror_poses(skeleton, first)]),
                          tp.dedup_deg)
    assert (len(kept) == len(tp.poses)) == mirror
    if mirror:  # the mirrored sequence is the mirror of the first, frame by frame
        assert (tp.sequences[1] >= 0).sum() == (tp.sequences[0] >= 0).sum()


def test_algorithm_1_prototypes_cover_their_clusters_within_the_threshold(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.hierarchy import cluster_level, geometry_of
    from bodyplay.trackers.silhouette.templates import render_templates

    tree = silhouette_tree
    poses = tree.poses[:80]
    r = render_templates(__import__("bodyplay").Skeleton(), poses, geometry_of(tree.options),
                         levels=(0,))
    t = 0.05
    protos, assign = cluster_level(r.runs[0], np.arange(80), t, np.random.default_rng(0))
    assert len(set(protos.tolist())) == len(protos)
    for k, p in enumerate(protos):
        maps = distance_maps(r.runs[0].masks(np.array([p]))[0])
        d = score_runs(maps, r.runs[0], np.flatnonzero(assign == k))
        assert d.max() <= t + 1e-9
        assert assign[p] == k


def _arms(kind: str) -> np.ndarray:
    m = np.zeros((80, 60), np.uint8)
    m[10:70, 25:35] = 1  # head, torso and legs
    if kind == "spread":
        m[20:24, 6:54] = 1  # both arms out to the sides
    elif kind == "folded":
        m[22:30, 21:39] = 1  # forearms across the chest, elbows just outside it
    return m


@pytest.mark.parametrize("membership", ["member", "both"])
def test_algorithm_1_in_the_filters_direction_keeps_a_folded_pose_out_of_a_spread_cluster(
        membership: str) -> None:
    from bodyplay.trackers.silhouette.hierarchy import cluster_level

    runs = encode_runs(np.stack([_arms("spread"), _arms("spread"), _arms("folded")]))
    rng = np.random.default_rng(0)
    # the paper's direction: the folded silhouette lies inside the spread one, so it
    # joins the spread prototype, whose template the filter scores far from a fold
    protos, assign = cluster_level(runs, np.arange(3), 0.06, rng)
    assert len(protos) == 1
    folded_maps = distance_maps(_arms("folded"), beta=5.0)
    assert score_direct(folded_maps, _arms("spread")) > 0.06
    # scored as the filter will (the member observed, beta 5): the fold has its own
    # prototype, and every member is within the threshold of its prototype that way
    protos, assign = cluster_level(runs, np.arange(3), 0.06, rng, membership, beta=5.0)
    assert len(protos) == 2 and assign[2] != assign[0] and assign[0] == assign[1]
    masks = runs.masks()
    for m, k in enumerate(assign):
        observed = distance_maps(masks[m], beta=5.0)
        assert score_direct(observed, masks[protos[k]]) <= 0.06 + 1e-9


def test_hierarchy_options_reject_an_unknown_membership() -> None:
    with pytest.raises(ConfigError, match="membership"):
        HierarchyOptions(membership=("prototype", "sideways", "both"))  # type: ignore[arg-type]
    assert "membership" not in dict(HierarchyOptions().key_items())  # old caches stay valid
    assert "membership" in dict(HierarchyOptions(membership=("both",) * 3).key_items())


def test_tree_levels_partition_the_poses(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    tree = silhouette_tree
    sizes = tree.level_sizes
    assert len(sizes) == 3 and sizes[0] <= sizes[1] <= sizes[2] <= len(tree.poses)
    for lv in (1, 2):
        par = tree.node_parent[lv]
        assert np.all(np.diff(par) >= 0)  # children contiguous, parent by parent
        assert set(par.tolist()) == set(range(sizes[lv - 1]))  # every node has children
    assert np.all(tree.node_parent[0] == -1)
    assert tree.trans_count.sum() > 0 and np.all(tree.part_sigma > 0)


def test_filter_prunes_subtrees_and_finds_a_template_shown_to_it(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.options import SilhouetteOptions
    from bodyplay.trackers.silhouette.treefilter import TreeFilter

    tree = silhouette_tree
    body = tree.bodies["m"]
    f = TreeFilter(tree, body, SilhouetteOptions(max_expand=(4, 8)))
    leaf = tree.num_leaves // 2
    shown = body.runs[2].masks(np.array([leaf]))[0]
    maps = tuple(
        distance_maps(np.asarray(
            __import__("cv2").resize(shown.astype(np.float32), (w, h),
                                     interpolation=__import__("cv2").INTER_AREA) >= 0.5,
            np.uint8))
        for w, h in ((60, 80), (120, 160), (240, 320)))
    for _ in range(3):
        step = f.step(maps)  # type: ignore[arg-type]
    shifts0 = (2 * f.options.shift_search[0] + 1) * (2 * f.options.shift_search[1] + 1)
    assert step.evaluations[0] == tree.level_sizes[0] * shifts0  # every node, every position
    assert step.evaluations[1] < tree.level_sizes[1] * 3  # only the children of the kept
    assert step.evaluations[2] < tree.level_sizes[2] * 3
    assert step.shift[1] == 0
    assert step.distance < 0.005
    assert f.posterior is not None and f.posterior.sum() == pytest.approx(1.0)


def test_transition_frames_predict_where_a_training_motion_goes_two_frames_on(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.options import SilhouetteOptions
    from bodyplay.trackers.silhouette.treefilter import TreeFilter

    tree = silhouette_tree
    nxt: dict[int, set[int]] = {}
    for a, b in zip(tree.trans_src.tolist(), tree.trans_dst.tolist(), strict=True):
        nxt.setdefault(a, set()).add(b)
    src, two = next((a, c) for a, bs in nxt.items() for b in bs for c in nxt.get(b, ())
                    if c != a and c not in bs)
    prior = {}
    for frames in (1, 3):
        filt = TreeFilter(tree, tree.bodies["m"], SilhouetteOptions(
            transition_frames=frames, transition_weight=1.0, uniform=1e-9))
        filt.posterior = np.zeros(tree.num_leaves)
        filt.posterior[src] = 1.0
        p = filt.predict()
        assert p.sum() == pytest.approx(1.0)
        prior[frames] = float(p[two])
    assert prior[1] < 1e-6 < prior[3]  # one frame's histogram cannot reach it; three can


def test_options_reject_transition_frames_that_are_not_1_to_10() -> None:
    from bodyplay.trackers.silhouette.options import SilhouetteOptions

    for bad in (0, 11, 2.5):
        with pytest.raises(ConfigError, match="transition_frames"):
            SilhouetteOptions(transition_frames=bad)  # type: ignore[arg-type]


def _shown(body, leaf: int, down: int = 0) -> tuple[object, ...]:  # type: ignore[no-untyped-def]
    """The distance maps of leaf ``leaf``'s own template (moved ``down`` level-3 pixels),
    at the three levels."""
    import cv2

    shown = np.roll(body.runs[2].masks(np.array([leaf]))[0], down, axis=0)
    return tuple(
        distance_maps(np.asarray(cv2.resize(shown.astype(np.float32), (w, h),
                                            interpolation=cv2.INTER_AREA) >= 0.5, np.uint8))
        for w, h in ((60, 80), (120, 160), (240, 320)))


def test_fit_prior_lets_a_pose_the_prediction_cannot_reach_win_when_it_fits_clearly_better(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette.distance import score_runs_shifted
    from bodyplay.trackers.silhouette.options import SilhouetteOptions
    from bodyplay.trackers.silhouette.treefilter import TreeFilter

    tree = silhouette_tree
    body = tree.bodies["m"]
    n = tree.num_leaves
    shown_leaf = n // 3
    maps = _shown(body, shown_leaf)
    zero = np.zeros(n, np.int64)
    d = score_runs_shifted(maps[2], body.runs[2], np.arange(n, dtype=np.int64), zero, zero)
    # the filter holds a leaf that fits a little worse and whose prediction gives the
    # shown leaf (almost) nothing
    def held_gives(a: int) -> float:
        f = TreeFilter(tree, body, SilhouetteOptions(uniform=1e-6))
        f.posterior = np.zeros(n)
        f.posterior[a] = 1.0
        return float(f.predict()[shown_leaf])

    held = next(int(a) for a in np.argsort(d) if d[a] >= 0.02 and held_gives(int(a)) < 1e-4)
    # a likelihood 4 nats better for the shown leaf: less than the prior's ratio
    sigma = float(d[held]) / np.sqrt(8.0) / tree.options.thresholds[2]
    leaf, post, prior = {}, {}, np.zeros(n)
    for share in (0.0, 0.3):
        f = TreeFilter(tree, body, SilhouetteOptions(uniform=1e-6, sigma=sigma, explore=8,
                                                     fit_prior=share))
        f.posterior = np.zeros(n)
        f.posterior[held] = 1.0
        prior = f.predict()
        step = f.step(maps)  # type: ignore[arg-type]
        leaf[share], post[share] = step.leaf, float(f.posterior[step.leaf])
        assert f.posterior.sum() == pytest.approx(1.0)
    assert d[leaf[0.0]] > 0.8 * d[held]  # the prediction wins: a pose near the held one
    # the evidence wins: a pose that fits several times better, the prediction gave ~0
    assert d[leaf[0.3]] < 0.25 * d[held] and prior[leaf[0.3]] < 1e-4 and post[0.3] > 0.2


def test_filter_searches_the_template_vertically_when_asked(
        silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    # a player shorter than the body preset: the template fits a few pixels lower than
    # the floor puts it
    from bodyplay.trackers.silhouette.options import SilhouetteOptions
    from bodyplay.trackers.silhouette.treefilter import TreeFilter

    tree = silhouette_tree
    body = tree.bodies["m"]
    maps = _shown(body, tree.num_leaves // 2, down=3)
    steps = {}
    for y in (0, 1):
        f = TreeFilter(tree, body, SilhouetteOptions(shift_search=(1, y)))
        for _ in range(3):
            steps[y] = f.step(maps)  # type: ignore[arg-type]
    assert steps[0].evaluations[0] == tree.level_sizes[0] * 3  # x only
    assert steps[1].evaluations[0] == tree.level_sizes[0] * 9
    assert steps[0].shift[1] == 0 and steps[1].shift[1] > 0
    assert steps[1].distance < 0.5 * steps[0].distance


def test_options_reject_a_fit_prior_outside_0_to_1() -> None:
    from bodyplay.trackers.silhouette.options import SilhouetteOptions

    for bad in (-0.1, 1.0, 2.0):
        with pytest.raises(ConfigError, match="fit_prior"):
            SilhouetteOptions(fit_prior=bad)
    assert SilhouetteOptions().fit_prior == 0.0  # the paper's prediction alone by default


def test_cache_is_rebuilt_when_its_version_changes(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.trackers.silhouette import hierarchy

    opts = HierarchyOptions(clips=("131_01",), yaw_offsets_deg=(0.0,), random_share=0.0,
                            bodies=("m",), thresholds=(0.1, 0.08, 0.06), max_poses=60,
                            dedup_deg=12.0)
    tree = hierarchy.load_or_build_tree(opts, tmp_path)
    path = hierarchy.tree_cache_path(opts, tmp_path)
    assert path.exists() and not list(tmp_path.glob("*.tmp*"))
    key = path.stem.rsplit("_", 1)[-1]
    assert hierarchy.ShapeTree.load(path, opts, key).level_sizes == tree.level_sizes
    monkeypatch.setattr(hierarchy, "FORMAT_VERSION", hierarchy.FORMAT_VERSION + 1)
    with pytest.raises(ValueError, match="stale"):
        hierarchy.ShapeTree.load(path, opts, key)
    built = []
    real = hierarchy.build_tree
    monkeypatch.setattr(hierarchy, "build_tree",
                        lambda o, progress=False: built.append(1) or real(o, progress))
    path2 = hierarchy.tree_cache_path(opts, tmp_path)
    hierarchy.load_or_build_tree(opts, tmp_path)
    assert built == [1] and path2.exists()


def test_options_reject_nonsense() -> None:
    from bodyplay.trackers.silhouette.options import SilhouetteOptions

    with pytest.raises(ConfigError):
        HierarchyOptions(thresholds=(0.1, -1.0, 0.1))
    with pytest.raises(ConfigError):
        SilhouetteOptions(occlusion_m=0.5)
    with pytest.raises(ConfigError):
        BackgroundOptions(rate=2.0)
    with pytest.raises(ConfigError, match="protect_radius"):
        SilhouetteOptions(protect_radius=1.5)
    with pytest.raises(ConfigError, match="beta"):
        SilhouetteOptions(beta=0.0)


@pytest.mark.parametrize("field", ["explore", "min_height", "box_below", "depth_window",
                                   "max_recession", "bootstrap_time"])
def test_options_reject_a_negative_count_length_or_time(field: str) -> None:
    from bodyplay.trackers.silhouette.options import SilhouetteOptions

    with pytest.raises(ConfigError, match=field):
        SilhouetteOptions(**{field: -1})  # type: ignore[arg-type]


def test_factory_needs_a_camera_and_uses_the_first_of_a_rig(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.capture.camera import Camera
    from bodyplay.trackers.silhouette import create_silhouette_tracker

    cam = Camera.from_fov("cam0", 640, 480, 60.0)
    with pytest.raises(ConfigError, match="one calibrated camera"):
        create_silhouette_tracker(cameras=(), tree=silhouette_tree)
    t = create_silhouette_tracker(cameras=(cam, Camera.from_fov("cam1", 320, 240, 60.0)),
                                  tree=silhouette_tree)
    assert t.name == "silhouette" and t.cameras == (cam,)


def test_silhouette_is_a_tracker_plugin() -> None:
    from bodyplay.plugins import PluginRegistry

    assert "silhouette" in PluginRegistry().names("trackers")


def test_shifted_run_scoring_equals_scoring_the_moved_template() -> None:
    from bodyplay.trackers.silhouette.distance import score_runs_shifted

    maps = distance_maps(_blob())
    runs = encode_runs(_blob()[None])
    for dx in (-3, 0, 2):
        moved = np.roll(_blob(), dx, axis=1)  # the blob is far from the window's sides
        got = score_runs_shifted(maps, runs, np.array([0]), np.array([dx]), np.array([0]))
        assert got[0] == pytest.approx(score_direct(maps, moved), rel=1e-9, abs=1e-12)


def test_first_build_of_the_hierarchy_is_announced_with_its_cache_path(
        tmp_path, caplog, capsys) -> None:  # type: ignore[no-untyped-def]
    import logging

    from bodyplay.trackers.silhouette import hierarchy

    opts = HierarchyOptions(clips=("131_01",), yaw_offsets_deg=(0.0,), random_share=0.0,
                            bodies=("m",), thresholds=(0.1, 0.08, 0.06), max_poses=40,
                            dedup_deg=12.0)
    path = hierarchy.tree_cache_path(opts, tmp_path)
    with caplog.at_level(logging.INFO, logger="bodyplay.silhouette"):
        hierarchy.load_or_build_tree(opts, tmp_path)
    building = [r for r in caplog.records if "building the silhouette shape hierarchy"
                in r.getMessage()]
    assert len(building) == 1 and building[0].levelno == logging.WARNING
    assert str(path) in building[0].getMessage() and "once" in building[0].getMessage()
    assert "%|" not in capsys.readouterr().err  # no bar when stderr is not a terminal
    caplog.clear()
    with caplog.at_level(logging.INFO, logger="bodyplay.silhouette"):
        hierarchy.load_or_build_tree(opts, tmp_path)  # cached: silent
    assert not caplog.records


def test_track_set_overrides_silhouette_options_and_rejects_unknown_names() -> None:
    from bodyplay.commands.track import _silhouette_options

    opts = _silhouette_options(["max_distance=12", "shift_search=2,1", "body=m"])
    assert opts.max_distance == 12.0 and opts.shift_search == (2, 1) and opts.body == "m"
    with pytest.raises(ConfigError, match="max_distance"):
        _silhouette_options(["max_distanse=12"])
    with pytest.raises(ConfigError, match="cannot read"):
        _silhouette_options(["max_distance=far"])
    with pytest.raises(ConfigError):
        _silhouette_options(["sigma=-1"])  # the options' own validation still applies


def test_hierarchy_keeps_clip_poses_past_the_joint_limits_only_when_clamp_is_off(tmp_path):
    # the ninja's hit swings the arm to 1.9 rad from the T-pose, past the shoulder's
    # 1.7 rad limit: clamped, the hierarchy's hit is 0.2 rad low and its template
    # scores worse than arms down against the player's silhouette
    from bodyplay.body.skeleton import Skeleton
    from bodyplay.motion import write_bvh
    from bodyplay.testing import Timeline
    from bodyplay.trackers.silhouette.poses import training_poses

    sk = Skeleton.from_shape("m")
    tl = Timeline(sk, blend=0.15).hold("idle", 0.5)
    tl.gesture("hit", start=0.6)
    tl.hold("idle", 0.5)
    path = write_bvh(tmp_path / "hit.bvh", sk, tl.poses(np.arange(0.0, tl.duration, 1 / 30)), 30.0)
    lo, hi = sk.limits
    past = []
    for clamp in (True, False):
        opts = HierarchyOptions(clips=(str(path),), yaw_offsets_deg=(0.0,), random_share=0.0,
                                clamp=clamp)
        poses = training_poses(sk, opts).poses
        past.append(float(np.max(np.maximum(lo - poses, poses - hi))))
        assert ("clamp" in dict(opts.key_items())) is (not clamp)  # old caches stay valid
    assert past[0] <= 1e-9 and past[1] > 0.1


def test_dilate_disc_sets_the_pixels_opencvs_ellipse_dilation_sets() -> None:
    import cv2

    from bodyplay.trackers.silhouette.window import dilate_disc

    rng = np.random.default_rng(4)
    for shape, share, radius in (((240, 320), 0.001, 28), ((120, 160), 0.05, 3),
                                 ((60, 80), 0.0, 7), ((5, 1), 0.5, 12), ((240, 320), 0.3, 1)):
        mask = (rng.random(shape) < share).astype(np.uint8)
        mask[shape[0] // 3: shape[0] // 2, shape[1] // 4: shape[1] // 3] = 1
        k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1,) * 2)
        np.testing.assert_array_equal(dilate_disc(mask, radius), cv2.dilate(mask, k))
    np.testing.assert_array_equal(dilate_disc(np.zeros((9, 9), np.uint8), 4), 0)


def test_normalized_color_is_chromaticity_over_the_offset_sum_and_intensity() -> None:
    from bodyplay.trackers.silhouette.background import normalized_color

    img = np.array([[[0, 0, 0], [255, 255, 255], [200, 40, 10]]], np.uint8)
    out = normalized_color(img)
    assert out.dtype == np.float32 and out.shape == img.shape
    f = img.astype(np.float32)
    s = f.sum(axis=2)
    np.testing.assert_array_equal(out[..., 0], f[..., 0] * (1.0 / (s + 30.0)))
    np.testing.assert_array_equal(out[..., 1], f[..., 1] * (1.0 / (s + 30.0)))
    np.testing.assert_array_equal(out[..., 2], s * np.float32(1.0 / 765.0))
