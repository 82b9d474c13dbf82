"""Pose trackers: estimate the 17 joints from camera frames, one
:class:`~bodyplay.trackers.base.TrackResult` per frame set.

:mod:`bodyplay.trackers.base` holds what every tracker shares (the ``Tracker``
protocol, its capabilities and result type), so that sessions, evaluation and games
work with any of them; each published method lives in its own subpackage
(``colorshirt``, ``silhouette``; DESIGN.md gives a screen on each).
"""

from collections.abc import Sequence
from typing import Any

from bodyplay.capture.camera import Camera
from bodyplay.trackers.base import Tracker, TrackerCapabilities, TrackResult, lost_result

__all__ = ["Tracker", "TrackerCapabilities", "TrackResult", "create_tracker", "lost_result"]


def create_tracker(
    name: str,
    cameras: Sequence[Camera],
    options: Any = None,
    registry: Any = None,
) -> Tracker:
    """Create a tracker by its plugin name (entry point group ``bodyplay.trackers``).

    ``cameras`` are the calibrated cameras whose frames the tracker will get;
    ``options`` is the tracker's own options dataclass (its defaults when None).
    Unknown names raise :class:`~bodyplay.errors.PluginError` listing what is installed.
    """
    from bodyplay.plugins import PluginRegistry

    reg = registry if registry is not None else PluginRegistry()
    kwargs: dict[str, Any] = {"cameras": tuple(cameras)}
    if options is not None:
        kwargs["options"] = options
    tracker: Tracker = reg.create("trackers", name, **kwargs)
    return tracker
