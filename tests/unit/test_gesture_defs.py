"""Specification of gesture definitions (TOML), features and the recognizer's state machine."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from bodyplay.body import JOINT_INDEX, Skeleton
from bodyplay.errors import ConfigError, TimestampError
from bodyplay.gestures import (
    FEATURES,
    GestureOptions,
    GestureRecognizer,
    builtin_gesture_names,
    gesture_options,
    load_gestures,
    parse_condition,
    parse_gesture,
)

REQUIRED = {"crouch", "step_left", "step_right", "jump", "raise_arms", "hit", "double_hit",
            "transfigure"}
RW = JOINT_INDEX["r_wrist"]

TWO_STAGE = """
[gesture]
name = "up_down"
cooldown = 0.5
[[stage]]
name = "up"
when = ["above(r_wrist, head) > 0.0"]
hold = 0.1
[[stage]]
name = "down"
when = ["above(r_wrist, r_shoulder) < -0.4"]
within = 0.5
"""


def _standing(skeleton: Skeleton) -> np.ndarray:
    arms_down = {"l_shoulder": (0, 0, -1.35), "r_shoulder": (0, 0, 1.35)}
    return skeleton.joint_positions(skeleton.pose(rotations=arms_down))


def _arm_up(skeleton: Skeleton) -> np.ndarray:
    rot = {"l_shoulder": (0, 0, -1.35), "r_shoulder": (0, 0, -1.45)}
    return skeleton.joint_positions(skeleton.pose(rotations=rot))


def _feed(rec: GestureRecognizer, frames: list[np.ndarray], t0: float = 0.0, fps: float = 30.0):
    events = []
    for k, j in enumerate(frames):
        events += rec.update(t0 + k / fps, j)
    return events


# ---- definitions ---------------------------------------------------------------------
def test_builtin_set_holds_every_required_gesture_and_parses():
    assert set(builtin_gesture_names()) >= REQUIRED
    defs = load_gestures("builtin")
    assert {d.name for d in defs} == set(builtin_gesture_names())
    for d in defs:
        assert d.stages and all(s.when for s in d.stages)
        assert d.description


def test_load_gestures_accepts_a_file_a_folder_a_builtin_name_and_a_list(tmp_path: Path):
    f = tmp_path / "up_down.toml"
    f.write_text(TWO_STAGE)
    assert [d.name for d in load_gestures(f)] == ["up_down"]
    assert [d.name for d in load_gestures(tmp_path)] == ["up_down"]
    assert [d.name for d in load_gestures("crouch")] == ["crouch"]
    assert [d.name for d in load_gestures([f, "jump"])] == ["up_down", "jump"]


def test_gesture_name_defaults_to_the_file_name(tmp_path: Path):
    f = tmp_path / "wave_twice.toml"
    f.write_text('[[stage]]\nwhen = ["pelvis_drop > 0.2"]\n')
    assert load_gestures(f)[0].name == "wave_twice"


def test_duplicate_gesture_names_are_rejected():
    with pytest.raises(ConfigError, match="defined twice"):
        load_gestures(["crouch", "crouch"])


def test_condition_parses_feature_joints_operator_and_threshold():
    c = parse_condition("above(r_wrist, head) >= -0.25")
    assert (c.feature, c.args, c.op, c.threshold) == ("above", ("r_wrist", "head"), ">=", -0.25)
    assert parse_condition("pelvis_drop > 0.2").args == ()
    assert c.test(0.0) and not c.test(-1.0) and not c.test(float("nan"))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('[[stage]]\nwhen = ["wrist_height(r_wrist) > 1"]\n',
         "stage\\[0\\].when\\[0\\]: unknown feature 'wrist_height'"),
        ('[[stage]]\nwhen = ["above(r_hand, head) > 1"]\n', "unknown joint 'r_hand'"),
        ('[[stage]]\nwhen = ["above(r_wrist) > 1"]\n', "takes 2 joint argument"),
        ('[[stage]]\nwhen = ["above(r_wrist, head) = 1"]\n', "cannot read condition"),
        ('[[stage]]\nwhen = ["pelvis_drop > 0.2"]\nhodl = 0.1\n',
         "stage\\[0\\]: unknown key\\(s\\) hodl"),
        ('[gesture]\ncooldown = -1\n[[stage]]\nwhen = ["pelvis_drop > 0.2"]\n', "gesture.cooldown"),
        ('[gesture]\nname = "x"\n', "needs at least one \\[\\[stage\\]\\]"),
        ('[[stage]]\nwhen = []\n', "stage\\[0\\].when: must be a non-empty list"),
        ('[[stage]\nwhen = 3\n', "malformed TOML"),
        ('[[stage]]\nwhen = ["pelvis_drop > 0.2"]\nwhen_no_legs = []\n',
         "stage\\[0\\].when_no_legs: must be a non-empty list"),
        ('[[stage]]\nwhen = ["pelvis_drop > 0.2"]\nwhen_no_legs = ["speed(hand) < 1"]\n',
         "when_no_legs\\[0\\]: unknown joint 'hand'"),
    ],
)
def test_bad_definitions_raise_config_error_naming_file_and_key(text: str, message: str):
    with pytest.raises(ConfigError, match=message) as err:
        parse_gesture(text, "my_gesture.toml", "g")
    assert "my_gesture.toml" in str(err.value)


def test_unknown_builtin_name_is_a_config_error():
    with pytest.raises(ConfigError, match="neither a .toml file nor a built-in"):
        load_gestures("moonwalk")


def test_every_feature_has_a_unit_and_a_description():
    for name, spec in FEATURES.items():
        assert spec.unit and spec.doc, name


# ---- features ------------------------------------------------------------------------
def test_features_are_relative_to_body_size(skeleton: Skeleton):
    values = []
    for shape in ("s", "xl"):
        sk = Skeleton.from_shape(shape)
        rec = GestureRecognizer([])
        frame = rec.features(0.0, _arm_up(sk))
        values.append([frame.value("above", ("r_wrist", "head")),
                       frame.value("distance", ("l_wrist", "r_wrist")),
                       frame.value("elevation", ("r_shoulder", "r_wrist"))])
    np.testing.assert_allclose(values[0], values[1], rtol=0.05, atol=0.05)


def test_pelvis_drop_is_measured_against_the_learned_standing_height(skeleton: Skeleton):
    rec = GestureRecognizer([])
    stand = _standing(skeleton)
    for k in range(30):
        rec.features(k / 30, stand)
    low = stand.copy()
    low[:, 1] -= 0.3 * skeleton.pelvis_height
    low[[JOINT_INDEX["l_ankle"], JOINT_INDEX["r_ankle"]], 1] = stand[JOINT_INDEX["l_ankle"], 1]
    f = rec.features(1.0, low)
    assert f.value("pelvis_drop", ()) == pytest.approx(0.3 * skeleton.pelvis_height / (
        skeleton.pelvis_height - stand[JOINT_INDEX["l_ankle"], 1]), rel=0.02)


def test_lost_joints_make_their_features_nan_and_conditions_false(skeleton: Skeleton):
    rec = GestureRecognizer([])
    j = _arm_up(skeleton)
    state = ["tracked"] * 17
    state[RW] = "lost"
    f = rec.features(0.0, j, tuple(state))
    assert np.isnan(f.value("above", ("r_wrist", "head")))


# ---- the state machine ---------------------------------------------------------------
def test_two_stage_gesture_emits_started_then_performed(skeleton: Skeleton):
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)])
    frames = [_standing(skeleton)] * 5 + [_arm_up(skeleton)] * 6 + [_standing(skeleton)] * 5
    ev = _feed(rec, frames)
    assert [e.phase for e in ev] == ["started", "performed"]
    assert ev[0].t == pytest.approx(5 / 30) and ev[0].progress == 0.0
    assert ev[1].progress == 1.0 and ev[1].started_t == pytest.approx(5 / 30)
    assert ev[1].t == pytest.approx(11 / 30) and ev[1].emitted_t == ev[1].t


def test_gesture_is_canceled_when_the_hold_breaks(skeleton: Skeleton):
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)])
    ev = _feed(rec, [_standing(skeleton)] * 3 + [_arm_up(skeleton)] * 2 + [_standing(skeleton)] * 3)
    assert [e.phase for e in ev] == ["started", "canceled"]
    assert 0.0 < ev[1].progress < 0.5


def test_gesture_is_canceled_when_the_next_stage_comes_too_late(skeleton: Skeleton):
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)])
    frames = [_standing(skeleton)] * 3 + [_arm_up(skeleton)] * 40 + [_standing(skeleton)] * 3
    ev = _feed(rec, frames)
    assert [e.phase for e in ev] == ["started", "canceled"]
    assert ev[1].t - ev[0].t == pytest.approx(0.1 + 0.5, abs=0.05)


def test_gesture_needs_stage_one_to_end_before_it_starts_again(skeleton: Skeleton):
    text = '[gesture]\ncooldown = 0\n[[stage]]\nwhen = ["above(r_wrist, head) > 0"]\n'
    rec = GestureRecognizer([parse_gesture(text, default_name="up")])
    ev = _feed(rec, [_arm_up(skeleton)] * 30)
    assert [e.phase for e in ev] == ["started", "performed"]
    ev = _feed(rec, [_standing(skeleton)] + [_arm_up(skeleton)] * 2, t0=2.0)
    assert [e.phase for e in ev] == ["started", "performed"]


def test_a_one_frame_break_of_a_held_pose_restarts_the_gesture_at_once(skeleton: Skeleton):
    text = '[gesture]\ncooldown = 0\n[[stage]]\nwhen = ["above(r_wrist, head) > 0"]\nhold = 0.2\n'
    rec = GestureRecognizer([parse_gesture(text, default_name="up")])
    up, down = _arm_up(skeleton), _standing(skeleton)
    ev = _feed(rec, [down, up, up, down] + [up] * 10)  # a glitch in the middle of the hold
    assert [e.phase for e in ev] == ["started", "canceled", "started", "performed"]
    assert ev[2].t == pytest.approx(4 / 30)  # the first frame the pose holds again


def test_a_gesture_canceled_while_stage_one_still_holds_waits_for_it_to_end(skeleton: Skeleton):
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)])
    up = _arm_up(skeleton)
    ev = _feed(rec, [_standing(skeleton)] + [up] * 60)  # "down" never comes: timed out
    assert [e.phase for e in ev] == ["started", "canceled"]


def test_cooldown_blocks_a_restart_right_after_performed(skeleton: Skeleton):
    text = '[gesture]\ncooldown = 1.0\n[[stage]]\nwhen = ["above(r_wrist, head) > 0"]\n'
    rec = GestureRecognizer([parse_gesture(text, default_name="up")])
    up, down = _arm_up(skeleton), _standing(skeleton)
    ev = _feed(rec, [up, down, up, down, up])  # within 0.2 s
    assert [e.phase for e in ev] == ["started", "performed"]


def test_events_use_the_given_clock_and_player(skeleton: Skeleton):
    opts = gesture_options(player=2, clock=lambda: 123.0)
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)], opts)
    ev = _feed(rec, [_standing(skeleton)] + [_arm_up(skeleton)] * 5)
    assert ev and all(e.emitted_t == 123.0 and e.player == 2 for e in ev)
    assert ev[0].to_json()["type"] == "gesture"


def test_only_performed_events_when_started_and_canceled_are_off(skeleton: Skeleton):
    opts = GestureOptions(emit_started=False, emit_canceled=False)
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)], opts)
    frames = [_standing(skeleton)] * 3 + [_arm_up(skeleton)] * 2 + [_standing(skeleton)] * 3
    frames += [_arm_up(skeleton)] * 6 + [_standing(skeleton)] * 3
    assert [e.phase for e in _feed(rec, frames)] == ["performed"]


def test_active_reports_progress_of_gestures_under_way(skeleton: Skeleton):
    rec = GestureRecognizer([parse_gesture(TWO_STAGE)])
    _feed(rec, [_standing(skeleton)] + [_arm_up(skeleton)] * 2)
    assert 0.0 < rec.active["up_down"] < 0.5


def test_recognizer_rejects_time_that_does_not_advance(skeleton: Skeleton):
    rec = GestureRecognizer("builtin")
    rec.update(1.0, _standing(skeleton))
    with pytest.raises(TimestampError):
        rec.update(1.0, _standing(skeleton))


def test_gesture_options_factory_rejects_bad_values():
    with pytest.raises(ConfigError):
        gesture_options(player=-1)
    with pytest.raises(ConfigError):
        gesture_options(colour="red")


def test_standing_still_triggers_no_builtin_gesture(skeleton: Skeleton):
    rec = GestureRecognizer("builtin")
    rng = np.random.default_rng(0)
    frames = [_standing(skeleton) + rng.normal(0, 0.005, (17, 3)) for _ in range(150)]
    assert _feed(rec, frames) == []


def test_when_no_legs_replaces_when_only_in_frames_without_legs(skeleton: Skeleton):
    g = parse_gesture('[[stage]]\nwhen = ["height(l_ankle) > 5"]\n'
                      'when_no_legs = ["height(head) > 2"]\n', "g.toml", "g")
    rec = GestureRecognizer([g])
    j = skeleton.joint_positions(skeleton.rest_pose())
    assert not [e for e in rec.update(0.0, j) if e.phase == "performed"]
    legless = j.copy()
    legless[11:] = np.nan
    assert [e.gesture for e in rec.update(0.1, legless) if e.phase == "performed"] == ["g"]
