"""Specifications of bodyplay.cloth: pins, collisions, energy, determinism, options."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.cloth import (
    CAPSULE_NAMES,
    BodyCapsules,
    Cloth,
    ClothOptions,
    Garment,
    body_capsules,
    body_frames,
    cape,
    garment,
    kernels,
    robe,
    skirt,
)
from bodyplay.errors import ConfigError
from bodyplay.motion import load_clip

DT = 1.0 / 60.0


@pytest.fixture(scope="module")
def jacks() -> np.ndarray:
    """Joints (T, 17, 3) of the real CMU 13_29 jumping jacks at 60 Hz (frame 0 dropped:
    the file's first frame is a glitch)."""
    return load_clip("13_29").resample(60).joints()[1:]


def _run(cloth: Cloth, joints: np.ndarray) -> list:
    return [cloth.step(DT, j) for j in joints]


def test_garment_builders_make_a_few_thousand_particles_with_pins() -> None:
    for build in (robe, cape, skirt):
        g = build()
        assert 2000 <= g.num_particles <= 4000, (g.name, g.num_particles)
        assert len(g.pins) > 0
        assert g.vertices.shape == (g.num_particles, 3)
    assert garment("skirt", resolution=0.5).num_particles < skirt().num_particles


def test_garment_rejects_unknown_names_and_bad_arrays() -> None:
    with pytest.raises(ConfigError, match="robe"):
        garment("kimono")
    with pytest.raises(ConfigError, match="resolution"):
        robe(resolution=0.0)
    g = cape(resolution=0.3)
    with pytest.raises(ConfigError, match="faces"):
        Garment("bad", g.vertices, g.faces + len(g.vertices), g.pins, g.pin_frames, g.rest_joints)
    with pytest.raises(ConfigError, match="pin"):
        Garment("bad", g.vertices, g.faces, g.pins, g.pin_frames[:-1], g.rest_joints)


@pytest.mark.parametrize("field,value", [
    ("substep", 0.0), ("substep", float("nan")), ("gravity", (0.0, -9.8)),
    ("wind", "east"), ("density", 0.0), ("stretch_compliance", -1.0), ("friction", 1.5),
    ("thickness", -0.01), ("self_collision", 1), ("max_joint_speed", 0.0),
    ("teleport_distance", float("inf")), ("body_height", 7.0), ("dress_seconds", -1.0),
])
def test_cloth_options_reject_bad_values_with_config_error(field: str, value: object) -> None:
    with pytest.raises(ConfigError, match=field):
        ClothOptions(**{field: value})


def test_step_rejects_bad_dt_and_joint_shapes() -> None:
    cloth = Cloth(skirt(resolution=0.3))
    j = cloth.garment.rest_joints
    for dt in (0.0, -DT, 1.0, float("nan")):
        with pytest.raises(ConfigError, match="dt"):
            cloth.step(dt, j)
    with pytest.raises(ConfigError, match="17"):
        cloth.step(DT, np.zeros((11, 3)))
    with pytest.raises(ConfigError, match="inf"):
        cloth.step(DT, np.full((17, 3), np.inf))
    with pytest.raises(ConfigError, match="Garment"):
        Cloth("robe")  # type: ignore[arg-type]


def test_constraint_colours_never_share_a_particle() -> None:
    cloth = Cloth(robe(resolution=0.5))
    for c in range(cloth.num_colors):
        a, b = cloth._cstart[c], cloth._cstart[c + 1]
        used = np.concatenate([cloth._ci[a:b], cloth._cj[a:b]])
        assert len(np.unique(used)) == len(used)
    assert cloth.num_colors < 64


def test_cloth_waits_for_a_pose_then_dresses_the_body(jacks: np.ndarray) -> None:
    cloth = Cloth(skirt(resolution=0.5))
    before = cloth.positions.copy()
    r = cloth.step(DT, None)
    assert not r.dressed and r.substeps == 0
    assert np.array_equal(cloth.positions, before)
    r = cloth.step(DT, jacks[0])
    assert r.dressed and r.substeps > 0
    assert r.pin_error < 1e-9


def test_pinned_particles_follow_their_joints(jacks: np.ndarray) -> None:
    for build in (robe, skirt):
        cloth = Cloth(build(resolution=0.5), ClothOptions(max_joint_speed=1000.0))
        g = cloth.garment
        local = g.pin_offsets()
        for j in jacks[:240:3]:
            r = cloth.step(DT, j)
            origins, rots = body_frames(j)
            want = origins[g.pin_frames] + np.einsum("pij,pj->pi", rots[g.pin_frames], local)
            assert np.max(np.abs(cloth.positions[g.pins] - want)) < 1e-9
            assert r.pin_error < 1e-9


def test_no_free_particle_ends_more_than_1cm_inside_a_capsule(jacks: np.ndarray) -> None:
    for build in (robe, cape, skirt):
        cloth = Cloth(build(resolution=0.6))
        worst = 0.0
        for j in jacks[:300]:
            cloth.step(DT, j)
            caps = cloth.capsules()
            assert caps is not None
            depth = caps.penetration(cloth.positions)
            depth[cloth.garment.pins] = 0.0
            worst = max(worst, float(depth.max()))
        assert worst <= 0.01, (cloth.garment.name, worst)


def test_capsules_cover_the_body_and_scale_with_height(jacks: np.ndarray) -> None:
    caps = body_capsules(jacks[0], 1.75)
    assert len(caps.radius) == len(CAPSULE_NAMES)
    inside = caps.penetration(jacks[0][[0, 2, 4, 6, 12]])  # pelvis, chest, head, elbow, knee
    assert np.all(inside > 0.03)
    assert np.allclose(body_capsules(jacks[0], 2.0).radius, caps.radius * 2.0 / 1.75)


def test_same_input_gives_identical_cloth(jacks: np.ndarray) -> None:
    seq: list[np.ndarray | None] = list(jacks[:60])
    lost = jacks[60].copy()
    lost[7] = np.nan  # a lost wrist
    seq += [lost, None, None, jacks[63] + [1.5, 0.0, 0.0], jacks[64] + [1.5, 0.0, 0.0]]
    runs = []
    for _ in range(2):
        cloth = Cloth(robe(resolution=0.5), ClothOptions(wind=(2.0, 0.0, 1.0)))
        results = [cloth.step(DT, j) for j in seq]
        runs.append((cloth.positions.copy(), cloth.velocities.copy(), results))
    assert np.array_equal(runs[0][0], runs[1][0])
    assert np.array_equal(runs[0][1], runs[1][1])
    assert [r.max_strain for r in runs[0][2]] == [r.max_strain for r in runs[1][2]]


def test_lost_tracking_lets_the_cloth_settle(jacks: np.ndarray) -> None:
    cloth = Cloth(cape(resolution=0.5))
    _run(cloth, jacks[:90])
    held = cloth.body_joints
    moving = cloth.energy()[0]
    results = [cloth.step(DT, None) for _ in range(180)]
    assert all(r.lost for r in results)
    assert np.array_equal(cloth.body_joints, held)
    assert results[-1].kinetic_energy < 0.05 * max(moving, 1e-3)
    assert results[-1].kinetic_energy < 1e-3


def test_a_small_tracking_jump_is_crossed_at_the_joint_speed_limit(jacks: np.ndarray) -> None:
    o = ClothOptions(max_joint_speed=4.0)
    cloth = Cloth(skirt(resolution=0.5), o)
    _run(cloth, [jacks[0]] * 30)
    jumped = jacks[0] + np.array([0.3, 0.0, 0.0])
    before = cloth.body_joints
    r = cloth.step(DT, jumped)
    assert not r.teleported
    moved = np.linalg.norm(cloth.body_joints - before, axis=1)
    assert np.all(moved <= o.max_joint_speed * DT + 1e-12)
    assert r.pin_error > 0.2  # the cloth lags the jump instead of snapping
    for _ in range(30):
        r = cloth.step(DT, jumped)
    assert r.pin_error < 1e-9
    assert r.max_penetration <= 0.01


def test_a_large_tracking_jump_moves_body_and_cloth_together(jacks: np.ndarray) -> None:
    cloth = Cloth(robe(resolution=0.5))
    _run(cloth, jacks[:60])
    shift = np.array([2.0, 0.0, -1.0])
    offset = cloth.positions - cloth.body_joints[0]
    r = cloth.step(DT, jacks[60] + shift)
    assert r.teleported
    assert r.max_penetration <= 0.01
    after = cloth.positions - cloth.body_joints[0]
    assert np.median(np.linalg.norm(after - offset, axis=1)) < 0.05
    assert r.kinetic_energy < 5.0


LOOP_S = 8.0


def _loop_energy(jacks: np.ndarray, loops: int, resolution: float) -> tuple[np.ndarray, float]:
    """Kinetic energy (loops, steps) over ``loops`` passes of the first 8 s of jumping
    jacks, looped (the end jumps back to the start: a tracking jump every loop), and the
    cloth's mass."""
    cloth = Cloth(skirt(resolution=resolution))
    part = jacks[: int(LOOP_S / DT)]
    ke = np.array([[cloth.step(DT, j).kinetic_energy for j in part] for _ in range(loops)])
    assert np.all(np.isfinite(cloth.positions))
    return ke, float(np.sum(cloth._mass))


def _check_bounded(ke: np.ndarray, mass: float) -> None:
    assert np.all(np.isfinite(ke))
    # the body gives the cloth its energy: never faster (rms) than the speed limit of
    # the driving joints (ClothOptions.max_joint_speed, 5 m/s)
    assert ke.max() < 0.5 * mass * ClothOptions().max_joint_speed ** 2
    # no growth: every pass through the same motion has about the same energy
    means = ke.mean(axis=1)
    assert np.all(means[1:] <= 1.5 * means[:2].max())


def test_energy_stays_bounded_over_a_long_run(jacks: np.ndarray) -> None:
    _check_bounded(*_loop_energy(jacks, 4, 0.4))  # 32 s


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_energy_stays_bounded_over_ten_minutes(jacks: np.ndarray) -> None:
    _check_bounded(*_loop_energy(jacks, int(600 / LOOP_S), 0.6))  # 36,000 steps


def test_parallel_solver_gives_the_serial_result(jacks: np.ndarray) -> None:
    out = []
    for parallel in (False, True):
        cloth = Cloth(cape(resolution=0.4), ClothOptions(parallel=parallel))
        _run(cloth, jacks[:20])
        out.append(cloth.positions.copy())
    assert np.array_equal(out[0], out[1])


def test_self_pairs_finds_close_particles_only_once() -> None:
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 0.2, (400, 3))
    rest = x * 10.0  # far apart at rest: every close pair counts
    pi, pj, ph = kernels.self_pairs(x, rest, 0.03, 0.01)
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    i, j = np.nonzero(np.triu(d < 0.03, k=1))
    want = set(zip(i.tolist(), j.tolist(), strict=True))
    got = list(zip(pi.tolist(), pj.tolist(), strict=True))
    assert len(got) == len(set(got)) and set(got) == want
    assert np.all(ph == 0.01)


