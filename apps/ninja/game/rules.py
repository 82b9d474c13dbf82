"""The ninja fight's rules: pure, windowless, deterministic for a seed.

The fight follows the game of the single-camera silhouette paper (section 4): the
player *transfigures* into a ninja (arms out to the sides, then folded on the chest)
and fights an opponent with body motions. The opponent telegraphs two kinds of
attack, each needing its own dodge:

* ``high``: a blade swung at head height; the player must ``crouch`` under it;
* ``sweep``: a low sweep along the floor; the player must ``step_left`` or
  ``step_right`` out of its way.

A dodge answers an attack when its gesture is *performed* between the telegraph and
``grace`` seconds after the strike. A wrong dodge (a step under a high attack, a
crouch before a sweep) does not help: the player takes the damage, and the attack is
recorded as answered wrongly. ``hit`` throws a fire ring, ``double_hit`` a stronger
double ring that then cools down. Rings fly for ``ring_flight`` seconds and hurt the
opponent when they arrive. The fight is won when the opponent's health reaches 0
and lost when the player's does.

:class:`NinjaRules` consumes gestures (``on_gesture(name, t)``) and time
(``update(t)``); it never reads a clock, draws or imports a window. Its state is
what the scene draws; :meth:`NinjaRules.summary` is what ``summary.json`` holds.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any, Literal

import numpy as np

from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = [
    "ATTACK_KINDS",
    "DODGES",
    "NINJA_GESTURES",
    "Attack",
    "FireRing",
    "NinjaOptions",
    "NinjaRules",
    "ninja_options",
]

NINJA_GESTURES = ("transfigure", "crouch", "step_left", "step_right", "hit", "double_hit")
"""The paper's five motions (a side step either way) as built-in gesture names."""

AttackKind = Literal["high", "sweep"]
ATTACK_KINDS: tuple[AttackKind, ...] = ("high", "sweep")
DODGES: dict[str, tuple[str, ...]] = {"high": ("crouch",), "sweep": ("step_left", "step_right")}
"""Which gestures dodge each kind of attack."""

Phase = Literal["waiting", "fight", "won", "lost"]


@dataclass(frozen=True)
class NinjaOptions:
    """Tunable rules; build with :func:`ninja_options`, which validates.

    Health is in points. ``telegraph`` is the time from the opponent's wind-up to the
    strike; the first attack comes ``first_attack`` s after the transfiguration, later
    ones ``attack_gap`` (min, max) s after the previous strike, chosen by the seed.
    ``grace`` s after the strike still count for a dodge (the gesture is recognized
    a little after the body moved). ``ring_damage`` / ``double_damage`` are what a
    ring / a double ring takes from the opponent, ``double_cooldown`` s must pass
    between double hits, ``attack_damage`` is what an undodged attack takes from the
    player. ``time_limit`` s after the transfiguration the fight ends as lost.
    """

    player_health: float = 100.0
    opponent_health: float = 200.0
    attack_damage: float = 34.0
    ring_damage: float = 20.0
    double_damage: float = 40.0
    double_cooldown: float = 4.0
    ring_flight: float = 0.6
    telegraph: float = 1.6
    grace: float = 0.3
    first_attack: float = 1.0
    attack_gap: tuple[float, float] = (2.0, 3.0)
    time_limit: float = 90.0

    def __post_init__(self) -> None:
        check_option_types(self)


def ninja_options(**kwargs: Any) -> NinjaOptions:
    """Validated :class:`NinjaOptions`; a bad value raises ConfigError naming it."""
    try:
        o = NinjaOptions(**kwargs)
    except TypeError as e:
        raise ConfigError(f"ninja options: {e}") from None
    for name in ("player_health", "opponent_health", "attack_damage", "ring_damage",
                 "double_damage", "ring_flight", "telegraph", "time_limit"):
        v = float(getattr(o, name))
        if not (np.isfinite(v) and v > 0):
            raise ConfigError(f"ninja options: {name} must be a positive number, got {v}")
    for name in ("double_cooldown", "grace", "first_attack"):
        v = float(getattr(o, name))
        if not (np.isfinite(v) and v >= 0):
            raise ConfigError(f"ninja options: {name} must be >= 0 seconds, got {v}")
    lo, hi = (float(x) for x in o.attack_gap)
    if not (0 < lo <= hi):
        raise ConfigError(f"ninja options: attack_gap must be (min, max) with 0 < min <= max, "
                          f"got {o.attack_gap}")
    return o


