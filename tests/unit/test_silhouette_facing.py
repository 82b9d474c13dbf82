"""The pose of a player filmed from behind (trackers/silhouette/facing.py)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.trackers.silhouette import SilhouetteOptions
from bodyplay.trackers.silhouette.facing import (
    LR_SWAP,
    reflect_joints,
    reflect_output,
    reflect_pose,
    sight_normal,
)

EYE = np.array([0.4, 2.6, -3.5])  # a camera high above the floor, looking down at the player


def _camera() -> Camera:
    R, t = look_at(EYE, (0.0, 1.0, 0.0))
    return Camera.from_fov("cam0", 640, 480, 60.0, R, t)


def _front_pose(sk: Skeleton) -> np.ndarray:
    """A pose with depth in it (a step, an arm forward, the trunk turned 20 degrees),
    standing at the origin and roughly facing the camera (which is at -Z)."""
    rot = {"l_shoulder": (0.0, 0.0, -0.9), "l_elbow": (0.0, -1.2, 0.0),
           "r_shoulder": (0.6, 0.0, 0.9), "l_hip": (-0.5, 0.0, 0.0), "l_knee": (0.7, 0.0, 0.0),
           "r_hip": (0.3, 0.0, 0.0)}
    q = sk.pose(rotations=rot)
    turn = Rotation.from_euler("y", np.pi + 0.35)  # rest faces +Z: turn towards the camera
    q[3:6] = (turn * Rotation.from_rotvec(q[3:6])).as_rotvec()
    q[0] = q[2] = 0.0
    return q


def test_reflected_joints_project_where_the_front_joints_do() -> None:
    sk = Skeleton.from_shape("m")
    cam = _camera()
    J = sk.joint_positions(_front_pose(sk))
    B = reflect_joints(J, cam.center)
    # joint j of the back-facing pose lies on the ray of the front pose's partner joint
    assert np.allclose(cam.project(B, distort=False), cam.project(J[LR_SWAP], distort=False),
                       atol=1e-6)


def test_reflected_joints_have_their_depth_mirrored_about_the_pelvis() -> None:
    sk = Skeleton.from_shape("m")
    C = _camera().center
    J = sk.joint_positions(_front_pose(sk))
    B = reflect_joints(J, C)
    s = sight_normal(C, J[JOINT_INDEX["pelvis"]])
    z, zr = (J - C) @ s, float((J[0] - C) @ s)
    assert np.allclose((B - C) @ s, (2 * zr - z)[LR_SWAP], atol=1e-9)
    assert np.allclose(B[JOINT_INDEX["pelvis"]], J[JOINT_INDEX["pelvis"]])
    # the pose has depth: the reflection is not the identity on positions
    assert np.abs(B - J[LR_SWAP]).max() > 0.1


def test_reflection_swaps_left_and_right_and_is_its_own_inverse() -> None:
    sk = Skeleton.from_shape("m")
    C = _camera().center
    J = sk.joint_positions(_front_pose(sk))
    B = reflect_joints(J, C)
    lw, rw = JOINT_INDEX["l_wrist"], JOINT_INDEX["r_wrist"]
    assert JOINT_NAMES[LR_SWAP[lw]] == "r_wrist" and LR_SWAP[JOINT_INDEX["head"]] == JOINT_INDEX[
        "head"]
    # the image position of the front pose's left wrist is the back pose's right wrist
    assert np.allclose(_camera().project(B[rw:rw + 1]), _camera().project(J[lw:lw + 1]))
    assert np.allclose(reflect_joints(B, C), J, atol=1e-9)


def test_a_flat_body_across_the_line_of_sight_only_changes_its_labels() -> None:
    C = np.array([0.0, 2.0, -4.0])
    J = np.zeros((17, 3))
    J[:, 0] = np.linspace(-0.5, 0.5, 17)
    J[:, 1] = np.linspace(0.1, 1.7, 17)  # every joint 4 m away along the level sight
    J[JOINT_INDEX["pelvis"]] = (0.0, 0.9, 0.0)  # straight ahead of the camera
    assert np.allclose(reflect_joints(J, C), J[LR_SWAP])


def test_reflected_pose_vector_is_the_mirror_image_of_the_front_pose() -> None:
    sk = Skeleton.from_shape("m")
    C = _camera().center
    q = _front_pose(sk)
    J = sk.joint_positions(q)
    pelvis = J[JOINT_INDEX["pelvis"]]
    s = sight_normal(C, pelvis)
    planar = J - 2.0 * np.outer((J - pelvis) @ s, s)  # mirror through the vertical plane
    got = sk.joint_positions(reflect_pose(sk, q, pelvis, C))
    assert np.allclose(got, planar[LR_SWAP], atol=1e-6)
    # seen from above, it agrees with the ray reflection of the joints within the
    # body's perspective; heights differ (a joint moved along a ray that looks down
    # rises or drops, the pose vector keeps the heights: feet stay on the floor)
    ray = reflect_joints(J, C)
    assert np.abs((got - ray)[:, [0, 2]]).max() < 0.06
    assert np.allclose(got[:, 1], J[LR_SWAP, 1])


def test_reflect_output_swaps_states_and_confidences_with_the_joints() -> None:
    sk = Skeleton.from_shape("m")
    C = _camera().center
    q = _front_pose(sk)
    J = sk.joint_positions(q)
    states = tuple("inferred" if n.startswith("l_") else "tracked" for n in JOINT_NAMES)
    conf = np.where(np.array([n.startswith("l_") for n in JOINT_NAMES]), 0.5, 1.0)
    J2, q2, st2, c2 = reflect_output(sk, J, q, states, conf, C)  # type: ignore[arg-type]
    assert np.allclose(J2, reflect_joints(J, C))
    assert all(st2[JOINT_INDEX[n]] == ("inferred" if n.startswith("r_") else "tracked")
               for n in JOINT_NAMES)
    assert c2[JOINT_INDEX["r_knee"]] == 0.5 and c2[JOINT_INDEX["l_knee"]] == 1.0
    assert q2.shape == q.shape


def test_reflect_joints_rejects_a_body_under_the_camera() -> None:
    with pytest.raises(ConfigError, match="under the camera"):
        reflect_joints(np.zeros((17, 3)), np.array([0.0, 3.0, 0.0]))


def test_silhouette_options_accept_front_or_away_facing_only() -> None:
    from bodyplay.commands.track import _silhouette_options

    assert SilhouetteOptions().facing == "front"
    assert SilhouetteOptions(facing="away").facing == "away"
    assert _silhouette_options(["facing=away"]).facing == "away"  # `track --set`
    with pytest.raises(ConfigError, match="facing"):
        SilhouetteOptions(facing="back")


def test_reflected_pose_has_the_front_poses_silhouette_far_from_the_camera() -> None:
    # why the tree cannot tell them apart: seen from afar (the tree's templates are
    # rendered from a level camera), the mesh at the reflected pose vector covers the
    # pixels of the front pose; from near and above, perspective shifts the limbs that
    # move in depth (the pose's step and arm: IoU 0.70 from 2.6 m high at 3.5 m)
    from bodyplay.body.mesh import body_mesh
    from bodyplay.render.idmap import silhouettes

    sk = Skeleton.from_shape("m")
    mesh = body_mesh(sk)
    q = _front_pose(sk)
    pelvis = sk.joint_positions(q)[JOINT_INDEX["pelvis"]]
    R, t = look_at((0.4, 1.2, -8.0), (0.0, 1.0, 0.0))
    cam = Camera.from_fov("far", 640, 480, 25.0, R, t)
    verts = mesh.pose(sk, np.stack([q, reflect_pose(sk, q, pelvis, cam.center)]))
    front, back = silhouettes(verts, mesh.faces, cam)
    iou = (front & back).sum() / (front | back).sum()
    assert front.sum() > 5000 and iou > 0.9
    # the front pose merely turned 180 degrees (not mirrored) is another silhouette
    turned = q.copy()
    turned[3:6] = (Rotation.from_euler("y", np.pi) * Rotation.from_rotvec(q[3:6])).as_rotvec()
    other = silhouettes(mesh.pose(sk, turned[None]), mesh.faces, cam)[0]
    assert (front & other).sum() / (front | other).sum() < iou - 0.1
