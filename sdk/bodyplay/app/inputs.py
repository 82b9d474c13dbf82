"""Turning ``GameOptions.input`` into a session: webcam, capture, video, recording, clip,
or the game's virtual player.

Every input a game accepts is resolved here, once, for every game: the source, the
tracker that reads its frames (none for pose-level input) and the clock. Whatever
goes wrong (no webcam, a missing folder, an unknown clip) becomes a
:class:`~bodyplay.errors.BodyplayError` whose message names the embedded default,
``--input virtual``, which needs no hardware.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bodyplay.app.options import VIRTUAL_INPUT, GameOptions
from bodyplay.errors import BodyplayError, CaptureError, ConfigError
from bodyplay.runtime.clock import FixedClock, SystemClock
from bodyplay.runtime.session import Session, SessionOptions, create_session

__all__ = ["GameInput", "open_game_input", "input_hint"]


def input_hint() -> str:
    """The sentence every input error ends with."""
    return ("or run the embedded virtual player, which needs no camera: --input virtual "
            "(the default)")


@dataclass(eq=False)
class GameInput:
    """A resolved input: the ``session`` to step, a ``kind`` (``virtual``, ``webcam``,
    ``capture``, ``recording``, ``clip``), a human ``description``, ``live`` (a
    webcam: frames come at the camera's pace) and ``fps`` (frames a second)."""

    session: Session
    kind: str
    description: str
    live: bool
    fps: float


def _pose_level(source: Any) -> bool:
    return bool(getattr(source, "pose_level", False)) or not getattr(source, "cameras", None)


def _fail(msg: str, exc: BaseException | None = None) -> BodyplayError:
    err = CaptureError(f"{msg}; {input_hint()}")
    if exc is not None:
        err.__cause__ = exc
    return err


def open_game_input(
    options: GameOptions, game: Any = None, *, session_options: SessionOptions | None = None,
    source: Any = None,
) -> GameInput:
    """Resolve ``options.input`` into a session (with a tracker for image input).

    ``game`` supplies the virtual player (``game.virtual_player(options)``);
    ``source`` overrides the input entirely (tests pass a ScriptedPlayer). Clocks
    are FixedClocks at the input's frame rate except for a live webcam.
    """
    spec = options.input.strip()
    sopts = session_options or SessionOptions()
    if source is not None:
        kind, desc = "custom", type(source).__name__
    elif spec == VIRTUAL_INPUT:
        make = getattr(game, "virtual_player", None)
        source = make(options) if callable(make) else None
        if source is None:
            raise ConfigError(
                f"{getattr(game, 'name', 'this game')} has no virtual player; pass --input "
                "with a webcam index, a capture folder, a recording or pose:CLIP"
            )
        kind, desc = "virtual", f"virtual player ({type(source).__name__})"
    elif spec.startswith(("pose:", "clip:")):
        from bodyplay.runtime.sources import ClipPoseSource

        name = spec.split(":", 1)[1].strip()
        try:
            source = ClipPoseSource(name)
        except BodyplayError as exc:
            raise _fail(f"cannot load clip {name!r} ({exc})", exc) from exc
        except OSError as exc:
            raise _fail(f"cannot load clip {name!r} ({exc})", exc) from exc
        kind, desc = "clip", f"clip {name} (poses, no tracker)"
    elif spec.endswith(".jsonl"):
        from bodyplay.record.replay import ReplaySource

        try:
            source = ReplaySource(spec)
        except (BodyplayError, OSError) as exc:
            raise _fail(f"cannot read recording {spec} ({exc})", exc) from exc
        source.pose_level = True  # type: ignore[attr-defined]
        kind, desc = "recording", f"recording {spec}"
    else:
        from bodyplay.capture.sources import open_source

        is_cam = spec.isdigit()
        try:
            source = open_source(spec)
        except BodyplayError as exc:
            what = f"webcam {spec}" if is_cam else spec
            raise _fail(f"cannot open {what}: {exc}", exc) from exc
        except OSError as exc:
            raise _fail(f"cannot open {spec}: {exc}", exc) from exc
        if not getattr(source, "cameras", None):
            if is_cam:
                from bodyplay.capture.camera import Camera

                w, h = getattr(source, "size", (options.width, options.height))
                cam = Camera.from_fov(f"cam{spec}", int(w), int(h), 60.0)
                source.cameras = (cam,)  # type: ignore[attr-defined]
            else:
                raise _fail(
                    f"{spec} has no camera calibration (calib.json); trackers need it "
                    "(`bodyplay calibrate`)"
                )
        kind = "webcam" if is_cam else "capture"
        desc = f"webcam {spec}" if is_cam else f"capture {Path(spec).name}"
    tracker: Any = None
    if not _pose_level(source):
        cams = tuple(source.cameras)
        from bodyplay.trackers import create_tracker

        try:
            make_opts = getattr(game, "tracker_options", None)
            topts = make_opts(options.tracker) if callable(make_opts) else None
            tracker = create_tracker(options.tracker, cams, topts)
        except BodyplayError:
            raise
        desc += f" + {options.tracker} tracker"
    fps = float(getattr(source, "fps", 0.0) or 0.0)
    if fps <= 0:
        clip = getattr(source, "clip", None)
        rec = getattr(source, "recording", None)
        fps = float(getattr(clip, "fps", 0.0) or getattr(rec, "fps", 0.0) or 30.0)
    live = kind == "webcam"
    clock = SystemClock() if live else FixedClock(1.0 / fps)
    gestures: Any = None
    names = tuple(getattr(game, "gestures", ()) or ())
    if names:
        from bodyplay.gestures import GestureRecognizer, load_gestures

        gestures = GestureRecognizer(load_gestures(list(names)))
    filters = tuple(getattr(game, "filters", ()) or ())
    session = create_session(sopts, source=source, tracker=tracker, clock=clock,
                             filters=filters, gestures=gestures)
    return GameInput(session, kind, desc, live, fps)
