"""Virtual players as input: the controller's actor filmed by synthetic webcams, or as poses.

:class:`VirtualPlayerSource` is a frame source like a webcam or a capture folder
(iterable of :class:`~bodyplay.capture.frames.FrameSet`, calibrated ``cameras``,
``fps``, ``close``) that renders the actor posed by a
:class:`~bodyplay.virtual.controller.PoseController` with
:class:`~bodyplay.synth.SyntheticCamera`. Frames are rendered lazily, one per
``next()``: a game may change the controller's targets between frames (closed
loop), so nothing is rendered ahead. The GL renderer is made once, at the first
frame, and reused. :class:`VirtualPoseSource` is the pose-level twin (PoseSamples,
no images) for fast gameplay tests. Both expose ``truth``: the joints of the last
frame they produced.
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from types import TracebackType
from typing import TYPE_CHECKING, Any, Self

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import NUM_JOINTS
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import CaptureError, ConfigError
from bodyplay.runtime.sources import UPPER_BODY_ONLY, PoseSample, state_from_joints
from bodyplay.virtual.controller import PoseController

if TYPE_CHECKING:
    from bodyplay.synth.camera import SynthFrame

__all__ = ["VirtualPlayerSource", "VirtualPoseSource"]

_LEGS = np.arange(11, 17)


def _check_controller(controller: Any) -> None:
    if not callable(getattr(controller, "pose_at", None)) or not hasattr(controller, "skeleton"):
        raise ConfigError(
            f"a virtual player needs a PoseController (pose_at(t) and skeleton), got "
            f"{type(controller).__name__}; e.g. ReachController() or TimelineController(tl)"
        )


def _check_seconds(seconds: float | None) -> float | None:
    if seconds is None:
        return None
    if not (math.isfinite(seconds) and seconds >= 0):
        raise ConfigError(f"seconds must be >= 0 (or None for no end), got {seconds}")
    return float(seconds)


def _reach_area(skeleton: Any, pose: NDArray[np.float64]) -> NDArray[np.float64]:
    """(5, 17, 3) joints a camera should frame for a controller that does not say:
    its first pose, and the rest pose where it stands with the arms raised and out
    and a half-metre step either way (the synthetic camera's play area)."""
    out = [skeleton.joint_positions(pose)]
    for dx in (-0.5, 0.5):
        for arm in (0.0, 1.2):
            q = skeleton.pose(
                root=(pose[0] + dx, skeleton.pelvis_height, pose[2]),
                rotations={"l_shoulder": (0.0, 0.0, arm), "r_shoulder": (0.0, 0.0, -arm)},
            )
            out.append(skeleton.joint_positions(q))
    return np.stack(out)


def _frame_count(seconds: float | None, fps: float) -> int | None:
    return None if seconds is None else int(math.floor(seconds * fps + 1e-9)) + 1


class VirtualPlayerSource:
    """The actor posed by ``controller``, filmed by one or two synthetic webcams.

    ``cameras`` (1 or 2), ``fps``, ``size`` (width, height), ``seed`` (rig jitter and
    sensor noise), ``background``, ``lighting``, ``noise``, ``body`` (the actor's
    preset; the controller should pose that actor's skeleton) and any other
    :func:`~bodyplay.synth.make_synthetic_camera_options` keyword (``camera_options``)
    set up the synthetic camera. The rig frames ``controller.frame_joints()`` when
    the controller has it (else its pose at 0 s and a play area about it: arms up
    and out, a half-metre step either way). ``seconds`` (None: no end) bounds
    the stream; ``empty_room_seconds`` of the room without the player come first
    (the player is in view from the first frame by default). Frame ``i`` is at
    ``i / fps`` seconds on the controller's clock. The stream plays once.
    ``lookahead`` renders the next frame in a worker thread while the caller
    tracks this one (one frame of camera latency; see docs/virtual-players.md).
    """

    pose_level = False
    """Frames, not poses: a session tracks them (the game kit reads this)."""

    def __init__(
        self,
        controller: PoseController,
        *,
        cameras: int = 1,
        fps: float = 30.0,
        size: tuple[int, int] | str = (640, 480),
        seed: int = 0,
        background: str = "brick",
        lighting: str = "steady",
        noise: str = "low",
        body: str = "m",
        seconds: float | None = None,
        empty_room_seconds: float = 0.0,
        camera_options: dict[str, Any] | None = None,
        lookahead: bool = False,
    ) -> None:
        from bodyplay.synth.camera import SyntheticCamera
        from bodyplay.synth.options import make_synthetic_camera_options

        _check_controller(controller)
        self.controller = controller
        self.seconds = _check_seconds(seconds)
        if not (math.isfinite(empty_room_seconds) and 0.0 <= empty_room_seconds <= 60.0):
            raise ConfigError(f"empty_room_seconds {empty_room_seconds} must be within 0..60")
        self.empty_room_seconds = float(empty_room_seconds)
        opts = make_synthetic_camera_options(
            cameras=cameras, fps=fps, size=size, seed=seed, background=background,
            lighting=lighting, noise=noise, body=body, **(camera_options or {}),
        )
        from bodyplay.body.actor import load_actor

        actor = load_actor(opts.body)
        if controller.skeleton.pose_dim != actor.skeleton.pose_dim:
            raise ConfigError("the controller's pose vectors do not fit the actor's skeleton")
        framing = getattr(controller, "frame_joints", None)
        if callable(framing):
            joints = np.asarray(framing(), dtype=np.float64)
        else:
            joints = _reach_area(actor.skeleton, np.asarray(controller.pose_at(0.0)))
        self.camera = SyntheticCamera(opts, frame_joints=joints, actor=actor,
                                      duration=self.seconds)
        self.options = opts
        self.fps = float(opts.fps)
        self.cameras: tuple[Camera, ...] | None = self.camera.cameras
        self.last: SynthFrame | None = None
        self.render_seconds = 0.0
        """Wall seconds spent posing and rendering so far (for per-stage timing)."""
        self.last_render_ms = 0.0
        """Milliseconds the last frame took to pose and render."""
        self._started = False
        self._closed = False
        self.lookahead = bool(lookahead)
        self._pool: ThreadPoolExecutor | None = None

    @property
    def truth(self) -> NDArray[np.float64] | None:
        """(17, 3) true joints of the last frame (the actor skeleton's FK; NaN for the
        empty room), None before the first frame."""
        return None if self.last is None else self.last.joints

    def __len__(self) -> int:
        n = _frame_count(self.seconds, self.fps)
        if n is None:
            raise TypeError("an endless VirtualPlayerSource (seconds=None) has no length")
        return n

    def _shoot(self, i: int, pose: NDArray[np.float64] | None) -> SynthFrame:
        """Render frame ``i`` (``pose`` None: the empty room); time it."""
        t = i / self.fps
        start = time.perf_counter()
        if pose is None:
            sf = self.camera.capture_empty(t, i)
        else:
            sf = self.camera.capture(t, pose, index=i)
        self.last_render_ms = 1000.0 * (time.perf_counter() - start)
        self.render_seconds += self.last_render_ms / 1000.0
        return sf

    def _pose(self, i: int) -> NDArray[np.float64] | None:
        """The controller's pose for frame ``i`` (asked in the caller's thread)."""
        t = i / self.fps
        if t < self.empty_room_seconds - 1e-9:
            return None
        return np.asarray(self.controller.pose_at(t), dtype=np.float64)

    def __iter__(self) -> Iterator[FrameSet]:
        """Render frame sets one at a time, posing the actor as the controller says.

        A frame whose pose or render fails raises CaptureError (naming the frame and
        the cause) from ``next``; the stream goes on with the next frame, so a
        session reports the one frame and keeps running.
        """
        return _FrameStream(self, _frame_count(self.seconds, self.fps))

    def _start(self) -> None:
        """Checks and set-up at the first frame (iterating is lazy, like a generator)."""
        if self._closed:
            raise CaptureError("this VirtualPlayerSource was closed; create a new one")
        if self._started:
            raise CaptureError("a VirtualPlayerSource plays once (the game steers it live); "
                               "create a new one to play again")
        self._started = True
        if self.lookahead:
            self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="virtual-player")

    def _stop_pool(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            # the stream plays once: release GL in the thread whose context it is
            pool.submit(self.camera.close).result()
            pool.shutdown(wait=True)

    def close(self) -> None:
        """Release the renderer; iterating afterwards raises CaptureError."""
        self._closed = True
        if self._pool is not None:
            self._stop_pool()
        else:
            self.camera.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


def _frame_error(i: int, exc: BaseException) -> CaptureError:
    return CaptureError(f"virtual player frame {i} failed: {exc!r} (the controller's "
                        f"pose_at or the synthetic camera); the stream goes on")


class _FrameStream:
    """The iterator of a :class:`VirtualPlayerSource` (one per source).

    With ``lookahead`` frame i + 1 renders in the source's worker thread while the
    caller tracks frame i. Its pose is asked for (in the caller's thread) before
    frame i is handed over, so a game's reaction to frame i shows from frame i + 2
    on (one frame of camera latency) and the frames never depend on thread timing.
    Every GL call of the camera then happens in the worker (an EGL context belongs
    to one thread).
    """

    def __init__(self, source: VirtualPlayerSource, n: int | None) -> None:
        self.source = source
        self.n = n
        self.i = 0
        self.begun = False
        self.pending: deque[Future[SynthFrame]] = deque()

    def __iter__(self) -> _FrameStream:
        return self

    def _has(self, i: int) -> bool:
        return self.n is None or i < self.n

    def _submit(self, i: int) -> None:
        src = self.source
        assert src._pool is not None
        try:
            pose = src._pose(i)
        except Exception as exc:  # reported when frame i is due
            failed: Future[SynthFrame] = Future()
            failed.set_exception(exc)
            self.pending.append(failed)
            return
        self.pending.append(src._pool.submit(src._shoot, i, pose))

    def _finish(self) -> None:
        for fut in self.pending:
            fut.cancel()
        self.pending.clear()
        self.source._stop_pool()

    def __next__(self) -> FrameSet:
        src = self.source
        i = self.i
        if not self.begun:
            src._start()  # raises again on every call if this stream may not play
            self.begun = True
        if src._closed or not self._has(i):
            self._finish()
            raise StopIteration
        self.i += 1
        try:
            if src._pool is None:
                src.last = src._shoot(i, src._pose(i))
            else:
                if not self.pending:
                    self._submit(i)
                if self._has(i + 1):
                    self._submit(i + 1)
                src.last = self.pending.popleft().result()
        except Exception as exc:
            raise _frame_error(i, exc) from exc
        return src.last.frames


class VirtualPoseSource:
    """The controller's poses as PoseSamples at ``fps`` (no images, no tracker).

    The fast path for gameplay tests: the same closed loop as
    :class:`VirtualPlayerSource` (poses are asked for one sample at a time) without
    rendering. ``noise`` adds seeded Gaussian jitter (metres) to the reported
    joints, like a tracker's; ``upper_body_only`` reports the legs as lost (the
    color shirt). ``truth`` holds the exact joints of the last sample.
    """

    pose_level = True
    """Poses, no images: a session takes them without a tracker."""
    cameras: tuple[Camera, ...] | None = None
    """No cameras: nothing to calibrate or track."""

    def __init__(
        self,
        controller: PoseController,
        *,
        fps: float = 30.0,
        seconds: float | None = None,
        noise: float = 0.0,
        seed: int = 0,
        upper_body_only: bool = False,
    ) -> None:
        _check_controller(controller)
        if not (math.isfinite(fps) and 1.0 <= fps <= 1000.0):
            raise ConfigError(f"fps {fps} must be within 1..1000")
        if not (math.isfinite(noise) and noise >= 0):
            raise ConfigError(f"noise must be >= 0 metres, got {noise}")
        self.controller = controller
        self.fps = float(fps)
        self.seconds = _check_seconds(seconds)
        self.noise = float(noise)
        self.seed = int(seed)
        self.upper_body_only = bool(upper_body_only)
        self.capabilities: tuple[str, ...] = (UPPER_BODY_ONLY,) if upper_body_only else ()
        self.truth: NDArray[np.float64] | None = None

    def __len__(self) -> int:
        n = _frame_count(self.seconds, self.fps)
        if n is None:
            raise TypeError("an endless VirtualPoseSource (seconds=None) has no length")
        return n

    def __iter__(self) -> Iterator[PoseSample]:
        """Pose samples, asking the controller for each just before handing it over.

        A sample whose pose fails raises CaptureError from ``next`` and the stream
        goes on with the next one (a session reports the one frame).
        """
        rng = np.random.default_rng(self.seed)
        n = _frame_count(self.seconds, self.fps)
        i = 0

        def step() -> PoseSample:
            nonlocal i
            if n is not None and i >= n:
                raise StopIteration
            frame, i = i, i + 1
            try:
                return self._sample(frame, rng)
            except Exception as exc:
                raise CaptureError(f"virtual player sample {frame} failed: {exc!r}; "
                                   f"the stream goes on") from exc

        return iter(step, None)  # type: ignore[arg-type]

    def _sample(self, i: int, rng: np.random.Generator) -> PoseSample:
        t = i / self.fps
        q = np.asarray(self.controller.pose_at(t), dtype=np.float64)
        truth = self.controller.skeleton.joint_positions(q)
        if truth.shape != (NUM_JOINTS, 3):
            raise ConfigError(f"the controller's skeleton gave joints of shape {truth.shape}")
        self.truth = truth
        j = truth + rng.normal(0.0, self.noise, size=truth.shape) if self.noise else truth
        if self.upper_body_only:
            j = j.copy()
            j[_LEGS] = np.nan
        conf = np.where(np.all(np.isfinite(j), axis=1), 1.0, 0.0)
        return PoseSample(t=t, frame=i, joints=j, state=state_from_joints(j),
                          confidence=conf, capabilities=self.capabilities, pose=q)
