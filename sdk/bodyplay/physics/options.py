"""Options of the physics bridge, and the body-part colliders it builds from the joints.

A body part is a capsule between two joints (a pymunk segment with a radius: the
limbs and the torso) or a circle (the head, and the hands, which sit a little past
the wrist along the forearm since trackers report wrists, not hands). Sizes are
fractions of the player's height so that one set of options fits every body.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import JOINT_INDEX, JOINT_NAMES
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = [
    "PhysicsOptions",
    "PartSpec",
    "PART_SPECS",
    "PART_NAMES",
    "PLANES",
    "POINT_NAMES",
    "TORSO_TO_HEIGHT",
    "estimate_height",
]

PLANES: Mapping[str, tuple[int, int, int]] = {
    "frontal": (0, 1, 2),
    "sagittal": (2, 1, 0),
}
"""Plane name -> (world axis of the plane's u, of its v, of its depth). ``frontal``:
u = world X, v = world Y (up), depth = world Z, the view of a camera facing the
player; ``sagittal``: u = world Z, v = world Y, depth = world X (seen from the side)."""

TORSO_TO_HEIGHT = 0.2805
"""Pelvis-to-neck distance over body height (reference 1.75 m skeleton: 0.491 m)."""


POINT_NAMES: tuple[str, ...] = (*JOINT_NAMES, "l_hand", "r_hand")
"""The points colliders hang on: the 17 joints, then each hand's centre (``hand_offset``
of body height past the wrist, along the elbow-to-wrist direction in 3-D)."""


@dataclass(frozen=True)
class PartSpec:
    """One collider: ``kind`` ``segment`` (capsule from point ``a`` to point ``b``) or
    ``circle`` (centred on ``a``); points are POINT_NAMES; ``radius`` names the
    PhysicsOptions field holding its radius as a fraction of body height."""

    name: str
    kind: Literal["segment", "circle"]
    a: str
    b: str
    radius: str


PART_SPECS: tuple[PartSpec, ...] = (
    PartSpec("head", "circle", "head", "head", "head_radius"),
    PartSpec("torso", "segment", "pelvis", "neck", "torso_radius"),
    PartSpec("l_upper_arm", "segment", "l_shoulder", "l_elbow", "upper_arm_radius"),
    PartSpec("l_forearm", "segment", "l_elbow", "l_wrist", "forearm_radius"),
    PartSpec("l_hand", "circle", "l_hand", "l_hand", "hand_radius"),
    PartSpec("r_upper_arm", "segment", "r_shoulder", "r_elbow", "upper_arm_radius"),
    PartSpec("r_forearm", "segment", "r_elbow", "r_wrist", "forearm_radius"),
    PartSpec("r_hand", "circle", "r_hand", "r_hand", "hand_radius"),
    PartSpec("l_thigh", "segment", "l_hip", "l_knee", "thigh_radius"),
    PartSpec("l_shin", "segment", "l_knee", "l_ankle", "shin_radius"),
    PartSpec("r_thigh", "segment", "r_hip", "r_knee", "thigh_radius"),
    PartSpec("r_shin", "segment", "r_knee", "r_ankle", "shin_radius"),
)
"""Every body part the bridge can build, in the order contact events are sorted."""

PART_NAMES: tuple[str, ...] = tuple(p.name for p in PART_SPECS)
"""Names of the body parts: the ``part`` of every ContactEvent the bridge emits."""


@dataclass(frozen=True)
class PhysicsOptions:
    """How the physics world is built; validated by :meth:`validate` (PhysicsWorld
    and attach_physics call it).

    ``plane``: the 2-D projection of the body (see PLANES); ``depth``: the plane's
    position along its depth axis in metres (None: follow the player's torso, pose
    by pose); ``dt``: the fixed simulation step (s); ``gravity``: (u, v) m/s^2 in the
    plane; ``parts``: which PART_NAMES get colliders (legs only act while reported);
    ``body_height``: metres (None: estimated once from the first pose's torso);
    ``*_radius`` and ``hand_offset``: fractions of body height; ``elasticity`` and
    ``friction`` of the body parts (pymunk multiplies them with the object's);
    ``iterations``: solver iterations; ``collision_slop``: allowed overlap (m);
    ``max_steps_per_pose``: steps simulated at most per pose (a longer gap, e.g.
    after a pause, is skipped rather than replayed); ``player``: whose pose events
    drive this world.
    """

    plane: str = "frontal"
    depth: float | None = None
    dt: float = 1.0 / 120.0
    gravity: tuple[float, float] = (0.0, -9.81)
    parts: tuple[str, ...] = PART_NAMES
    body_height: float | None = None
    head_radius: float = 0.065
    torso_radius: float = 0.095
    upper_arm_radius: float = 0.025
    forearm_radius: float = 0.022
    hand_radius: float = 0.035
    hand_offset: float = 0.045
    thigh_radius: float = 0.04
    shin_radius: float = 0.03
    elasticity: float = 0.5
    friction: float = 0.6
    iterations: int = 10
    collision_slop: float = 0.002
    max_steps_per_pose: int = 60
    player: int = 0

    def validate(self) -> PhysicsOptions:
        """Return self, or raise ConfigError naming the bad option and what is allowed."""
        if self.plane not in PLANES:
            raise ConfigError(
                f"PhysicsOptions.plane must be one of {', '.join(PLANES)}, got {self.plane!r}"
            )
        _positive("dt", self.dt)
        if self.dt > 0.1:
            raise ConfigError(f"PhysicsOptions.dt must be at most 0.1 s, got {self.dt}")
        if self.depth is not None and not _finite(self.depth):
            raise ConfigError(
                f"PhysicsOptions.depth must be finite metres or None, got {self.depth!r}"
            )
        g = self.gravity
        if not (isinstance(g, tuple | list) and len(g) == 2 and all(_finite(v) for v in g)):
            raise ConfigError(
                f"PhysicsOptions.gravity must be two finite numbers (u, v), got {g!r}"
            )
        if isinstance(self.parts, str) or not self.parts:
            raise ConfigError(
                f"PhysicsOptions.parts must be a non-empty tuple of part names, got {self.parts!r}"
            )
        unknown = [p for p in self.parts if p not in PART_NAMES]
        if unknown:
            raise ConfigError(
                f"unknown body part(s) {', '.join(map(repr, unknown))}; "
                f"known parts are {', '.join(PART_NAMES)}"
            )
        if len(set(self.parts)) != len(self.parts):
            raise ConfigError(f"PhysicsOptions.parts names a part twice: {self.parts!r}")
        if self.body_height is not None:
            _positive("body_height", self.body_height)
            if self.body_height > 3.0:
                raise ConfigError(
                    f"PhysicsOptions.body_height is in metres (at most 3), got {self.body_height}"
                )
        for name in ("head_radius", "torso_radius", "upper_arm_radius", "forearm_radius",
                     "hand_radius", "thigh_radius", "shin_radius"):
            v = getattr(self, name)
            _positive(name, v)
            if v > 0.5:
                raise ConfigError(
                    f"PhysicsOptions.{name} is a fraction of body height (0..0.5), got {v}"
                )
        if not (_finite(self.hand_offset) and 0.0 <= self.hand_offset <= 0.5):
            raise ConfigError(
                f"PhysicsOptions.hand_offset must be a fraction of body height in 0..0.5, "
                f"got {self.hand_offset!r}"
            )
        for name in ("elasticity", "friction", "collision_slop"):
            v = getattr(self, name)
            if not (_finite(v) and v >= 0):
                raise ConfigError(f"PhysicsOptions.{name} must be a number >= 0, got {v!r}")
        for name, lo in (("iterations", 1), ("max_steps_per_pose", 1), ("player", 0)):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool) or v < lo:
                raise ConfigError(f"PhysicsOptions.{name} must be an integer >= {lo}, got {v!r}")
        return self

    def radius(self, spec: PartSpec, height: float) -> float:
        """The radius in metres of a part for a player ``height`` metres tall."""
        return float(getattr(self, spec.radius)) * height

    def __post_init__(self) -> None:
        check_option_types(self)


def _finite(v: object) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def _positive(name: str, v: object) -> None:
    if not (_finite(v) and float(v) > 0):  # type: ignore[arg-type]
        raise ConfigError(f"PhysicsOptions.{name} must be a positive number, got {v!r}")


def estimate_height(joints: NDArray[np.float64]) -> float | None:
    """Body height (m) from the pelvis-to-neck distance of (17, 3) joints, or None."""
    d = joints[JOINT_INDEX["neck"]] - joints[JOINT_INDEX["pelvis"]]
    if not np.all(np.isfinite(d)):
        return None
    torso = float(np.linalg.norm(d))
    if torso < 0.05:
        return None
    return torso / TORSO_TO_HEIGHT
