"""Pose trackers: estimate the 17 joints from camera frames, one
:class:`~bodyplay.trackers.base.TrackResult` per frame set.

:mod:`bodyplay.trackers.base` holds what every tracker shares (the ``Tracker``
protocol, its capabilities and result type), so that sessions, evaluation and games
work with any of them; each published method lives in its own subpackage
(``colorshirt``, ``silhouette``; DESIGN.md gives a screen on each).
"""