def test_an_upper_body_pose_dresses_and_unseen_legs_follow_the_torso(jacks: np.ndarray) -> None:
    cloth = Cloth(skirt(resolution=0.4))
    upper = jacks[0].copy()
    upper[11:] = np.nan  # an upper-body tracker: no hips, knees, ankles
    assert cloth.step(DT, upper).dressed
    legs = cloth.body_joints[11:]
    assert np.all(np.isfinite(legs))
    moved = upper + np.array([0.05, 0.0, 0.0])
    for _ in range(5):
        r = cloth.step(DT, moved)
    assert np.allclose(cloth.body_joints[11:], legs + [0.05, 0.0, 0.0], atol=1e-9)
    assert r.max_penetration <= 0.01


def test_self_collision_keeps_a_crumpled_sheet_from_passing_through_itself() -> None:
    g0 = cape()
    # the cape unpinned, 3 m beside the body and 1 m up: it falls and piles on the floor
    sheet = Garment("sheet", g0.vertices + [-3.0, 1.0, 0.0], g0.faces, np.zeros(0, np.int64),
                    np.zeros(0, np.int64), g0.rest_joints)
    close = {}
    for on in (True, False):
        cloth = Cloth(sheet, ClothOptions(self_collision=on, dress_seconds=0.0))
        for _ in range(150):
            cloth.step(DT, sheet.rest_joints)
        # pairs not neighbours in the mesh that ended closer than half the kept distance
        pi, _, _ = kernels.self_pairs(cloth.positions, sheet.vertices, 0.005, 0.01)
        close[on] = len(pi)
    assert close[False] > 50
    assert close[True] == 0


