"""The game loop every example game shares: :func:`run_game`.

One session step per camera frame (read, track, filter, emit events); the physics
world follows each pose; the game's rules advance in fixed steps of
``1 / update_hz`` seconds of capture time in between, independent of the camera's
rate; the scene is drawn for the window on every frame, and for the video at
``video_fps``. Everything derives from the input and the seed, so the same input
and seed give the same summary.

While the tracker has lost the player (``tracking: lost``) the game pauses: game
time stops, the physics world is not stepped, and it resumes without replaying the
gap (:meth:`~bodyplay.physics.world.PhysicsWorld.resume`). Keys in a window: Esc /
q quit, p / space pause, r restart.
"""

from __future__ import annotations

import json
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bodyplay.app.game import STAGES, Game, GameContext
from bodyplay.app.inputs import GameInput, input_hint, open_game_input
from bodyplay.app.options import GameOptions
from bodyplay.app.renderer import SceneRenderer
from bodyplay.app.scene import Scene
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import BodyplayError, CaptureError
from bodyplay.events.types import PoseEvent, TrackingEvent

__all__ = ["GameError", "GameResult", "run_game", "MAX_GAME_FAILURES"]

MAX_GAME_FAILURES = 30
"""Consecutive failures of a game's update or draw that end a run (fewer are skipped)."""


class GameError(BodyplayError, RuntimeError):
    """A game's own code kept failing; the message names the method and the error."""

_log = logging.getLogger("bodyplay.app")


@dataclass(frozen=True, eq=False)
class GameResult:
    """What a run produced: the ``summary`` dict (also in ``summary_path``), the
    ``video_path`` (None without video) and the final ``context``."""

    summary: dict[str, Any]
    summary_path: Path | None
    video_path: Path | None
    context: GameContext


class _TimedSource:
    """Wraps a session's source to time reading each frame (the ``capture`` stage)."""

    def __init__(self, source: Any, ctx: GameContext) -> None:
        self._source = source
        self._ctx = ctx

    def __getattr__(self, name: str) -> Any:
        return getattr(self._source, name)

    def __len__(self) -> int:
        return len(self._source)

    def __iter__(self) -> Any:
        it = iter(self._source)
        times = self._ctx.stage_times
        while True:
            t0 = time.perf_counter()
            try:
                item = next(it)
            except StopIteration:
                return
            finally:
                times["capture"] += time.perf_counter() - t0
            yield item


