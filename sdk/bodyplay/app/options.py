"""What a game run is asked to do: :class:`GameOptions` and its validating factory.

Every example game takes the same options (``game_main`` builds them from one
command-line shape): where the player comes from (``input``), which tracker reads
the frames, how many synthetic cameras film the virtual player, how long to play,
the seed, window or headless, where the video and the summary go, the picture size,
the fixed game step and the video frame rate.
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = ["GameOptions", "make_game_options", "display_available", "VIRTUAL_INPUT"]

VIRTUAL_INPUT = "virtual"
"""The ``input`` naming a game's embedded default player (no hardware needed)."""


@dataclass(frozen=True)
class GameOptions:
    """One game run; build it with :func:`make_game_options` (it validates).

    ``input``: ``"virtual"`` (the game's embedded virtual player), a webcam index
    (``"0"``), a capture folder, a video file, a recording ``*.jsonl``, or
    ``"pose:CLIP"`` / ``"clip:CLIP"`` (a mocap clip fed as poses, no images).
    ``tracker``: tracker plugin for image input (``colorshirt``, ``silhouette``...).
    ``cameras``: synthetic cameras filming the virtual player (1 or 2).
    ``seconds``: game time to play (None: until the game or the input ends).
    ``seed``: the game's random numbers (the same seed and input replay exactly).
    ``headless``: no window; render with EGL and write the video (None: headless
    when no display is available). ``out``: folder of ``<name>.mp4`` and
    ``summary.json``. ``video``: write the video. ``width`` x ``height``: picture
    size. ``update_hz``: the fixed game step rate, independent of the camera's.
    ``video_fps``: frames per second of the video. ``realtime``: pace recorded
    and virtual input to the wall clock (None: only in a window).
    ``pause_when_lost``: pause the game while the tracker has lost the player.
    ``progress``: show a progress bar on headless runs. ``no_player_seconds``: image
    input that never shows the player this long stops with an error (a capture
    without the shirt, a camera pointing elsewhere).
    """

    input: str = VIRTUAL_INPUT
    tracker: str = "colorshirt"
    cameras: int = 1
    seconds: float | None = None
    seed: int = 0
    headless: bool | None = None
    out: Path = Path("out/game")
    video: bool = True
    width: int = 640
    height: int = 480
    update_hz: float = 60.0
    video_fps: float = 30.0
    realtime: bool | None = None
    pause_when_lost: bool = True
    progress: bool = True
    no_player_seconds: float = 6.0

    @property
    def is_headless(self) -> bool:
        """Whether this run has no window (asked for, or no display available)."""
        return self.headless if self.headless is not None else not display_available()

    @property
    def dt(self) -> float:
        """The fixed game step in seconds (``1 / update_hz``)."""
        return 1.0 / self.update_hz

    def replace(self, **changes: Any) -> GameOptions:
        """A validated copy with ``changes`` applied."""
        return make_game_options(self, **changes)

    def to_json(self) -> dict[str, Any]:
        """The options as a JSON-ready dict (written into summary.json)."""
        d = dataclasses.asdict(self)
        d["out"] = str(self.out)
        return d

    def __post_init__(self) -> None:
        check_option_types(self)


def display_available() -> bool:
    """Whether a window can be opened: a display on Linux, always on macOS / Windows."""
    if os.environ.get("SDL_VIDEODRIVER", "") in ("dummy", "offscreen"):
        return False
    if sys.platform.startswith("linux"):
        return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    return True


def make_game_options(base: GameOptions | None = None, **changes: Any) -> GameOptions:
    """``base`` (default :class:`GameOptions`) with ``changes``, validated.

    Raises ConfigError naming the bad option and what is allowed.
    """
    base = base or GameOptions()
    unknown = [k for k in changes if k not in {f.name for f in dataclasses.fields(GameOptions)}]
    if unknown:
        raise ConfigError(f"unknown game option(s) {', '.join(unknown)}")
    if "out" in changes and changes["out"] is not None:
        changes["out"] = Path(changes["out"])
    o = dataclasses.replace(base, **changes)
    if not isinstance(o.input, str) or not o.input.strip():
        raise ConfigError("input must be a non-empty string (try --input virtual)")
    for prefix in ("pose:", "clip:"):
        if o.input.startswith(prefix) and not o.input[len(prefix):].strip():
            raise ConfigError(
                f"--input {prefix}CLIP needs a clip name or BVH path after '{prefix}'"
            )
    if not isinstance(o.tracker, str) or not o.tracker:
        raise ConfigError("tracker must name a tracker plugin, e.g. colorshirt")
    if o.cameras not in (1, 2):
        raise ConfigError(f"cameras must be 1 or 2, got {o.cameras!r}")
    if o.seconds is not None and not (math.isfinite(o.seconds) and o.seconds > 0):
        raise ConfigError(f"seconds must be a positive number (or None), got {o.seconds!r}")
    if not isinstance(o.seed, int) or isinstance(o.seed, bool) or o.seed < 0:
        raise ConfigError(f"seed must be an integer >= 0, got {o.seed!r}")
    for name in ("width", "height"):
        v = getattr(o, name)
        if not isinstance(v, int) or not 64 <= v <= 4096:
            raise ConfigError(f"{name} must be an integer number of pixels in 64..4096, got {v!r}")
    if not (math.isfinite(o.update_hz) and 10.0 <= o.update_hz <= 1000.0):
        raise ConfigError(f"update_hz must be in 10..1000 steps a second, got {o.update_hz!r}")
    if not (math.isfinite(o.no_player_seconds) and o.no_player_seconds > 0):
        raise ConfigError(f"no_player_seconds must be positive, got {o.no_player_seconds!r}")
    if not (math.isfinite(o.video_fps) and 1.0 <= o.video_fps <= 240.0):
        raise ConfigError(f"video_fps must be in 1..240, got {o.video_fps!r}")
    return o
