"""The gesture recognizer: one small state machine per gesture definition.

Each frame the recognizer updates the body calibration and joint velocities, then
steps every gesture's machine:

* idle -> *started* when stage 1's conditions all hold (and the gesture is armed:
  after it ends, stage 1 must stop holding once before it can start again, and the
  cooldown must have passed; a cancel on a frame where stage 1 does not hold is
  that stop);
* a stage completes when its conditions have held for ``hold`` seconds; the next
  stage must then begin within its ``within`` seconds;
* *performed* when the last stage completes; *canceled* when a stage's conditions
  break before their hold time, when the next stage does not begin in time, or
  when the gesture's overall ``timeout`` passes.

Precedence (``inhibits`` in a definition): a gesture whose last stage completes while
a gesture that inhibits it is under way is *held* (progress 1, no event yet). Once
every such inhibitor has ended, the frame settles it: ``performed`` if none of them
was performed, ``canceled`` if one was. An inhibitor's ``performed`` cancels every
gesture it inhibits that is under way or held, and they may not start again for the
inhibitor's cooldown. So a subscriber to ``performed`` never sees a ``hit`` that was
the right arm of a ``double_hit``; a held gesture's ``performed`` comes late (when
its inhibitor gives up), and only then.

Events are :class:`~bodyplay.events.types.GestureEvent` with ``t`` the frame time and
``emitted_t`` the given clock's time (or ``t`` without a clock).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from bodyplay.errors import ConfigError
from bodyplay.events.types import GestureEvent, GesturePhase
from bodyplay.filters.base import JointState, as_joints, check_timestamp, lost_mask
from bodyplay.gestures.definitions import GestureDefinition, check_gesture_set, load_gestures
from bodyplay.gestures.features import (
    BodyCalibration,
    CalibrationOptions,
    FeatureFrame,
    VelocityTracker,
)
from bodyplay.optiontypes import check_option_types

__all__ = ["GestureOptions", "GestureRecognizer", "gesture_options"]


@dataclass(frozen=True)
class GestureOptions:
    """Settings of the recognizer.

    ``player``: written into every event. ``clock``: returns the session time for
    ``emitted_t`` (None: ``emitted_t = t``). ``calibration``: how torso length,
    floor and standing height are learned. ``emit_started``/``emit_canceled``: set
    False to receive only ``performed`` events.
    """

    player: int = 0
    clock: Callable[[], float] | None = None
    calibration: CalibrationOptions = field(default_factory=CalibrationOptions)
    emit_started: bool = True
    emit_canceled: bool = True

    def __post_init__(self) -> None:
        check_option_types(self)


def gesture_options(**kwargs: Any) -> GestureOptions:
    """Build validated :class:`GestureOptions` (ConfigError for unknown or bad values)."""
    try:
        o = GestureOptions(**kwargs)
    except TypeError as e:
        raise ConfigError(f"bad gesture option: {e}") from None
    _validate(o)
    return o


def _validate(o: GestureOptions) -> None:
    if not isinstance(o.player, int) or o.player < 0:
        raise ConfigError(f"GestureOptions.player must be an integer >= 0, got {o.player!r}")
    if o.clock is not None and not callable(o.clock):
        raise ConfigError("GestureOptions.clock must be a callable returning seconds, or None")
    c = o.calibration
    for name in ("time_constant", "velocity_window", "shift_window", "floor_margin",
                 "upright_band"):
        v = getattr(c, name)
        if not isinstance(v, int | float) or not v > 0:
            raise ConfigError(f"CalibrationOptions.{name} must be a positive number, got {v!r}")


@dataclass
class _Machine:
    """Run-time state of one gesture."""

    gesture: GestureDefinition
    stage: int = -1  # -1: idle
    holding_since: float | None = None
    last_done_t: float = 0.0
    started_t: float = 0.0
    armed: bool = True
    cooldown_until: float = -np.inf

    @property
    def held(self) -> bool:
        """Every stage completed, ``performed`` withheld while an inhibitor is under way."""
        return self.stage >= len(self.gesture.stages)

    def progress(self, t: float) -> float:
        n = len(self.gesture.stages)
        if self.stage < 0:
            return 0.0
        frac = 0.0
        if self.holding_since is not None:
            hold = self.gesture.stages[self.stage].hold
            frac = 1.0 if hold <= 0 else min((t - self.holding_since) / hold, 1.0)
        return min((self.stage + frac) / n, 1.0)


class GestureRecognizer:
    """Turns a stream of joint frames into gesture events.

    ``GestureRecognizer(load_gestures("builtin"))`` recognizes the built-in set;
    call :meth:`update` once per frame with strictly increasing times.
    """

    def __init__(
        self,
        definitions: Sequence[GestureDefinition] | str | None = None,
        options: GestureOptions | None = None,
    ) -> None:
        if definitions is None or isinstance(definitions, str):
            definitions = load_gestures(definitions or "builtin")
        names = [d.name for d in definitions]
        if len(set(names)) != len(names):
            raise ConfigError(f"gesture names must be unique, got {names}")
        self.definitions = tuple(definitions)
        self._settle_order = check_gesture_set(self.definitions)
        self.options = options if options is not None else GestureOptions()
        _validate(self.options)
        self.reset()

    def reset(self) -> None:
        """Forget calibration, velocities and every gesture in progress."""
        self.calibration = BodyCalibration(self.options.calibration)
        self._velocity = VelocityTracker(self.options.calibration.velocity_window)
        self._shift = VelocityTracker(self.options.calibration.shift_window)
        self._machines = [_Machine(d) for d in self.definitions]
        by_name = {m.gesture.name: m for m in self._machines}
        # Settled inhibitors first, so an inhibitor's `performed` cancels what it inhibits
        # before that gets its turn.
        self._settle = [by_name[d.name] for d in self._settle_order]
        self._inhibitors = {m.gesture.name: [o for o in self._machines
                                             if m.gesture.name in o.gesture.inhibits]
                            for m in self._machines}
        self._inhibited = {m.gesture.name: [by_name[g] for g in m.gesture.inhibits
                                            if g in by_name]
                           for m in self._machines}
        self._last_t: float | None = None

    @property
    def active(self) -> dict[str, float]:
        """Gestures in progress and their progress 0..1 (after the last frame); a gesture
        held back by an inhibitor under way shows 1.0."""
        t = self._last_t or 0.0
        return {m.gesture.name: m.progress(t) for m in self._machines if m.stage >= 0}

    def features(self, t: float, joints: ArrayLike, state: JointState = None) -> FeatureFrame:
        """Update calibration and velocities with a frame and return its features.

        :meth:`update` calls this; use it directly to inspect feature values.
        """
        j = as_joints(joints)
        j[lost_mask(j, state)] = np.nan
        check_timestamp(t, self._last_t)
        self._last_t = float(t)
        self.calibration.update(t, j)
        vel = self._velocity.update(t, j)
        shift = self._shift.displacement(t, j)
        return FeatureFrame(j, vel, self.calibration, shift)

    def update(self, t: float, joints: ArrayLike, state: JointState = None) -> list[GestureEvent]:
        """Process one frame at time ``t``; return the gesture events it caused."""
        frame = self.features(t, joints, state)
        events: list[GestureEvent] = []
        for m in self._machines:
            self._step(m, t, frame, events)
        self._settle_completed(t, events)
        return events

    def _settle_completed(self, t: float, events: list[GestureEvent]) -> None:
        """Emit ``performed`` for every completed gesture none of whose inhibitors is
        under way; an inhibitor's ``performed`` cancels what it inhibits."""
        for m in self._settle:
            if not m.held or any(i.stage >= 0 for i in self._inhibitors[m.gesture.name]):
                continue
            self._end(m, t, "performed", events)
            for v in self._inhibited[m.gesture.name]:
                if v.stage >= 0:
                    self._end(v, t, "canceled", events)
                v.cooldown_until = max(v.cooldown_until, t + m.gesture.cooldown)

    # ---- the state machine ----------------------------------------------------------
    def _holds(self, m: _Machine, k: int, frame: FeatureFrame) -> bool:
        stage = m.gesture.stages[k]
        conds = stage.when
        if stage.when_no_legs is not None and frame.legs_unseen:
            conds = stage.when_no_legs
        return all(c.test(frame.value(c.feature, c.args)) for c in conds)

    def _emit(self, m: _Machine, t: float, phase: GesturePhase, progress: float,
              events: list[GestureEvent]) -> None:
        if phase == "started" and not self.options.emit_started:
            return
        if phase == "canceled" and not self.options.emit_canceled:
            return
        clock = self.options.clock
        events.append(
            GestureEvent(
                t=float(t),
                emitted_t=float(clock()) if clock is not None else float(t),
                gesture=m.gesture.name,
                phase=phase,
                progress=float(progress),
                started_t=float(m.started_t),
                player=self.options.player,
            )
        )

    def _end(self, m: _Machine, t: float, phase: GesturePhase, events: list[GestureEvent]) -> None:
        self._emit(m, t, phase, 1.0 if phase == "performed" else m.progress(t), events)
        m.stage = -1
        m.holding_since = None
        m.armed = False
        if phase == "performed":
            m.cooldown_until = t + m.gesture.cooldown

    def _cancel(self, m: _Machine, t: float, frame: FeatureFrame,
                events: list[GestureEvent]) -> None:
        """End ``m`` as canceled; armed again at once if stage 1 does not hold on this
        frame: it has then stopped holding once, so it may start on the next frame
        that it holds (a one-frame break of a held pose no longer locks the gesture
        out while the pose goes on)."""
        self._end(m, t, "canceled", events)
        m.armed = not self._holds(m, 0, frame)

    def _step(self, m: _Machine, t: float, frame: FeatureFrame, events: list[GestureEvent]) -> None:
        g = m.gesture
        if m.held:  # waits for _settle_completed
            return
        if m.stage < 0:
            first = self._holds(m, 0, frame)
            if not first:
                m.armed = True
                return
            if not m.armed or t < m.cooldown_until:
                return
            m.stage, m.holding_since, m.started_t = 0, t, t
            self._emit(m, t, "started", 0.0, events)
        elif g.timeout is not None and t - m.started_t > g.timeout:
            self._cancel(m, t, frame, events)
            return
        # Advance through as many stages as this frame completes.
        while m.stage >= 0:
            st = g.stages[m.stage]
            if m.holding_since is None:  # waiting for this stage to begin
                if self._holds(m, m.stage, frame):
                    m.holding_since = t
                elif t - m.last_done_t > st.within:
                    self._cancel(m, t, frame, events)
                    return
                else:
                    return
            elif not self._holds(m, m.stage, frame):
                self._cancel(m, t, frame, events)
                return
            if t - m.holding_since < st.hold:
                return
            m.last_done_t = t
            m.holding_since = None
            m.stage += 1
            if m.held:  # performed (or canceled) by _settle_completed
                return

