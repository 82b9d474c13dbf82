"""bodyplay: a person in front of one or two webcams as game input.

The public API is re-exported here; everything else is private to its module.
"""

from bodyplay.body import (
    BODY_SHAPES,
    JOINT_NAMES,
    UPPER_BODY,
    BodyShape,
    Skeleton,
    body_shape,
)
from bodyplay.errors import BodyplayError, ConfigError

__version__ = "0.1.0"

__all__ = [
    "BODY_SHAPES",
    "BodyShape",
    "BodyplayError",
    "ConfigError",
    "JOINT_NAMES",
    "Skeleton",
    "UPPER_BODY",
    "body_shape",
]
