"""The pymunk bridge: body colliders driven by the pose, and the ``contact`` events
they make (see docs/physics.md), so games get collisions without their own body model.

``attach_physics(session, PhysicsOptions(...))`` returns a :class:`PhysicsWorld`
whose pymunk space holds the player's body parts (PART_NAMES) as kinematic
colliders in a 2-D plane through the player; add balls with ``world.add_ball`` and
subscribe to ``contact`` on the session.
"""

from bodyplay.physics.options import (
    PART_NAMES,
    PART_SPECS,
    PLANES,
    POINT_NAMES,
    PartSpec,
    PhysicsOptions,
    estimate_height,
)
from bodyplay.physics.world import (
    PART_COLLISION_TYPE,
    PhysicsObject,
    PhysicsWorld,
    attach_physics,
)

__all__ = [
    "PART_COLLISION_TYPE",
    "PART_NAMES",
    "PART_SPECS",
    "PLANES",
    "POINT_NAMES",
    "PartSpec",
    "PhysicsObject",
    "PhysicsOptions",
    "PhysicsWorld",
    "attach_physics",
    "estimate_height",
]
