"""Options of the cloth simulation (frozen, validated on construction)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = ["ClothOptions"]


@dataclass(frozen=True)
class ClothOptions:
    """How a :class:`~bodyplay.cloth.Cloth` is simulated; every field is checked on creation.

    Time: a call to ``Cloth.step(dt, joints)`` is split into ``ceil(dt / substep)``
    equal substeps (XPBD with small steps: one constraint pass per substep).

    Material: ``stretch_compliance`` and ``bend_compliance`` are XPBD compliances
    (inverse stiffness, m/N; 0 = rigid); ``density`` is the cloth's mass per area
    (kg/m^2); ``damping`` a velocity decay rate (1/s); ``drag`` the aerodynamic
    coefficient (1/s) of the air (and ``wind``, m/s) pushing along the cloth's normal;
    ``gust`` the relative amplitude and ``gust_hz`` the frequency of the wind's
    deterministic variation.

    ``tethers``: long-range attachments (Kim et al. 2012) keep every particle within
    its rest distance along the cloth (times 1 + ``tether_slack``) of its nearest pin,
    so a long garment does not sag under its own weight at a few solver passes.

    Contact: ``thickness`` is the gap (m) kept between the cloth and the body capsules
    (and the floor); ``friction`` the fraction (0..1) of sliding removed at a contact;
    ``self_collision`` keeps particles at least ``self_distance`` (m) apart (pairs
    closer in the rest shape keep their rest distance); ``max_speed`` (m/s) caps a
    particle's speed, a safety net against explosions.

    Body: ``body_height`` (m) sizes the collision capsules (None: the median of the
    estimates from the first 30 poses' torsos); ``radius_scale`` scales every capsule
    radius; ``separate_limbs`` moves elbows, wrists, knees and ankles that the tracking
    put inside the torso out until their limb only touches it (cloth caught between
    a limb sunk into the torso and the torso could be outside neither; for tracked
    input: it changes the pose, so mocap, whose limbs do not sink, goes without).

    Tracking glitches: the skeleton that drives the cloth follows the tracked joints
    with at most ``max_joint_speed`` (m/s) per joint, so a jump in the tracking is
    crossed in a few steps instead of one, and while it is, the cloth is carried
    rigidly with the body's frame (a glitch gives the cloth no speed); when the pelvis
    jumps by more than ``teleport_distance`` (m) in one step the body and its cloth
    are moved rigidly to the new place (no snap through the cloth). Joints that are
    lost (NaN) keep their last place relative to the torso (legs an upper-body tracker
    never sees hang as in the rest pose); a lost pose (``None``) holds the body still
    while the cloth settles.
    ``dress_seconds``: on the first pose the garment, made for the rest pose, is
    moved to the body and the skeleton blends from the rest pose to the first pose
    over this time (simulated inside the first step).

    ``parallel``: solve each colour of constraints on all cores (numba prange); the
    result is identical to the serial solver, which is faster on busy machines.
    """

    substep: float = 1.0 / 480.0
    gravity: tuple[float, float, float] = (0.0, -9.81, 0.0)
    wind: tuple[float, float, float] = (0.0, 0.0, 0.0)
    gust: float = 0.3
    gust_hz: float = 0.4
    drag: float = 1.0
    damping: float = 0.4
    density: float = 0.25
    stretch_compliance: float = 1e-7
    bend_compliance: float = 2e-3
    thickness: float = 0.012
    friction: float = 0.3
    tethers: bool = True
    tether_slack: float = 0.02
    self_collision: bool = True
    self_distance: float = 0.01
    max_speed: float = 15.0
    body_height: float | None = None
    radius_scale: float = 1.0
    separate_limbs: bool = False
    max_joint_speed: float = 5.0
    teleport_distance: float = 0.5
    dress_seconds: float = 0.6
    parallel: bool = False

    def __post_init__(self) -> None:
        check_option_types(self)
        _in_range("substep", self.substep, 1e-5, 0.05)
        for name in ("gravity", "wind"):
            v = getattr(self, name)
            if not (isinstance(v, tuple | list) and len(v) == 3 and all(_finite(c) for c in v)):
                raise ConfigError(f"ClothOptions.{name} must be three finite numbers (x, y, z), "
                                  f"got {v!r}")
            object.__setattr__(self, name, tuple(float(c) for c in v))
        _in_range("gust", self.gust, 0.0, 1.0)
        _in_range("gust_hz", self.gust_hz, 0.0, 100.0)
        _in_range("drag", self.drag, 0.0, 100.0)
        _in_range("damping", self.damping, 0.0, 100.0)
        _in_range("density", self.density, 1e-4, 100.0, open_low=True)
        _in_range("stretch_compliance", self.stretch_compliance, 0.0, 1.0)
        _in_range("bend_compliance", self.bend_compliance, 0.0, 10.0)
        _in_range("thickness", self.thickness, 0.0, 0.2)
        _in_range("friction", self.friction, 0.0, 1.0)
        _in_range("self_distance", self.self_distance, 1e-4, 0.1)
        _in_range("max_speed", self.max_speed, 0.1, 1000.0)
        if self.body_height is not None:
            _in_range("body_height", self.body_height, 0.5, 3.0)
        _in_range("radius_scale", self.radius_scale, 0.1, 5.0)
        _in_range("max_joint_speed", self.max_joint_speed, 0.1, 1000.0)
        _in_range("teleport_distance", self.teleport_distance, 0.01, 100.0)
        _in_range("dress_seconds", self.dress_seconds, 0.0, 10.0)
        _in_range("tether_slack", self.tether_slack, 0.0, 1.0)
        for name in ("tethers", "self_collision", "separate_limbs", "parallel"):
            if not isinstance(getattr(self, name), bool):
                raise ConfigError(f"ClothOptions.{name} must be True or False, "
                                  f"got {getattr(self, name)!r}")


def _finite(v: object) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def _in_range(name: str, v: object, lo: float, hi: float, open_low: bool = False) -> None:
    ok = _finite(v) and lo <= float(v) <= hi  # type: ignore[arg-type]
    if ok and open_low and float(v) <= lo:  # type: ignore[arg-type]
        ok = False
    if not ok:
        raise ConfigError(f"ClothOptions.{name} must be a number in {lo:g}..{hi:g}, got {v!r}")
