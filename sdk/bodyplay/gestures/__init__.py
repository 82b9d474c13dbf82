"""Gestures as data: TOML definitions over body-relative features, and their recognizer.

``GestureRecognizer(load_gestures("builtin"))`` recognizes the shipped set (crouch,
jump, raise_arms, step_left, step_right, hit, double_hit, transfigure);
``recognizer.update(t, joints, state)`` returns :class:`GestureEvent` objects.
See docs/gestures.md for the file format and the features.
"""

from bodyplay.gestures.definitions import (
    Condition,
    GestureDefinition,
    Stage,
    builtin_gesture_names,
    load_gestures,
    parse_condition,
    parse_gesture,
)
from bodyplay.gestures.features import FEATURES, BodyCalibration, CalibrationOptions, FeatureSpec
from bodyplay.gestures.recognizer import GestureOptions, GestureRecognizer, gesture_options

__all__ = [
    "FEATURES",
    "BodyCalibration",
    "CalibrationOptions",
    "Condition",
    "FeatureSpec",
    "GestureDefinition",
    "GestureOptions",
    "GestureRecognizer",
    "Stage",
    "builtin_gesture_names",
    "gesture_options",
    "load_gestures",
    "parse_condition",
    "parse_gesture",
]
