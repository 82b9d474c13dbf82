"""Body-size presets: the family of body models a tracker chooses among.

The silhouette paper selects one of 30 body models by height, chest and weight; the
synthetic camera dresses its actor in these sizes. Lengths scale with height,
breadths (shoulders, hips) and limb girth with build.
"""

from __future__ import annotations

from dataclasses import dataclass

from bodyplay.errors import ConfigError

__all__ = ["BodyShape", "BODY_SHAPES", "body_shape", "closest_body_shape"]


@dataclass(frozen=True)
class BodyShape:
    """Measurements of one body model.

    ``height`` is standing height in metres, ``chest`` the chest circumference in
    metres and ``weight`` in kilograms. ``breadth`` scales shoulder and hip width and
    ``girth`` scales limb and torso thickness relative to the reference body.
    """

    name: str
    height: float
    chest: float
    weight: float
    breadth: float = 1.0
    girth: float = 1.0

    def __post_init__(self) -> None:
        if not 1.0 <= self.height <= 2.4:
            raise ConfigError(f"body height {self.height} m is outside 1.0..2.4 m")
        if self.breadth <= 0 or self.girth <= 0:
            raise ConfigError("body breadth and girth must be positive")

    @property
    def length_scale(self) -> float:
        """Scale of bone lengths relative to the 1.75 m reference body."""
        return self.height / 1.75


BODY_SHAPES: dict[str, BodyShape] = {
    s.name: s
    for s in (
        BodyShape("xs", 1.55, 0.82, 48.0, breadth=0.90, girth=0.88),
        BodyShape("s", 1.63, 0.88, 58.0, breadth=0.95, girth=0.94),
        BodyShape("m_slim", 1.70, 0.90, 62.0, breadth=0.97, girth=0.92),
        BodyShape("m", 1.75, 0.98, 72.0, breadth=1.00, girth=1.00),
        BodyShape("m_heavy", 1.75, 1.10, 90.0, breadth=1.06, girth=1.18),
        BodyShape("l", 1.82, 1.02, 80.0, breadth=1.03, girth=1.04),
        BodyShape("xl", 1.88, 1.08, 90.0, breadth=1.06, girth=1.10),
        BodyShape("xxl", 1.95, 1.14, 100.0, breadth=1.09, girth=1.16),
    )
}
"""The shipped presets, from 1.55 m to 1.95 m; ``m`` is the reference body."""


def body_shape(name: str | BodyShape) -> BodyShape:
    """Look up a preset by name (or pass a :class:`BodyShape` through)."""
    if isinstance(name, BodyShape):
        return name
    try:
        return BODY_SHAPES[name]
    except KeyError:
        raise ConfigError(
            f"unknown body preset {name!r}; choose one of {', '.join(BODY_SHAPES)}"
        ) from None


def closest_body_shape(height: float, chest: float | None = None) -> BodyShape:
    """The preset nearest to a measured height (and chest circumference, if known)."""

    def cost(s: BodyShape) -> float:
        c = ((s.height - height) / 0.05) ** 2
        if chest is not None:
            c += ((s.chest - chest) / 0.06) ** 2
        return c

    return min(BODY_SHAPES.values(), key=cost)
