"""The ninja game on the kit: rules, virtual player, scene and summary.

:class:`NinjaGame` is a :class:`bodyplay.app.Game`: the session recognizes the five
motions (One Euro smoothed joints), each ``performed`` gesture goes to the rules
(:mod:`apps.ninja.game.rules`), the rules advance with the capture time, and the
embedded virtual ninja (:class:`~apps.ninja.game.player.NinjaPlayer`) reacts to
the fight between frames (closed loop). The scene is seen from behind the player:
the avatar mirrors the tracked pose (dark ninja colors once transfigured), the
opponent faces it 4 m away and winds up its attacks, fire rings fly between them,
and the HUD names the gesture seen last and the progress of the ones under way.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from apps.ninja.game.player import NinjaPlayer
from apps.ninja.game.rules import NINJA_GESTURES, NinjaOptions, NinjaRules
from bodyplay.app import Game, GameContext, GameOptions, Scene, camera_inset
from bodyplay.body.joints import JOINT_INDEX
from bodyplay.body.skeleton import Skeleton

__all__ = ["NinjaGame", "check_script", "OPPONENT_Z", "EMPTY_ROOM_SECONDS"]

OPPONENT_Z = 4.0
"""How far in front of the player the opponent stands (metres along +Z)."""

_NINJA = (0.25, 0.2, 0.45)
_OPPONENT = (0.75, 0.2, 0.15)
_HURT = (1.0, 0.95, 0.3)
_FIRE = (1.0, 0.5, 0.1)
_FIRE2 = (0.4, 0.8, 1.0)
_ARMS = {"l_shoulder": (0.0, 0.0, -1.3), "r_shoulder": (0.0, 0.0, 1.3)}
_OPP_POSES = {
    "idle": _ARMS,
    "high": {**_ARMS, "r_shoulder": (0.0, 0.6, -1.9), "l_shoulder": (0.0, -0.6, 1.9)},
    "sweep": {**_ARMS, "r_shoulder": (0.0, 0.0, 0.4), "l_hip": (-0.9, 0.0, 0.0),
              "r_hip": (-0.9, 0.0, 0.0), "l_knee": (1.6, 0.0, 0.0), "r_knee": (1.6, 0.0, 0.0)},
}
_LATE = 0.6  # s after a motion's end by which its gesture must be recognized

EMPTY_ROOM_SECONDS = 1.0
"""With the silhouette tracker, the virtual ninja steps into view after this many
seconds of the empty room (the paper's background model is learned from the empty
room; from the first frame in view the background model keeps the player's copy and
the tracker starts in a crouched pose, docs/ninja.md)."""

NINJA_TURN_STD = 0.1
"""Radians: how tightly the colour shirt, with one camera, holds the trunk's turn at
the database blend's (``ColorShirtOptions.turn_std``)."""


def check_script(script: list[dict[str, Any]], gestures: list[dict[str, Any]],
                 until: float | None) -> dict[str, Any]:
    """Match what a scripted player performed against the gestures the game saw.

    A motion counts as recognized when its gesture was seen between its start and
    0.6 s after the end of its movement; motions that end after ``until`` (the end of
    the fight) are not judged (their gestures are not unexpected either). Returns per
    motion the seen time and the latency (seen - movement end), plus the missed and
    the unexpected gestures.
    """
    seen = [dict(g) for g in gestures]
    used: set[int] = set()
    rows, missed = [], []
    for m in script:
        hit = next((i for i, g in enumerate(seen) if i not in used
                    and g["gesture"] == m["gesture"]
                    and m["start"] <= g["t"] <= m["motion_end"] + _LATE), None)
        if until is not None and m["motion_end"] + _LATE > until:
            if hit is not None:  # performed as the fight ended: fine, but not judged
                used.add(hit)
            continue
        row = {**m, "seen_t": None, "latency": None}
        if hit is None:
            missed.append(m["gesture"])
        else:
            used.add(hit)
            row["seen_t"] = seen[hit]["t"]
            row["latency"] = round(seen[hit]["t"] - m["motion_end"], 4)
        rows.append(row)
    extra = [g for i, g in enumerate(seen) if i not in used]
    return {"motions": rows, "judged": len(rows), "recognized": len(rows) - len(missed),
            "missed": missed, "unexpected": extra}