def test_body_height_is_the_median_of_the_first_poses(jacks: np.ndarray) -> None:
    from bodyplay.cloth.body import body_height

    cloth = Cloth(skirt(resolution=0.3))
    bad = jacks[0].copy()
    bad[3:11] += [0.0, 0.3, 0.0]  # a tracker's first guess: the torso 0.3 m too long
    cloth.step(DT, bad)
    assert cloth.height is not None and cloth.height > 2.0
    for j in jacks[1:40]:
        cloth.step(DT, j)
    assert abs(cloth.height - body_height(jacks[20])) < 0.02
    fixed = Cloth(skirt(resolution=0.3), ClothOptions(body_height=1.6))
    fixed.step(DT, bad)
    assert fixed.height == 1.6


def test_separate_limbs_moves_a_sunken_elbow_out_of_the_torso(jacks: np.ndarray) -> None:
    from bodyplay.cloth.body import body_capsules as caps_of

    sunk = jacks[0].copy()
    sunk[6] = 0.5 * (sunk[0] + sunk[3])  # left elbow on the spine
    for separate in (False, True):
        cloth = Cloth(skirt(resolution=0.3), ClothOptions(separate_limbs=separate))
        cloth.step(DT, sunk)
        for _ in range(20):
            cloth.step(DT, sunk)
        body = cloth.body_joints
        caps = caps_of(body, cloth.height)
        torso = [CAPSULE_NAMES.index("torso_l"), CAPSULE_NAMES.index("torso_r")]
        inside = BodyCapsules(caps.a[torso], caps.b[torso], caps.radius[torso]).penetration(
            body[6:7])[0]
        if separate:
            # the elbow's arm capsule only touches the torso: its centre is outside
            assert inside == 0.0
        else:
            assert inside > 0.05