class _Loop:
    """The state of one run (kept out of the public API)."""

    def __init__(self, game: Game, options: GameOptions, inp: GameInput) -> None:
        self.game = game
        self.options = options
        self.inp = inp
        session = inp.session
        self.ctx = GameContext(options, session, np.random.default_rng(options.seed))
        if game.physics_options is not None:
            from bodyplay.physics.world import PhysicsWorld

            self.ctx.physics = PhysicsWorld(
                game.physics_options, emit=session.emit, now=session.now
            )
        self._physics_paused = False
        self._prev_t: float | None = None
        self.budget = 0.0
        self.pauses = 0
        self.paused_seconds = 0.0
        self.found_once = False
        self.failures = 0
        self.errors = 0
        self.first_t: float | None = None
        session.source = _TimedSource(session.source, self.ctx)
        session.subscribe("pose", self._on_pose)
        session.subscribe("tracking", self._on_tracking)
        session.add_frame_listener(self._on_item)

    # ---- session callbacks ---------------------------------------------------------
    def _on_item(self, item: Any) -> None:
        if isinstance(item, FrameSet):
            self.ctx.frame = item

    def _on_pose(self, ev: PoseEvent) -> None:
        ctx = self.ctx
        ctx.pose = ev
        ok = np.array([s != "lost" for s in ev.state]) & np.all(np.isfinite(ev.joints), axis=1)
        if ok.any():
            ctx.last_seen[ok] = ev.joints[ok]
        world = ctx.physics
        if world is None:
            return
        with ctx.timed("physics"):
            if ctx.paused:
                self._physics_paused = True
            elif self._physics_paused:
                self._physics_paused = False
                world.resume(ev)
            else:
                world.on_pose(ev)

    def _on_tracking(self, ev: TrackingEvent) -> None:
        if ev.status == "found":
            self.found_once = True
            if self.ctx.paused and self.ctx.pause_reason == "tracking lost":
                self.set_paused(False)
        elif ev.status == "lost" and self.options.pause_when_lost and not self.ctx.paused:
            self.set_paused(True, "tracking lost")

    def _guarded(self, what: str, fn: Any, *args: Any) -> None:
        """Call a game method; a failure is logged and skipped (one bad step never
        ends a run) unless it fails MAX_GAME_FAILURES times in a row."""
        try:
            fn(*args)
        except Exception as exc:
            self.failures += 1
            self.errors += 1
            _log.exception("%s.%s failed", type(self.game).__name__, what)
            if self.failures >= MAX_GAME_FAILURES:
                raise GameError(
                    f"{type(self.game).__name__}.{what} failed {self.failures} times in a "
                    f"row (last: {exc!r}); see the log above"
                ) from exc
        else:
            self.failures = 0

    def set_paused(self, paused: bool, reason: str = "paused") -> None:
        """Pause or resume the game (key or tracking), telling the game."""
        ctx = self.ctx
        if paused == ctx.paused:
            return
        if paused:
            ctx.pause(reason)
            self.pauses += 1
        else:
            ctx.resume()
        try:
            self.game.on_pause(ctx, paused)
        except Exception:  # a game callback never ends the run
            _log.exception("%s.on_pause failed", type(self.game).__name__)

    # ---- one camera frame ----------------------------------------------------------
    def step(self) -> bool:
        """Consume one frame; False when the input ended."""
        ctx = self.ctx
        st = ctx.stage_times
        before = st["physics"] + st["capture"]
        t0 = time.perf_counter()
        pose = ctx.session.step()
        inner = st["physics"] + st["capture"] - before
        ctx.stage_times["tracking"] += time.perf_counter() - t0 - inner
        if ctx.session.done:
            return False
        if pose is None:
            return True
        ctx.frames += 1
        if any(s != "lost" for s in pose.state):
            ctx.tracked_frames += 1
        if self.first_t is None:
            self.first_t = pose.t
        elapsed = 0.0 if self._prev_t is None else pose.t - self._prev_t
        self._prev_t = pose.t
        if (not self.found_once and self.inp.kind != "custom"
                and pose.t - self.first_t > self.options.no_player_seconds):
            raise CaptureError(
                f"no player found in the first {self.options.no_player_seconds:g} s of "
                f"{self.inp.description}: the player must stand in view"
                + (" wearing the printed color shirt (`bodyplay shirt`)"
                   if self.options.tracker == "colorshirt" and self.inp.kind != "clip" else "")
                + f"; {input_hint()}"
            )
        if ctx.paused:
            self.paused_seconds += elapsed
            return True
        self.budget += elapsed
        dt = self.options.dt
        with ctx.timed("game"):
            while self.budget >= dt - 1e-9 and not ctx.finished:
                self.budget -= dt
                self._guarded("update", self.game.update, ctx, dt)
                ctx.steps += 1
                ctx.t = ctx.steps * dt
                if self.options.seconds is not None and ctx.t >= self.options.seconds - 1e-9:
                    ctx.finish()
        return True

    def scene(self) -> Scene:
        """The game's drawing of the current frame, with the kit's pause banner."""
        o = self.options
        scene = Scene(o.width, o.height)
        self._guarded("draw", self.game.draw, self.ctx, scene)
        if self.ctx.paused:
            msg = ("PLAYER LOST - step back into view" if self.ctx.pause_reason == "tracking lost"
                   else "PAUSED - press p to play")
            scene.text(msg, (o.width / 2, o.height / 2), 1.3, (1.0, 0.85, 0.2), anchor="center")
        return scene


def _expected_frames(game: Game, options: GameOptions, inp: GameInput) -> int | None:
    """Frames the progress bar expects: the input's length, the seconds asked for or
    the game's own estimate of a round, whichever is known and smallest."""
    src = inp.session.source
    n: int | None
    try:
        n = len(src)
    except TypeError:
        n = None
    seconds = options.seconds
    if seconds is None:
        try:
            seconds = game.expected_seconds(options)
        except Exception:
            seconds = None
    if seconds is not None:
        k = int(math.ceil(seconds * inp.fps)) + 1
        n = k if n is None else min(n, k)
    return n