class NinjaGame(Game):
    """The ninja fight (see the module docstring). ``player`` overrides the virtual
    ninja (a :class:`NinjaPlayer` of another style, or one used by a test's source)."""

    name = "ninja"
    title = "bodyplay ninja"
    gestures = NINJA_GESTURES
    filters = ("one_euro",)

    def __init__(self, rules_options: NinjaOptions | None = None,
                 player: NinjaPlayer | None = None, player_style: str = "fighter") -> None:
        self.rules_options = rules_options
        self.player = player
        self.player_style = player_style
        self.rules = NinjaRules(rules_options)
        self._opp_skeleton = Skeleton()
        self._opp_cache: dict[str, NDArray[np.float64]] = {}
        self._last_gesture: tuple[str, float] | None = None
        self._now = 0.0
        self._joints: NDArray[np.float64] | None = None
        self._ring_from: dict[int, NDArray[np.float64]] = {}

    # ---- the kit's hooks -----------------------------------------------------------------
    def virtual_player(self, options: GameOptions) -> Any:
        """The virtual ninja filmed by the synthetic camera (or its joints for a
        pose-level run): the embedded default input."""
        from bodyplay.body.actor import load_actor
        from bodyplay.virtual import VirtualPlayerSource

        empty = EMPTY_ROOM_SECONDS if options.tracker == "silhouette" else 0.0
        if self.player is None:
            skel = load_actor(shape="m").skeleton
            self.player = NinjaPlayer(skel, style=self.player_style,  # type: ignore[arg-type]
                                      transfigure_at=1.0 + empty)
        return VirtualPlayerSource(self.player, cameras=options.cameras, fps=options.video_fps,
                                   size=(options.width, options.height), seed=options.seed,
                                   seconds=options.seconds or 60.0, empty_room_seconds=empty)

    def tracker_options(self, tracker: str) -> Any:
        """The silhouette tracker's hierarchy also holds the ninja's five motions (as
        the paper's game did). The colour shirt holds the trunk's turn at the
        database blend's with one camera (``turn_std``): the ninja faces the
        camera, and one camera alone turned the torso by 20-40 degrees, which
        made side steps look like steps forwards (docs/ninja.md). Other trackers
        keep their defaults."""
        if tracker == "silhouette":
            from apps.ninja.game.training import silhouette_options

            return silhouette_options()
        if tracker == "colorshirt":
            from bodyplay.trackers.colorshirt import ColorShirtOptions

            return ColorShirtOptions(turn_std=NINJA_TURN_STD)
        return None

    def setup(self, ctx: GameContext) -> None:
        """Fresh rules seeded from the run's generator; gestures feed them."""
        self.rules = NinjaRules(self.rules_options, rng=ctx.rng)
        self._ring_from = {}
        ctx.session.on("gesture")(self._on_gesture)

    def _on_gesture(self, ev: Any) -> None:
        if ev.phase == "performed":
            n = len(self.rules.rings)
            self.rules.on_gesture(ev.gesture, ev.t, ev.started_t)
            self._last_gesture = (ev.gesture, ev.t)
            if len(self.rules.rings) > n and self._joints is not None:
                # The ring leaves from the throwing hand(s) (the paper's ring follows
                # the player's motion): the right wrist, or between both for a double.
                j = self._joints
                hand = j[JOINT_INDEX["r_wrist"]] if ev.gesture == "hit" else 0.5 * (
                    j[JOINT_INDEX["l_wrist"]] + j[JOINT_INDEX["r_wrist"]])
                if np.all(np.isfinite(hand)):
                    self._ring_from[n] = hand.copy()

    def update(self, ctx: GameContext, dt: float) -> None:
        """Advance the fight to the latest capture time; let the virtual ninja react."""
        now = ctx.pose.t if ctx.pose is not None else self._now
        if ctx.pose is not None:
            self._joints = ctx.pose.joints
        self._now = max(self._now, now)
        self.rules.update(self._now)
        if self.player is not None:
            self.player.react(self._now, self.rules)
        if self.rules.over and self.rules.ended_t is not None \
                and self._now > self.rules.ended_t + 2.0:
            ctx.finish()

    def restart(self, ctx: GameContext) -> None:
        """A new fight (waits for the next transfigure)."""
        self.rules = NinjaRules(self.rules_options, rng=ctx.rng)
        self._ring_from = {}

    def summary(self, ctx: GameContext) -> dict[str, Any]:
        """The fight's summary, plus the virtual player's script checked against it."""
        out = self.rules.summary()
        if self.player is not None:
            until = self.rules.ended_t if self.rules.ended_t is not None else self._now
            out["script"] = self.player.script
            out["script_check"] = check_script(self.player.script, self.rules.gestures, until)
        return out

    def headline(self, ctx: GameContext) -> str:
        """One line for the terminal."""
        r = self.rules
        return (f"ninja: {r.summary()['result']}; health {r.player_health:.0f} vs "
                f"{r.opponent_health:.0f}; {len(r.gestures)} gestures, "
                f"{sum(a.outcome == 'dodged' for a in r.attacks)}/{len(r.attacks)} "
                "attacks dodged")

    # ---- drawing --------------------------------------------------------------------------
    def _opp_pose(self, name: str) -> NDArray[np.float64]:
        if name not in self._opp_cache:
            sk = self._opp_skeleton
            q = sk.pose(root=(0.0, sk.pelvis_height, OPPONENT_Z), orientation=(0.0, np.pi, 0.0),
                        rotations=dict(_OPP_POSES[name]))
            self._opp_cache[name] = sk.joint_positions(q)
        return self._opp_cache[name]

    def draw(self, ctx: GameContext, scene: Scene) -> None:
        """The arena from behind the player, the two fighters, rings, HUD."""
        r, now = self.rules, self._now
        scene.look(eye=(1.3, 2.1, -3.4), target=(0.0, 1.0, 2.0), hfov_deg=62)
        scene.sky = (0.12, 0.1, 0.2)
        scene.floor((0.35, 0.3, 0.25), (0.3, 0.26, 0.22), size=16.0, tile=1.0)
        # The opponent: idle, winding up, striking.
        a = r.current_attack
        joints = self._opp_pose("idle")
        if a is not None:
            w = a.progress(now)
            joints = (1 - w) * joints + w * self._opp_pose(a.kind)
        recent = [h for h in r.hits if now - h["t"] < 0.35]
        hurt_opp = any(h["by"] == "player" for h in recent)
        hurt_me = any(h["by"] == "opponent" for h in recent)
        scene.avatar(joints, color=_HURT if hurt_opp else _OPPONENT)
        if a is not None:
            self._draw_attack(scene, a, now)
        # The player (mirrors the tracked pose).
        if ctx.pose is not None:
            col = _HURT if hurt_me else (_NINJA if r.phase != "waiting" else (0.85, 0.75, 0.6))
            scene.avatar(ctx.pose.joints, ctx.pose.state, color=col, last_seen=ctx.last_seen)
        for k, ring in enumerate(r.rings):
            if not ring.landed:
                self._draw_ring(scene, ring.progress(now), ring.double, now,
                                self._ring_from.get(k))
        self._hud(ctx, scene)
        camera_inset(ctx, scene, 150, pos=(scene.width - 160, scene.height - 138))

    def _draw_attack(self, scene: Scene, a: Any, now: float) -> None:
        w = a.progress(now)
        y = 1.55 if a.kind == "high" else 0.12
        if w < 1.0:  # the telegraph: a warning bar growing at the height it will strike
            scene.box((0.0, y, OPPONENT_Z - 0.6), (2.4 * w + 0.05, 0.05, 0.05), (1.0, 0.2, 0.1))
        else:  # the strike: a blade sweeping over the player's place
            z = OPPONENT_Z - 0.6 - (OPPONENT_Z - 0.6) * min(1.0, (now - a.strike_t) / 0.2)
            scene.box((0.0, y, z), (3.0, 0.06, 0.3), (0.9, 0.9, 1.0))

    def _draw_ring(self, scene: Scene, w: float, double: bool, now: float,
                   start: NDArray[np.float64] | None = None) -> None:
        if start is None:
            start = np.array([0.0, 1.3, 0.4])
        end = np.array([0.0, 1.3, OPPONENT_Z - 0.3])
        c = start + w * (end - start)
        rad = 0.32 if double else 0.22
        spin = now * 9.0
        for k in range(14):
            ang = spin + 2 * np.pi * k / 14
            p = c + rad * np.array([np.cos(ang), np.sin(ang), 0.0])
            scene.sphere(p, 0.06 if double else 0.045, _FIRE2 if double else _FIRE)
        scene.shadow((c[0], 0.0, c[2]), rad, 0.3)

    def _hud(self, ctx: GameContext, scene: Scene) -> None:
        r, now = self.rules, self._now
        scene.text(f"NINJA {r.player_health:3.0f}", (12, 28), 0.8, (0.7, 0.7, 1.0))
        scene.text(f"OPPONENT {r.opponent_health:3.0f}", (scene.width - 12, 28), 0.8,
                   (1.0, 0.6, 0.5), anchor="right")
        msg = {
            "waiting": "Transfigure: arms out to the sides, then fold them on your chest",
            "won": "YOU WIN", "lost": "YOU LOSE",
        }.get(r.phase)
        a = r.current_attack
        if r.phase == "fight":
            if a is not None:
                msg = "HIGH ATTACK - crouch!" if a.kind == "high" else "SWEEP - step aside!"
            else:
                cd = r.double_ready_in(now)
                msg = "hit: fire ring   double hit: " + ("ready" if cd == 0 else f"{cd:.1f} s")
        if msg:
            scene.text(msg, (scene.width / 2, 60), 0.7, (1.0, 1.0, 0.6), anchor="center")
        y = scene.height - 16.0
        if self._last_gesture is not None:
            g, t = self._last_gesture
            scene.text(f"seen: {g} ({now - t:.1f} s ago)", (12, y), 0.65)
            y -= 24
        active: dict[str, float] = {}
        for rec in getattr(ctx.session, "gestures", ()):
            active.update(getattr(rec, "active", {}) or {})
        for g, p in sorted(active.items()):
            bar = "#" * int(round(10 * p)) + "-" * (10 - int(round(10 * p)))
            scene.text(f"{g} [{bar}]", (12, y), 0.6, (0.8, 1.0, 0.8))
            y -= 22
