"""What a game implements (:class:`Game`) and what it is given (:class:`GameContext`).

A game is a short program: ``setup`` builds its state and subscribes to session
events, ``update`` advances its rules by one fixed step, ``draw`` describes the
frame as a :class:`~bodyplay.app.scene.Scene`, ``summary`` returns what the round
produced. The kit (:func:`~bodyplay.app.runner.run_game`) owns the loop, the
session, the physics world, the window or the video, and the timing.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from bodyplay.app.options import GameOptions
from bodyplay.body.joints import NUM_JOINTS
from bodyplay.events.types import PoseEvent

if TYPE_CHECKING:
    from bodyplay.app.scene import Scene
    from bodyplay.capture.frames import FrameSet
    from bodyplay.physics.options import PhysicsOptions
    from bodyplay.physics.world import PhysicsWorld
    from bodyplay.runtime.session import Session

__all__ = ["Game", "GameContext", "STAGES"]

STAGES: tuple[str, ...] = ("capture", "tracking", "physics", "game", "render", "video")
"""The stages the runner times: reading a frame from the source (for a virtual
player: the synthetic camera rendering it), tracking it (tracker, filters, events),
the physics world, the game's update, drawing the scene (with read-back), encoding
the video."""


@dataclass(eq=False)
class GameContext:
    """Everything a game touches while it runs.

    ``options`` (the run's :class:`GameOptions`), ``session`` (subscribe with
    ``ctx.session.on("contact")``), ``physics`` (a PhysicsWorld when the game asked
    for one with ``Game.physics_options``), ``rng`` (numpy Generator from the seed),
    ``t`` (game time: seconds of fixed steps played, stops while paused), ``pose``
    (latest PoseEvent or None), ``last_seen`` ((17, 3) where each joint was last
    tracked, NaN if never), ``frame`` (latest camera FrameSet, None for pose input),
    ``paused`` / ``pause_reason``, ``stage_times`` (seconds per stage), ``out``.
    """

    options: GameOptions
    session: Session
    rng: np.random.Generator
    physics: PhysicsWorld | None = None
    t: float = 0.0
    steps: int = 0
    pose: PoseEvent | None = None
    frame: FrameSet | None = None
    last_seen: NDArray[np.float64] = field(
        default_factory=lambda: np.full((NUM_JOINTS, 3), np.nan)
    )
    paused: bool = False
    pause_reason: str = ""
    finished: bool = False
    tracked_frames: int = 0
    frames: int = 0
    stage_times: dict[str, float] = field(default_factory=lambda: dict.fromkeys(STAGES, 0.0))

    @property
    def out(self) -> Path:
        """The folder of the video, the summary and any file the game saves."""
        return self.options.out

    @property
    def tracking(self) -> bool:
        """Whether the latest pose has at least one joint that is not lost."""
        p = self.pose
        return p is not None and any(s != "lost" for s in p.state)

    def finish(self) -> None:
        """End the round: the runner stops after this step and writes the summary."""
        self.finished = True

    def pause(self, reason: str = "paused") -> None:
        """Stop game time (and the physics world) until :meth:`resume`."""
        self.paused = True
        self.pause_reason = reason

    def resume(self) -> None:
        """Let game time run again."""
        self.paused = False
        self.pause_reason = ""

    @contextmanager
    def timed(self, stage: str) -> Iterator[None]:
        """Add the time spent in the ``with`` block to ``stage_times[stage]``."""
        t0 = time.perf_counter()
        try:
            yield
        finally:
            self.stage_times[stage] = self.stage_times.get(stage, 0.0) + (
                time.perf_counter() - t0
            )


class Game:
    """Base class of a game; override what you need (every method has a default).

    Class attributes: ``name`` (file names: ``<name>.mp4``), ``title`` (window),
    ``physics_options`` (a :class:`~bodyplay.physics.options.PhysicsOptions` to get
    ``ctx.physics``; None: no physics world), ``gestures`` and ``filters`` (what the
    session recognizes and how it smooths the joints first).
    """

    name: str = "game"
    title: str = "bodyplay game"
    physics_options: PhysicsOptions | None = None
    gestures: tuple[str, ...] = ()
    """Gestures the session recognizes (built-in names or .toml paths; empty: none)."""
    filters: tuple[str, ...] = ()
    """Joint filters (plugin names, e.g. ``"one_euro"``) applied before the gestures."""

    def setup(self, ctx: GameContext) -> None:
        """Build the game's state and subscribe to session events (called once)."""

    def update(self, ctx: GameContext, dt: float) -> None:
        """Advance the rules by one fixed step of ``dt`` seconds (not while paused)."""

    def draw(self, ctx: GameContext, scene: Scene) -> None:
        """Describe this frame: camera, primitives, the avatar, HUD lines."""
        if ctx.pose is not None:
            scene.avatar(ctx.pose.joints, ctx.pose.state, last_seen=ctx.last_seen)

    def summary(self, ctx: GameContext) -> dict[str, Any]:
        """What the round produced, merged into summary.json (JSON-ready values)."""
        return {}

    def restart(self, ctx: GameContext) -> None:
        """Start the round again (the ``r`` key); default: nothing."""

    def on_pause(self, ctx: GameContext, paused: bool) -> None:
        """Called when the game pauses or resumes (key or lost tracking)."""

    def finish(self, ctx: GameContext) -> None:
        """Called once after the last step, before :meth:`summary` (save plots here)."""

    def expected_seconds(self, options: GameOptions) -> float | None:
        """Game seconds a round should last (the progress bar's total); None: unknown."""
        return None

    def tracker_options(self, tracker: str) -> Any:
        """Options for the named tracker on image input (None: its defaults), e.g. a
        silhouette hierarchy that also holds the game's own motions."""
        return None

    def virtual_player(self, options: GameOptions) -> Any:
        """The embedded default input (``--input virtual``), made before the session:
        a pose source, or a frame source with calibrated ``cameras`` that the options'
        tracker reads (a source with ``pose_level = True`` is never tracked). Keep a
        reference to steer it from ``update`` (closed loop). None: no virtual player."""
        return None


GameFactory = Callable[[], Game]