@dataclass
class Attack:
    """One opponent attack: when it was telegraphed, when it strikes, how it ended.

    ``answer`` is the dodge gesture the player performed in time (None: none);
    ``outcome`` is ``pending``, ``dodged``, ``wrong_dodge`` or ``hit``.
    """

    kind: AttackKind
    telegraph_t: float
    strike_t: float
    answer: str | None = None
    answer_t: float | None = None
    outcome: str = "pending"
    wrong: list[str] = field(default_factory=list)

    def progress(self, t: float) -> float:
        """0 at the telegraph, 1 at the strike (for drawing the wind-up)."""
        span = self.strike_t - self.telegraph_t
        return float(np.clip((t - self.telegraph_t) / span, 0.0, 1.0)) if span > 0 else 1.0


@dataclass
class FireRing:
    """A fire ring in flight from the player to the opponent (``double``: the strong one)."""

    thrown_t: float
    arrive_t: float
    double: bool
    damage: float
    landed: bool = False

    def progress(self, t: float) -> float:
        """0 when thrown, 1 when it reaches the opponent."""
        span = self.arrive_t - self.thrown_t
        return float(np.clip((t - self.thrown_t) / span, 0.0, 1.0)) if span > 0 else 1.0


class NinjaRules:
    """The fight's state machine (see the module docstring).

    ``seed`` (or a numpy Generator ``rng``) chooses the attacks and their timing, so
    the same seed and the same gestures at the same times give the same fight.
    """

    def __init__(self, options: NinjaOptions | None = None, *, seed: int = 0,
                 rng: np.random.Generator | None = None) -> None:
        self.options = options or NinjaOptions()
        self.rng = rng if rng is not None else np.random.default_rng(seed)
        self.phase: Phase = "waiting"
        self.t = 0.0
        self.player_health = float(self.options.player_health)
        self.opponent_health = float(self.options.opponent_health)
        self.started_t: float | None = None
        self.ended_t: float | None = None
        self.gestures: list[dict[str, Any]] = []
        self.attacks: list[Attack] = []
        self.rings: list[FireRing] = []
        self.hits: list[dict[str, Any]] = []
        self.rejected: list[dict[str, Any]] = []
        self._next_attack_t: float | None = None
        self._double_ready_t = 0.0

    # ---- queries ---------------------------------------------------------------------
    @property
    def current_attack(self) -> Attack | None:
        """The attack being telegraphed now (None between attacks)."""
        if self.attacks and self.attacks[-1].outcome == "pending":
            return self.attacks[-1]
        return None

    @property
    def over(self) -> bool:
        """Whether the fight has ended (won or lost)."""
        return self.phase in ("won", "lost")

    def double_ready_in(self, t: float | None = None) -> float:
        """Seconds until ``double_hit`` may be used again (0: ready)."""
        return max(0.0, self._double_ready_t - (self.t if t is None else t))

    # ---- input -----------------------------------------------------------------------
    def on_gesture(self, gesture: str, t: float, started_t: float | None = None) -> None:
        """A gesture was performed at ``t``; apply what it does in the current phase."""
        if not np.isfinite(t):
            raise ConfigError(f"gesture time must be finite, got {t}")
        self.update(t)
        self.gestures.append({"gesture": gesture, "t": round(float(t), 4),
                              "started_t": None if started_t is None
                              else round(float(started_t), 4), "phase": self.phase})
        if self.phase == "waiting":
            if gesture == "transfigure":
                self.phase = "fight"
                self.started_t = float(t)
                self._next_attack_t = float(t) + self.options.first_attack
            return
        if self.phase != "fight":
            return
        attack = self.current_attack
        if gesture in DODGES["high"] + DODGES["sweep"]:
            if attack is None:
                return
            if gesture in DODGES[attack.kind]:
                if attack.answer is None:
                    attack.answer, attack.answer_t = gesture, float(t)
            else:
                attack.wrong.append(gesture)
        elif gesture == "hit":
            self._throw(float(t), double=False)
        elif gesture == "double_hit":
            if t < self._double_ready_t:
                self.rejected.append({"gesture": gesture, "t": round(float(t), 4),
                                      "why": f"cooling down ({self._double_ready_t - t:.1f} s)"})
                return
            self._double_ready_t = float(t) + self.options.double_cooldown
            self._throw(float(t), double=True)

    def _throw(self, t: float, double: bool) -> None:
        o = self.options
        self.rings.append(FireRing(t, t + o.ring_flight, double,
                                   o.double_damage if double else o.ring_damage))

    # ---- time ------------------------------------------------------------------------
    def update(self, t: float) -> None:
        """Advance the fight to time ``t`` (seconds; earlier times are ignored)."""
        if not np.isfinite(t):
            raise ConfigError(f"time must be finite, got {t}")
        if t <= self.t:
            return
        # Events between the last update and t, in time order.
        while self.phase == "fight":
            nxt = self._next_due(t)
            if nxt is None:
                break
            self._apply_due(nxt)
        self.t = float(t)

    def _next_due(self, t: float) -> float | None:
        cands = [r.arrive_t for r in self.rings if not r.landed]
        a = self.current_attack
        if a is not None:
            cands.append(a.strike_t + self.options.grace)
        elif self._next_attack_t is not None:
            cands.append(self._next_attack_t)
        if self.started_t is not None:
            cands.append(self.started_t + self.options.time_limit)
        due = [c for c in cands if c <= t]
        return min(due) if due else None

    def _apply_due(self, when: float) -> None:
        o = self.options
        for r in self.rings:
            if not r.landed and r.arrive_t <= when:
                r.landed = True
                self.opponent_health = max(0.0, self.opponent_health - r.damage)
                self.hits.append({"by": "player", "kind": "double_ring" if r.double else "ring",
                                  "thrown_t": round(r.thrown_t, 4), "t": round(r.arrive_t, 4),
                                  "damage": r.damage})
                if self.opponent_health <= 0:
                    self._end("won", r.arrive_t)
                    return
        a = self.current_attack
        if a is not None and a.strike_t + o.grace <= when:
            if a.answer is not None:
                a.outcome = "dodged"
            else:
                a.outcome = "wrong_dodge" if a.wrong else "hit"
                self.player_health = max(0.0, self.player_health - o.attack_damage)
                self.hits.append({"by": "opponent", "kind": a.kind, "t": round(a.strike_t, 4),
                                  "damage": o.attack_damage})
                if self.player_health <= 0:
                    self._end("lost", a.strike_t + o.grace)
                    return
            lo, hi = o.attack_gap
            self._next_attack_t = a.strike_t + float(self.rng.uniform(lo, hi))
        elif a is None and self._next_attack_t is not None and self._next_attack_t <= when:
            kind: AttackKind = ATTACK_KINDS[int(self.rng.integers(len(ATTACK_KINDS)))]
            t0 = self._next_attack_t
            self.attacks.append(Attack(kind, t0, t0 + o.telegraph))
            self._next_attack_t = None
        if self.started_t is not None and self.started_t + o.time_limit <= when:
            self._end("lost", self.started_t + o.time_limit)

    def _end(self, result: Phase, t: float) -> None:
        self.phase = result
        self.ended_t = float(t)

    # ---- report ----------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """JSON-ready account of the fight: result, gestures, attacks, hits, health."""
        result = self.phase if self.over else ("unfinished" if self.phase == "fight"
                                               else "not_started")
        return {
            "result": result,
            "started_t": None if self.started_t is None else round(self.started_t, 4),
            "ended_t": None if self.ended_t is None else round(self.ended_t, 4),
            "health": {"player": self.player_health, "opponent": self.opponent_health},
            "gestures": list(self.gestures),
            "attacks": [{**asdict(a), "telegraph_t": round(a.telegraph_t, 4),
                         "strike_t": round(a.strike_t, 4)} for a in self.attacks],
            "hits": list(self.hits),
            "rejected": list(self.rejected),
            "options": {k: list(v) if isinstance(v, tuple) else v
                        for k, v in asdict(self.options).items()},
        }