def run_game(
    game: Game,
    options: GameOptions,
    *,
    source: Any = None,
    window: Any = None,
) -> GameResult:
    """Play ``game`` with ``options`` until it finishes, the input ends, ``seconds``
    of game time pass, or the player quits; write the video and summary.json.

    ``source`` replaces ``options.input`` (tests pass a ScriptedPlayer or a
    VirtualPlayerSource); ``window`` replaces the pygame window (tests). Headless
    runs render with EGL. Returns a :class:`GameResult`.
    """
    t_start = time.perf_counter()
    headless = options.is_headless and window is None
    inp = open_game_input(options, game, source=source)
    loop = _Loop(game, options, inp)
    ctx = loop.ctx
    out = options.out
    out.mkdir(parents=True, exist_ok=True)
    video_path = out / f"{game.name}.mp4" if options.video else None
    win = window
    renderer: SceneRenderer | None = None
    writer: Any = None
    bar: Any = None
    wall0: float | None = None
    realtime = options.realtime if options.realtime is not None else not headless
    try:
        if not headless and win is None:
            from bodyplay.app.window import GameWindow

            win = GameWindow(options.width, options.height, game.title)
        renderer = SceneRenderer(options.width, options.height,
                                 ctx=None if win is None else win.ctx)
        if video_path is not None:
            from bodyplay.capture.video import VideoWriter

            writer = VideoWriter(video_path, options.video_fps)
        game.setup(ctx)
        if headless and options.progress:
            from tqdm import tqdm

            bar = tqdm(total=_expected_frames(game, options, inp), unit="frame", desc=game.name,
                       leave=False)
        next_video = 0.0
        while not ctx.finished:
            if win is not None:
                for action in win.poll():
                    if action == "quit":
                        ctx.finish()
                    elif action == "pause":  # the key never overrides a lost player
                        if not ctx.paused:
                            loop.set_paused(True, "paused")
                        elif ctx.pause_reason == "paused":
                            loop.set_paused(False)
                    elif action == "restart":
                        loop._guarded("restart", game.restart, ctx)
                if ctx.finished:
                    break
            if not loop.step():
                break
            if bar is not None:
                bar.update(1)
            pose = ctx.pose
            if pose is None or loop.first_t is None:
                continue
            t_rel = pose.t - loop.first_t
            if realtime and not inp.live:
                now = time.perf_counter()
                if wall0 is None:
                    wall0 = now - t_rel
                delay = wall0 + t_rel - now
                if delay > 0:
                    time.sleep(delay)
            due = writer is not None and t_rel >= next_video - 1e-9
            if not (due or win is not None):
                continue
            with ctx.timed("render"):
                image = renderer.render(loop.scene())
                if win is not None:
                    renderer.present(image)
                    win.flip()
            if due:
                with ctx.timed("video"):
                    while t_rel >= next_video - 1e-9:
                        writer.write(image)
                        next_video += 1.0 / options.video_fps
        game.finish(ctx)
    finally:
        if bar is not None:
            bar.close()
        if writer is not None:
            writer.close()
        if renderer is not None:
            renderer.release()
        if win is not None and window is None:
            win.close()
        if ctx.physics is not None:
            ctx.physics.close()
        inp.session.close()
    wall = time.perf_counter() - t_start
    summary = _summary(game, loop, inp, wall, video_path)
    summary_path = out / "summary.json"
    summary_path.write_text(json.dumps(summary, indent=2, allow_nan=False, default=_json_default))
    return GameResult(summary, summary_path, video_path, ctx)


def _json_default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serializable: {type(o).__name__}")


def _summary(game: Game, loop: _Loop, inp: GameInput, wall: float,
             video: Path | None) -> dict[str, Any]:
    ctx = loop.ctx
    st = {k: round(v, 4) for k, v in ctx.stage_times.items()}
    total = sum(ctx.stage_times[s] for s in STAGES) or 1.0
    frames = max(ctx.frames, 1)
    out: dict[str, Any] = {
        "game": game.name,
        "input": inp.description,
        "seed": loop.options.seed,
        "frames": ctx.frames,
        "game_seconds": round(ctx.t, 4),
        "game_steps": ctx.steps,
        "tracking_share": round(ctx.tracked_frames / frames, 4),
        "pauses": loop.pauses,
        "game_errors": loop.errors,
        "paused_seconds": round(loop.paused_seconds, 4),
        "video": str(video) if video is not None else None,
    }
    try:
        extra = game.summary(ctx)
    except Exception:
        _log.exception("%s.summary failed", type(game).__name__)
        extra = {"summary_error": True}
    for k, v in extra.items():
        out.setdefault(k, v)
    # timing last, and apart: it is the only part that differs between identical runs
    out["timing"] = {
        "wall_seconds": round(wall, 3),
        "frames_per_second": round(ctx.frames / wall, 2) if wall > 0 else None,
        "stage_seconds": st,
        "stage_share": {k: round(ctx.stage_times[k] / total, 4) for k in STAGES},
        "stage_ms_per_frame": {k: round(1000 * ctx.stage_times[k] / frames, 3) for k in STAGES},
    }
    out["options"] = loop.options.to_json()
    return out
