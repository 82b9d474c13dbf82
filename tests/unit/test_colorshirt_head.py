"""Specifications of the head cue: the head found above the collar, and its anchors."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera, look_at
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt import ColorShirtOptions
from bodyplay.trackers.colorshirt.head import (
    HEAD_PATCH,
    HeadPoint,
    find_head,
    head_anchors,
    head_from_cue,
)
from bodyplay.trackers.colorshirt.ik import PatchAnchors
from bodyplay.trackers.colorshirt.locate import BackgroundMask
from bodyplay.trackers.colorshirt.views import CameraState

HEAD = np.array([320.0, 100.0])  # full-resolution centre of the head
NECK = np.array([320.0, 136.0])
RADIUS = 18.0  # full-resolution pixels


def _person(head: np.ndarray = HEAD, with_head: bool = True, hand: np.ndarray | None = None
            ) -> np.ndarray:
    """Plate-resolution (half) foreground: head disk, throat and a shirt below it."""
    fg = np.zeros((240, 320), bool)
    yy, xx = np.mgrid[0:240, 0:320]
    cx, cy, r = head[0] / 2, head[1] / 2, RADIUS / 2
    if with_head:
        fg |= (xx + 0.5 - cx) ** 2 + (yy + 0.5 - cy) ** 2 <= r * r
    fg[int(cy + r - 2): 70, 156:164] = True  # throat
    fg[66:160, 130:190] = True  # shirt and shoulders
    if hand is not None:
        hx, hy = hand / 2
        fg |= (xx + 0.5 - hx) ** 2 + (yy + 0.5 - hy) ** 2 <= 16
    return fg


def test_find_head_returns_the_centre_of_the_head_disk() -> None:
    hp = find_head(_person(), 2, HEAD, NECK, RADIUS)
    assert hp is not None
    assert np.hypot(hp.u - HEAD[0], hp.v - HEAD[1]) < 2.0
    assert hp.fill > 0.9 and hp.radius == RADIUS


def test_find_head_is_not_pulled_down_by_the_shirt_below_the_collar() -> None:
    # the prediction sits on the collar: the shirt fills a disk there, but it is
    # below the cut, so the head above is found
    hp = find_head(_person(), 2, HEAD + (0.0, 14.0), NECK + (0.0, 14.0), RADIUS)
    assert hp is not None
    assert np.hypot(hp.u - HEAD[0], hp.v - HEAD[1]) < 3.0


def test_find_head_corrects_a_prediction_off_by_more_than_a_radius() -> None:
    hp = find_head(_person(), 2, HEAD + (25.0, 0.0), NECK + (25.0, 0.0), RADIUS)
    assert hp is not None
    assert np.hypot(hp.u - HEAD[0], hp.v - HEAD[1]) < 3.0


def test_find_head_is_barely_moved_by_a_hand_beside_the_face() -> None:
    hp = find_head(_person(hand=HEAD + (22.0, 6.0)), 2, HEAD, NECK, RADIUS)
    assert hp is not None
    assert np.hypot(hp.u - HEAD[0], hp.v - HEAD[1]) < 4.0


def test_find_head_reports_nothing_without_a_head_in_view() -> None:
    assert find_head(_person(with_head=False), 2, HEAD, NECK, RADIUS) is None
    assert find_head(np.zeros((240, 320), bool), 2, HEAD, NECK, RADIUS) is None


def test_find_head_rejects_unusable_predictions() -> None:
    fg = _person()
    assert find_head(fg, 2, np.array([np.nan, 100.0]), NECK, RADIUS) is None
    assert find_head(fg, 2, HEAD, HEAD, RADIUS) is None  # no neck-to-head direction
    assert find_head(fg, 2, HEAD, NECK, 2.0) is None  # a head of one plate pixel


def test_head_anchors_join_the_shirt_anchors_after_them() -> None:
    def anchors(n: int, patch: int) -> PatchAnchors:
        return PatchAnchors(np.zeros(n, np.int64), np.zeros((n, 3)), np.zeros(n, np.int64),
                            np.zeros((n, 2)), np.ones(n), np.full(n, patch, np.int64))

    joined = anchors(3, 5).join(anchors(2, HEAD_PATCH))
    assert len(joined) == 5 and list(joined.patch) == [5, 5, 5, HEAD_PATCH, HEAD_PATCH]
    assert anchors(3, 5).join(anchors(0, HEAD_PATCH)).patch.tolist() == [5, 5, 5]
    assert HEAD_PATCH == 21  # after the shirt's twenty patches


@pytest.mark.parametrize("field,value", [("head_std", 0.0), ("head_std", np.nan),
                                         ("head_offset", 0.5)])
def test_options_reject_impossible_head_cue_settings(field: str, value: float) -> None:
    with pytest.raises(ConfigError, match=field):
        ColorShirtOptions(**{field: value})  # type: ignore[arg-type]


def _rig_and_pose() -> tuple[Skeleton, np.ndarray, list[Camera]]:
    sk = Skeleton.from_shape("m")
    q = sk.rest_pose()
    q[:3] = (0.0, 1.0, 0.0)
    cams = []
    for x in (-0.5, 0.5):
        R, t = look_at((x, 1.3, 2.6), (0.0, 1.3, 0.0))
        cams.append(Camera.from_fov(f"cam{len(cams)}", 640, 480, 60.0, R, t))
    return sk, q, cams


def _seen_at(cam: Camera, point: np.ndarray) -> HeadPoint:
    u, v = cam.project(point, distort=False)
    return HeadPoint(float(u), float(v), 15.0, 1.0)


def test_head_from_cue_triangulates_the_heads_found_by_two_cameras() -> None:
    sk, q, cams = _rig_and_pose()
    opts = ColorShirtOptions()
    head = sk.joint_positions(q)[JOINT_INDEX["head"]]
    true_head = head + np.array([0.01, 0.035, -0.02])  # a longer neck than the preset's
    visible = true_head + np.array([0.0, opts.head_offset, 0.0])
    found = [(i, _seen_at(c, visible)) for i, c in enumerate(cams)]
    out = head_from_cue(sk, q, cams, found, opts)
    assert out is not None
    # across the rays it lands on the found head; along them (depth, which a 1 m
    # baseline tells poorly) the pull towards the fitted head keeps part of the gap
    assert np.abs(out - true_head)[:2].max() < 0.005
    assert np.linalg.norm(out - true_head) < 0.5 * np.linalg.norm(head - true_head)


def test_head_from_cue_with_one_camera_moves_the_head_across_the_ray_only() -> None:
    sk, q, cams = _rig_and_pose()
    opts = ColorShirtOptions()
    head = sk.joint_positions(q)[JOINT_INDEX["head"]]
    visible = head + np.array([0.0, opts.head_offset + 0.03, 0.0])
    out = head_from_cue(sk, q, cams[:1], [(0, _seen_at(cams[0], visible))], opts)
    assert out is not None
    before = cams[0].project(head + np.array([0.0, opts.head_offset, 0.0]), distort=False)
    seen = cams[0].project(out + np.array([0.0, opts.head_offset, 0.0]), distort=False)
    target = cams[0].project(visible, distort=False)
    # most of the way onto the ray (the pull towards the fitted head keeps a tenth)
    assert np.linalg.norm(seen - target) < 0.15 * np.linalg.norm(before - target)
    depth = cams[0].world_to_camera(np.stack([out, head]))[:, 2]
    assert abs(depth[0] - depth[1]) < 0.01  # the depth is the pose's


def test_head_from_cue_ignores_a_head_far_from_the_fitted_one() -> None:
    sk, q, cams = _rig_and_pose()
    opts = ColorShirtOptions()
    head = sk.joint_positions(q)[JOINT_INDEX["head"]]
    far = head + np.array([0.3, 0.0, 0.0])
    assert head_from_cue(sk, q, cams, [(i, _seen_at(c, far)) for i, c in enumerate(cams)],
                         opts) is None
    assert head_from_cue(sk, q, cams, [], opts) is None


def _in_view_state(cam: Camera, visible: np.ndarray, neck: np.ndarray,
                   other_camera: bool) -> CameraState:
    """A camera that saw no empty room: its room plate knows nothing yet, and (when
    ``other_camera``) another camera's view tells the room everywhere but the
    player (a head disk at ``visible`` and the body below ``neck``)."""
    st = CameraState(background=BackgroundMask())
    frame = np.full((240, 320, 3), 120, np.uint8)
    st.floor.start(frame, reduced=True)
    u, v = cam.project(visible, distort=False) / 2
    nu, nv = cam.project(neck, distort=False) / 2
    yy, xx = np.mgrid[0:240, 0:320]
    player = (xx + 0.5 - u) ** 2 + (yy + 0.5 - v) ** 2 <= 8.0**2
    player[int(v): int(nv) + 2, int(nu) - 3: int(nu) + 4] = True  # the throat
    player[int(nv): int(nv) + 60, int(nu) - 25: int(nu) + 26] = True  # the shirt
    st.room.start(frame, ~player if other_camera else None)
    st.floor.shirt_at((int(2 * nu) - 50, int(2 * nv), int(2 * nu) + 50, int(2 * nv) + 120))
    return st


def test_head_anchors_with_the_player_in_view_find_the_head_for_the_report_only() -> None:
    sk, q, cams = _rig_and_pose()
    opts = ColorShirtOptions()
    J = sk.joint_positions(q)
    head, neck = J[JOINT_INDEX["head"]], J[JOINT_INDEX["neck"]]
    visible = head + np.array([0.0, opts.head_offset + 0.04, 0.0])  # a longer neck
    st = _in_view_state(cams[0], visible, neck, other_camera=True)
    view = SimpleNamespace(index=0)
    anchors, found = head_anchors(sk, q, cams[:1], [st], [view], opts)  # type: ignore[list-item]
    assert len(anchors) == 0  # the fit and the body chosen stay the shirt's
    assert [i for i, _ in found] == [0]
    seen = np.array([found[0][1].u, found[0][1].v])
    assert np.linalg.norm(seen - cams[0].project(visible, distort=False)) < 3.0
    out = head_from_cue(sk, q, cams[:1], found, opts)
    assert out is not None and out[1] - head[1] > 0.02  # the reported head is raised


def test_head_anchors_with_the_player_in_view_need_another_cameras_view() -> None:
    sk, q, cams = _rig_and_pose()
    opts = ColorShirtOptions()
    J = sk.joint_positions(q)
    visible = J[JOINT_INDEX["head"]] + np.array([0.0, opts.head_offset + 0.04, 0.0])
    st = _in_view_state(cams[0], visible, J[JOINT_INDEX["neck"]], other_camera=False)
    anchors, found = head_anchors(sk, q, cams[:1], [st], [SimpleNamespace(index=0)],  # type: ignore[list-item]
                                  opts)
    assert len(anchors) == 0 and found == []  # the unknown room beside the head is no outline
