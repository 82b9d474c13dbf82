"""Specifications of the type check every options dataclass runs when it is made
(``bodyplay.optiontypes.check_option_types``)."""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass
from typing import Literal

import pytest

from bodyplay.cloth import ClothOptions
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types
from bodyplay.physics import PhysicsOptions
from bodyplay.runtime.session import SessionOptions
from bodyplay.trackers.colorshirt import ColorShirtOptions
from bodyplay.trackers.silhouette import SilhouetteOptions


@dataclass(frozen=True)
class _PluginOptions:
    gain: float = 1.0
    steps: int = 3
    mode: Literal["fast", "exact"] = "fast"
    window: tuple[float, float] = (0.5, 1.5)
    weights: tuple[float, ...] = (1.0,)
    label: str | None = None
    enabled: bool = True

    def __post_init__(self) -> None:
        check_option_types(self)


def test_defaults_of_every_options_class_pass() -> None:
    for cls in (SessionOptions, ColorShirtOptions, SilhouetteOptions, PhysicsOptions,
                ClothOptions, _PluginOptions):
        cls()


@pytest.mark.parametrize(("field", "value", "says"), [
    ("gain", "1.0", "_PluginOptions.gain takes a number, got '1.0' (str)"),
    ("gain", float("nan"), "takes a number, got nan"),
    ("gain", None, "takes a number, got None"),
    ("gain", True, "takes a number, got True (bool)"),
    ("steps", 2.5, "takes a whole number, got 2.5"),
    ("mode", "slow", "takes one of 'fast', 'exact', got 'slow'"),
    ("window", (1.0,), "takes a tuple of 2 values"),
    ("window", (1.0, "x"), "takes a tuple of 2 values"),
    ("weights", 1.0, "takes a tuple, each item a number, got 1.0"),
    ("label", 3, "takes a string or None"),
    ("enabled", "yes", "takes True or False"),
])
def test_a_value_that_does_not_fit_its_hint_is_named_with_what_the_option_takes(
        field: str, value: object, says: str) -> None:
    with pytest.raises(ConfigError, match=re.escape(says)):
        _PluginOptions(**{field: value})  # type: ignore[arg-type]


def test_infinity_is_a_number_and_a_list_becomes_the_hinted_tuple() -> None:
    options = _PluginOptions(gain=float("inf"), weights=[1.0, 2])  # type: ignore[arg-type]
    assert options.weights == (1.0, 2)
    assert hash(options) == hash(dataclasses.replace(options))


def test_the_trackers_options_reject_nan_and_strings_before_their_range_checks() -> None:
    with pytest.raises(ConfigError, match="SilhouetteOptions.lost_after takes a number, got nan"):
        SilhouetteOptions(lost_after=float("nan"))
    with pytest.raises(ConfigError, match="ColorShirtOptions.threshold takes a number"):
        ColorShirtOptions(threshold="3")  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="SilhouetteOptions.hierarchy takes a HierarchyOptions"):
        SilhouetteOptions(hierarchy="default")  # type: ignore[arg-type]


def _options_classes() -> list[type]:
    from apps.goalkeeper.game.rules import GoalkeeperOptions
    from apps.ninja.game.rules import NinjaOptions

    from bodyplay.app.options import GameOptions
    from bodyplay.filters.kalman import KalmanOptions
    from bodyplay.filters.one_euro import OneEuroOptions
    from bodyplay.gestures.features import CalibrationOptions
    from bodyplay.gestures.recognizer import GestureOptions
    from bodyplay.motion.retarget import RetargetOptions
    from bodyplay.record.recorder import RecorderOptions
    from bodyplay.render.idmap import IdMapRendererOptions
    from bodyplay.render.shaded import ShadedRendererOptions
    from bodyplay.synth.options import SyntheticCameraOptions
    from bodyplay.synth.rig import RigOptions
    from bodyplay.trackers.colorshirt.database import DatabaseOptions
    from bodyplay.trackers.colorshirt.locate import LocateOptions
    from bodyplay.trackers.silhouette.options import BackgroundOptions, HierarchyOptions
    from bodyplay.virtual.reach import ReachOptions

    return [SessionOptions, ColorShirtOptions, SilhouetteOptions, PhysicsOptions, ClothOptions,
            GoalkeeperOptions, NinjaOptions, GameOptions, KalmanOptions, OneEuroOptions,
            CalibrationOptions, GestureOptions, RetargetOptions, RecorderOptions,
            IdMapRendererOptions, ShadedRendererOptions, SyntheticCameraOptions, RigOptions,
            DatabaseOptions, LocateOptions, BackgroundOptions, HierarchyOptions, ReachOptions]


_JUNK = ["x", None, float("nan"), float("inf"), -1, -1.5, 0, 10**9, (), (1.0, "x"), [3], {}]


def test_no_options_class_answers_a_junk_value_with_anything_but_a_config_error() -> None:
    surprises = []
    for cls in _options_classes():
        for field in dataclasses.fields(cls):
            for junk in _JUNK:
                try:
                    options = cls(**{field.name: junk})
                    getattr(options, "validate", lambda: None)()
                except ConfigError:
                    pass
                except Exception as error:  # noqa: BLE001 - collected and reported below
                    surprises.append(f"{cls.__name__}.{field.name}={junk!r}: "
                                     f"{type(error).__name__}: {error}")
    assert not surprises, "\n".join(surprises)
