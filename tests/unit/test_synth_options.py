"""Specifications of the synthetic camera's options, rig, lighting and sensor (no GL)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.synth.backgrounds import background_names, load_background
from bodyplay.synth.lighting import LIGHTING_PRESETS, kelvin_to_rgb, lighting_preset
from bodyplay.synth.occluder import Occlusion, parse_occlusion
from bodyplay.synth.options import SyntheticCameraOptions, make_synthetic_camera_options
from bodyplay.synth.rig import frame_rig, make_rig_options, out_of_view_frames
from bodyplay.synth.sensor import Sensor, noise_level


def test_options_reject_unknown_lighting_preset_naming_the_valid_ones():
    with pytest.raises(ConfigError, match="unknown lighting preset 'disco'.*steady"):
        make_synthetic_camera_options(lighting="disco")


@pytest.mark.parametrize("size", ["640", "640x", "axb", "10x10", "641x480", "640x480x3"])
def test_options_reject_bad_size(size):
    with pytest.raises(ConfigError, match="size"):
        make_synthetic_camera_options(size=size)


@pytest.mark.parametrize(
    ("kw", "what"),
    [({"noise": "extreme"}, "noise"), ({"body": "giant"}, "body preset"),
     ({"cameras": 3}, "cameras"), ({"format": "gif"}, "format"),
     ({"background": "/no/such/file.png"}, "background"), ({"fps": 0}, "fps")],
)
def test_options_reject_bad_values_with_a_message_naming_them(kw, what):
    with pytest.raises(ConfigError, match=what):
        make_synthetic_camera_options(**kw)


def test_options_round_trip_through_dict():
    o = make_synthetic_camera_options(
        cameras=2, size="320x240", lighting="switch", noise="high", occlusions=["1:0.5"],
        seed=7, format="png", k1=-0.05, background="#336699",
    )
    again = SyntheticCameraOptions.from_dict(o.to_dict())
    assert again == o
    assert again.occlusions == (Occlusion(1.0, 0.5),)


def test_parse_occlusion_reads_start_and_length_and_rejects_garbage():
    occ = parse_occlusion("1.5:0.8")
    assert occ.active(1.5) and occ.active(2.29) and not occ.active(2.31) and not occ.active(1.4)
    for bad in ("1.5", "a:b", "1:-2", "-1:1"):
        with pytest.raises(ConfigError):
            parse_occlusion(bad)


def test_tungsten_is_warm_and_daylight_is_cool_relative_to_the_camera_white():
    r, g, b = kelvin_to_rgb(2800.0)
    assert r > g > b
    r, g, b = kelvin_to_rgb(7500.0)
    assert b > g > r
    assert np.allclose(kelvin_to_rgb(5000.0), (1.0, 1.0, 1.0), atol=1e-6)


def test_switch_preset_turns_the_warm_lamp_off_at_mid_clip():
    p = lighting_preset("switch")
    before, after = p.state(4.9, 10.0), p.state(5.1, 10.0)
    assert len(before.lights) == len(after.lights) + 1
    ill_b, ill_a = before.room_illuminant(), after.room_illuminant()
    assert ill_a.sum() < 0.8 * ill_b.sum()  # darker
    assert ill_a[2] / ill_a[0] > 1.3 * ill_b[2] / ill_b[0]  # bluer
    assert set(LIGHTING_PRESETS) == {"steady", "tungsten", "fluorescent", "dim", "mixed", "switch"}


def test_dim_sensor_is_noisier_than_steady_sensor():
    rng = np.random.default_rng(0)
    flat = np.full((64, 64, 3), 0.2, np.float32)
    level = noise_level("none")
    level = type(level)("test", 4000.0, 4.0, None)
    steady = Sensor(level, lighting_preset("steady").gain).develop(flat.copy(), rng)
    dim = Sensor(level, lighting_preset("dim").gain).develop(flat.copy(), rng)
    assert dim.astype(float).std() > 1.8 * steady.astype(float).std() > 0
    clean = Sensor(noise_level("none")).develop(flat.copy(), rng)
    assert clean.std() == 0 and abs(int(clean[0, 0, 0]) - 124) <= 1  # sRGB of linear 0.2


def test_rig_keeps_every_joint_of_a_moving_clip_in_view_at_webcam_distance(skeleton):
    t = np.linspace(0, 2 * np.pi, 40)
    poses = np.repeat(skeleton.rest_pose()[None], len(t), 0)
    poses[:, 0] = 0.6 * np.sin(t)  # side steps
    poses[:, 1] += 0.15 * np.abs(np.sin(2 * t))  # hops
    joints = skeleton.joint_positions(poses)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rig = frame_rig(joints, make_rig_options(seed=3))
    assert 2.5 <= rig.distance <= 4.0
    assert out_of_view_frames(rig.cameras, joints).size == 0
    cam = rig.cameras[0]
    assert abs(cam.hfov_deg - 60.0) < 1e-6
    chest = np.median(joints[:, 2, 1])
    assert abs(cam.center[1] - chest) <= 0.06  # at chest height
    assert cam.center[2] > 2.0  # in front (the actor faces +Z)


def test_two_camera_rig_is_a_converging_pair_one_to_two_metres_apart(skeleton):
    joints = skeleton.joint_positions(skeleton.rest_pose())[None]
    rig = frame_rig(joints, make_rig_options(cameras=2, seed=5))
    c0, c1 = (c.center for c in rig.cameras)
    assert 1.0 <= np.linalg.norm(c0 - c1) <= 2.0
    # both look at the target: it projects near both image centres
    for cam in rig.cameras:
        u, v = cam.project(rig.target)
        assert abs(u - 319.5) < 1 and abs(v - 239.5) < 1
    again = frame_rig(joints, make_rig_options(cameras=2, seed=5))
    assert np.array_equal(again.cameras[1].t, rig.cameras[1].t)
    other = frame_rig(joints, make_rig_options(cameras=2, seed=6))
    assert not np.array_equal(other.cameras[1].t, rig.cameras[1].t)


def test_rig_warns_when_the_actor_leaves_the_picture():
    sk = Skeleton()
    joints = sk.joint_positions(sk.rest_pose())[None]
    far = joints.copy()
    far[..., 0] += 5.0
    with pytest.warns(UserWarning, match="leaves the picture"):
        frame_rig(np.concatenate([joints, far]), make_rig_options(distance=3.0))


def test_backgrounds_ship_small_photos_and_accept_plain_colors():
    names = background_names()
    assert {"brick", "coffee", "plain"} <= set(names)
    img = load_background("coffee", 320, 240)
    assert img.shape == (240, 320, 3) and img.dtype == np.uint8 and img.std() > 10
    assert np.all(load_background("#ff8000", 8, 8) == (255, 128, 0))
    with pytest.raises(ConfigError, match="unknown background"):
        load_background("nowhere", 8, 8)
