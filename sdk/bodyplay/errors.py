"""Exceptions that bodyplay raises for problems the user can fix.

Every error says what was wrong and what to do about it; the CLI prints them as
one line instead of a traceback.
"""

from __future__ import annotations

__all__ = [
    "BodyplayError",
    "BVHError",
    "CaptureError",
    "CalibrationError",
    "ConfigError",
    "TimestampError",
    "UnknownEventError",
    "PluginError",
]


class BodyplayError(Exception):
    """Base class of every error bodyplay raises on purpose."""


class ConfigError(BodyplayError, ValueError):
    """An option or argument has an invalid value."""


class BVHError(BodyplayError, ValueError):
    """A BVH file is malformed; the message names the file, the line and the problem."""


class CaptureError(BodyplayError, OSError):
    """A frame source is missing, unreadable or inconsistent (e.g. sizes do not match)."""


class CalibrationError(BodyplayError, ValueError):
    """Camera calibration could not be read or computed."""


class TimestampError(BodyplayError, ValueError):
    """A frame or event arrived with a timestamp not after the previous one."""


class UnknownEventError(BodyplayError, KeyError):
    """Subscribing to or emitting an event name that is not registered."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class PluginError(BodyplayError, RuntimeError):
    """A plugin could not be loaded or does not provide what its entry point promises."""