def test_resolve_union_frees_a_particle_pinched_between_arm_and_torso() -> None:
    # the case of the robe on the jumping jacks: a particle 0.3 mm inside the torso
    # and on the upper arm's surface, where the arm presses on the torso; each
    # capsule's exit point lies inside the other
    a = np.array([[-0.0547, 0.9296, 0.0053], [-0.1806, 1.4150, -0.0334],
                  [-0.2434, 1.1363, -0.0277]])
    b = np.array([[-0.0638, 1.3523, -0.0238], [-0.2434, 1.1363, -0.0277],
                  [-0.2926, 0.8829, -0.0291]])
    radius = np.array([0.12056, 0.06135, 0.05148])
    x = np.array([[-0.17650, 1.15859, -0.03928]])
    # put it exactly on the arm's surface and inside the torso
    t = float(np.clip((x[0] - a[1]) @ (b[1] - a[1]) / ((b[1] - a[1]) @ (b[1] - a[1])), 0, 1))
    axis = a[1] + t * (b[1] - a[1])
    x[0] = axis + (x[0] - axis) / np.linalg.norm(x[0] - axis) * (radius[1] - 1e-5)
    before = kernels.penetration(x, a, b, radius)[0]
    assert before > 1e-4
    cand = np.array([[0, 1, 2, 0, 0, 0]])
    ncand = np.array([3])
    start = x.copy()
    kernels.resolve_union(x, np.ones(1), a, b, radius, cand, ncand)
    assert kernels.penetration(x, a, b, radius)[0] < 1e-5
    assert np.linalg.norm(x - start) < 0.05  # out along the crease, not through the arm
