"""The color-shirt tracker (papers/color-shirt-mocap.txt): upper body from a colored shirt.

Build one with :func:`create_colorshirt_tracker` (a :class:`bodyplay.trackers.base.Tracker`);
docs/colorshirt.md says what each module does.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt.bodyselect import build_body_models
from bodyplay.trackers.colorshirt.colors import ColorModel, default_color_model
from bodyplay.trackers.colorshirt.database import (
    DatabaseOptions,
    PoseDatabase,
    load_or_build_database,
)
from bodyplay.trackers.colorshirt.ik import PriorModel, default_prior_model
from bodyplay.trackers.colorshirt.options import ColorShirtOptions, options_with_overrides
from bodyplay.trackers.colorshirt.tracker import ColorShirtTracker

__all__ = ["ColorShirtOptions", "ColorShirtTracker", "ColorModel", "DatabaseOptions",
           "PoseDatabase", "PriorModel", "create_colorshirt_tracker", "options_with_overrides"]


def create_colorshirt_tracker(
    options: ColorShirtOptions | None = None,
    cameras: Sequence[Camera] = (),
    database: PoseDatabase | None = None,
    progress: bool = False,
) -> ColorShirtTracker:
    """Validate the options and cameras and build a ready tracker; the pose database
    is loaded from the cache (built on first use) unless ``database`` is given."""
    opts = options or ColorShirtOptions()
    cams = tuple(cameras)
    if not 1 <= len(cams) <= 4:
        raise ConfigError(
            f"the color-shirt tracker needs 1 to 4 calibrated cameras, got {len(cams)}"
        )
    skeleton = Skeleton.from_shape("m" if opts.body == "auto" else opts.body)
    if database is None:
        cache = Path(opts.database_cache) if opts.database_cache else None
        database = load_or_build_database(
            skeleton, DatabaseOptions(size=opts.database_size, yaw_deg=opts.database_yaw),
            cache, progress=progress)
    model = ColorModel.load(opts.color_model) if opts.color_model else default_color_model()
    if opts.prior_model:
        import json

        p = Path(opts.prior_model)
        if not p.exists():
            raise ConfigError(f"{p}: no such IK prior file")
        prior = PriorModel.from_dict(json.loads(p.read_text()))
    else:
        prior = default_prior_model()
    bodies = build_body_models(cams) if opts.body == "auto" else None
    return ColorShirtTracker(opts, cams, database, model, prior, skeleton, bodies)
