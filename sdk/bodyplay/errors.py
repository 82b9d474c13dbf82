"""Exceptions that bodyplay raises for problems the user can fix.

Every error says what was wrong and what to do about it; the CLI prints them as
one line instead of a traceback.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

__all__ = [
    "reading",
    "BodyplayError",
    "BVHError",
    "CaptureError",
    "CalibrationError",
    "ConfigError",
    "TimestampError",
    "UnknownEventError",
    "PluginError",
    "SessionError",
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


class SessionError(BodyplayError, RuntimeError):
    """A running session cannot go on or be stopped (e.g. a subscriber never returns)."""


class PluginError(BodyplayError, RuntimeError):
    """A plugin could not be loaded or does not provide what its entry point promises."""


@contextlib.contextmanager
def reading(path: str | Path, error: type[BodyplayError], what: str = "file") -> Iterator[None]:
    """Turn anything that goes wrong while reading ``path`` into a BodyplayError naming it.

    A BodyplayError that does not mention the file is raised again with ``path:`` in
    front; any other exception (a malformed value deep in numpy, bad UTF-8, an overflow)
    becomes ``error`` saying the file holds an unreadable ``what``. Readers wrap their
    parsing in it so that bad input never ends in a traceback.
    """
    p = Path(path)
    try:
        yield
    except BodyplayError as exc:
        if p.name in str(exc):
            raise
        raise type(exc)(f"{p}: {exc}") from exc
    except MemoryError:
        raise
    except UnicodeDecodeError as exc:
        where = str(p)
        with contextlib.suppress(OSError):
            if isinstance(exc.object, bytes) and len(exc.object) == p.stat().st_size:
                line = exc.object.count(b"\n", 0, exc.start) + 1  # the whole file was decoded
                where = f"{p}:{line}"
        raise error(f"{where}: not UTF-8 text (byte {exc.object[exc.start:exc.start + 1]!r}); "
                    f"is this really a {what}?") from exc
    except Exception as exc:
        raise error(f"{p}: unreadable {what} ({type(exc).__name__}: {exc}); "
                    "fix or replace the file") from exc
