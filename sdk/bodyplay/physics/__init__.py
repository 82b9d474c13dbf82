"""The pymunk bridge: body colliders driven by the pose, and the contacts they make
(DESIGN.md layout), so games get ``contact`` events without their own physics.

The package is reserved for it and holds no code yet.
"""
