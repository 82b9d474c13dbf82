"""Shared options of the commands that build a session (``events``, ``record``).

Input is either a mocap clip fed as poses (``--clip``) or frames from a capture
(``--input DIR --tracker NAME``), both resolved through a
:class:`~bodyplay.plugins.PluginRegistry` so installed plugins work the same way.
"""

from __future__ import annotations

import argparse
from typing import Any

from bodyplay.errors import ConfigError, PluginError
from bodyplay.plugins import PluginRegistry
from bodyplay.runtime.clock import FixedClock
from bodyplay.runtime.session import Session, SessionOptions, create_session

__all__ = ["add_session_arguments", "session_from_args"]


def add_session_arguments(p: argparse.ArgumentParser) -> None:
    """Add --clip / --input / --tracker / --fps / --gestures / --filter / --upper-body."""
    src = p.add_argument_group("input (one of)")
    src.add_argument("--clip", help="BVH file or built-in clip name, fed as poses (no tracker)")
    src.add_argument("--input", metavar="DIR",
                     help="capture folder, video, or webcam (index, webcam or webcam:N)")
    p.add_argument("--tracker", help="tracker plugin for --input (e.g. colorshirt)")
    p.add_argument("--fps", type=float, default=None,
                   help="resample --clip to this frame rate (default: the clip's)")
    p.add_argument("--gestures", default="builtin",
                   help="gesture recognizer plugin, or 'none' (default: builtin)")
    p.add_argument("--filter", action="append", default=[], metavar="NAME",
                   help="joint filter plugin to apply (repeatable), e.g. one_euro")
    p.add_argument("--upper-body", action="store_true",
                   help="report the clip's legs as lost, like the color-shirt tracker")
    p.add_argument("--force", action="store_true", help="overwrite the output file")


def session_from_args(args: argparse.Namespace, registry: PluginRegistry) -> Session:
    """Build the session the arguments describe, with a FixedClock at the input's rate."""
    if bool(args.clip) == bool(args.input):
        raise ConfigError("give exactly one input: --clip CLIP.bvh or --input DIR --tracker NAME")
    gestures: Any = None if args.gestures in (None, "", "none") else args.gestures
    if args.clip:
        source = registry.create("sources", "clip", args.clip, fps=args.fps,
                                 upper_body_only=args.upper_body)
        tracker = None
        clip = getattr(source, "clip", None)
        fps = float(clip.fps) if clip is not None else 30.0
    else:
        if not args.tracker:
            raise ConfigError(
                f"--input needs --tracker NAME; installed trackers: "
                f"{', '.join(registry.names('trackers')) or 'none'}"
            )
        if args.tracker not in registry.names("trackers"):
            raise PluginError(
                f"tracker {args.tracker!r} is not installed; installed trackers: "
                f"{', '.join(registry.names('trackers')) or 'none'} (entry point group "
                "bodyplay.trackers)"
            )
        source = registry.create("sources", "capture", args.input, fps=args.fps)
        tracker = registry.create("trackers", args.tracker,
                                  cameras=tuple(getattr(source, "cameras", None) or ()))
        fps = float(getattr(source, "fps", 30.0) or 30.0)
    return create_session(
        SessionOptions(),
        source=source,
        tracker=tracker,
        filters=list(args.filter),
        gestures=gestures,
        clock=FixedClock(1.0 / fps),
        plugins=registry,
    )
