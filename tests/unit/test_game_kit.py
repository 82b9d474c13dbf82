"""Specifications of the game kit's pure parts: options, scene draw lists, inputs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bodyplay.app import Game, Scene, make_game_options, open_game_input
from bodyplay.app.scene import LOST_COLOR
from bodyplay.errors import BodyplayError, ConfigError


def test_game_options_reject_bad_values_naming_the_option() -> None:
    with pytest.raises(ConfigError, match="cameras"):
        make_game_options(cameras=3)
    with pytest.raises(ConfigError, match="seconds"):
        make_game_options(seconds=-1.0)
    with pytest.raises(ConfigError, match="update_hz"):
        make_game_options(update_hz=0.5)
    with pytest.raises(ConfigError, match="pose:CLIP"):
        make_game_options(input="pose:")
    with pytest.raises(ConfigError, match="unknown game option"):
        make_game_options(speed=2)


def test_game_options_default_to_the_virtual_player_and_a_fixed_step() -> None:
    o = make_game_options(out="x")
    assert o.input == "virtual" and o.out == Path("x")
    assert o.dt == pytest.approx(1 / 60)
    assert make_game_options(o, headless=True).is_headless


def test_scene_collects_primitives_and_skips_lost_ones() -> None:
    s = Scene()
    s.sphere((0, 1, 0), 0.1, (1, 0, 0), shadow=True)
    s.sphere((np.nan, 1, 0), 0.1)
    s.capsule((0, 0, 0), (0, 1, 0), 0.05)
    s.box((0, 0.5, 0), (1, 1, 1))
    s.text("hello")
    assert len(s.spheres) == 1 and len(s.shadows) == 1
    assert len(s.capsules) == 1 and len(s.boxes) == 1 and len(s.texts) == 1
    with pytest.raises(ConfigError):
        s.mesh(np.zeros((3, 3)), np.array([[0, 1, 5]]))
    with pytest.raises(ConfigError):
        s.text("x", anchor="top")  # type: ignore[arg-type]


def test_avatar_draws_lost_bones_in_the_lost_color_where_last_seen() -> None:
    from bodyplay.body.skeleton import Skeleton

    j = Skeleton().joint_positions(Skeleton().rest_pose())
    state = ["tracked"] * 17
    state[10] = "lost"  # r_wrist
    joints = j.copy()
    joints[10] = np.nan
    s = Scene()
    s.avatar(joints, state, last_seen=j)
    lost = [c for c in s.capsules if tuple(c[7:10]) == LOST_COLOR]
    assert len(lost) == 1  # the right forearm only
    assert np.allclose(lost[0][3:6], j[10])  # drawn to where the wrist was last seen


def test_avatar_stands_never_seen_legs_under_the_pelvis() -> None:
    from bodyplay.body.skeleton import Skeleton

    j = Skeleton().joint_positions(Skeleton().rest_pose())
    joints = j.copy()
    joints[11:] = np.nan
    s = Scene()
    s.avatar(joints)
    lost = [c for c in s.capsules if tuple(c[7:10]) == LOST_COLOR]
    assert len(lost) == 6  # two hips, two thighs, two shins
    assert min(min(c[1], c[4]) for c in lost) < 0.2  # down to the floor


def test_missing_webcam_names_the_virtual_default() -> None:
    with pytest.raises(BodyplayError, match="--input virtual"):
        open_game_input(make_game_options(input="97"), Game())


def test_missing_capture_folder_names_the_virtual_default(tmp_path: Path) -> None:
    with pytest.raises(BodyplayError, match="--input virtual"):
        open_game_input(make_game_options(input=str(tmp_path / "nope")), Game())


def test_unknown_clip_names_the_virtual_default() -> None:
    with pytest.raises(BodyplayError, match="--input virtual"):
        open_game_input(make_game_options(input="pose:no_such_clip"), Game())


def test_a_game_without_virtual_player_says_what_to_pass() -> None:
    with pytest.raises(ConfigError, match="no virtual player"):
        open_game_input(make_game_options(), Game())


def test_clip_input_is_pose_level_with_the_clip_rate() -> None:
    inp = open_game_input(make_game_options(input="pose:13_29"), Game())
    assert inp.session.tracker is None and inp.kind == "clip" and inp.fps > 0
    inp.session.close()


def test_camera_inset_shows_the_picture_with_the_skeleton_and_skips_pose_input():
    from types import SimpleNamespace

    from bodyplay.app import Scene, camera_inset
    from bodyplay.capture.camera import Camera, look_at
    from bodyplay.capture.frames import Frame, FrameSet

    R, t = look_at(np.array([0.0, 1.2, 3.0]), np.array([0.0, 1.0, 0.0]))
    cam = Camera.from_fov("cam0", 64, 48, 60.0, R, t)
    img = np.zeros((48, 64, 3), np.uint8)
    fs = FrameSet((Frame(img, 0.0, 0),), 0.0, 0)
    joints = np.zeros((17, 3)) + [0.0, 1.0, 0.0]
    joints[:, 0] = np.linspace(-0.3, 0.3, 17)
    ctx = SimpleNamespace(frame=fs, session=SimpleNamespace(cameras=(cam,)),
                          pose=SimpleNamespace(joints=joints))
    scene = Scene()
    camera_inset(ctx, scene, 32)  # type: ignore[arg-type]
    assert len(scene.insets) == 1 and scene.insets[0].image.max() > 0
    empty = Scene()
    camera_inset(SimpleNamespace(frame=None, session=SimpleNamespace(cameras=()), pose=None),
                 empty)  # type: ignore[arg-type]
    assert not empty.insets


def test_preferred_tracker_takes_the_first_installed_and_falls_back() -> None:
    from bodyplay.app import preferred_tracker

    assert preferred_tracker("no_such_tracker", "colorshirt") == "colorshirt"
    assert preferred_tracker("no_such_tracker", fallback="silhouette") == "silhouette"
    assert preferred_tracker("silhouette") == "silhouette"
