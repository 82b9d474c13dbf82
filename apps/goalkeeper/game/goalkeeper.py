"""The goalkeeper game: :class:`GoalkeeperGame`, the rules and view put on the kit."""

from __future__ import annotations

from typing import Any

from apps.goalkeeper.game.rules import GoalkeeperLogic, GoalkeeperOptions, Rules
from apps.goalkeeper.game.view import draw_ball, draw_hud, draw_pitch
from bodyplay.app import Game, GameContext, GameOptions, Scene, camera_inset
from bodyplay.physics import PhysicsOptions

__all__ = ["GoalkeeperGame"]


class GoalkeeperGame(Game):
    """Balls are kicked at the player; block them with hands, arms, body or head.

    ``options``: the round (:class:`GoalkeeperOptions`); ``controller``: a virtual
    keeper to steer (anything with ``set_target(t_arrival, point, now=)``, e.g.
    :class:`bodyplay.virtual.ReachController`), made by :meth:`virtual_player` for
    ``--input virtual``; ``virtual_poses``: the virtual keeper as poses, no camera.
    """

    name = "goalkeeper"
    title = "bodyplay goalkeeper"
    physics_options = PhysicsOptions()

    def __init__(self, options: GoalkeeperOptions | None = None, *, controller: Any = None,
                 virtual_poses: bool = False) -> None:
        self.round = options or GoalkeeperOptions()
        self.logic = GoalkeeperLogic(self.round, controller)
        self.virtual_poses = virtual_poses

    @property
    def rules(self) -> Rules:
        """The round's state (after setup)."""
        assert self.logic.rules is not None, "the game has not been set up"
        return self.logic.rules

    def virtual_player(self, options: GameOptions) -> Any:
        """The embedded keeper: mocap idle motion reaching for each ball (IK), filmed by
        the synthetic camera (or as poses with ``virtual_poses``)."""
        from bodyplay.virtual import ReachController, VirtualPlayerSource, VirtualPoseSource

        controller = ReachController()
        self.logic.controller = controller
        if self.virtual_poses:
            return VirtualPoseSource(controller, seed=options.seed, upper_body_only=True)
        return VirtualPlayerSource(controller, cameras=options.cameras, seed=options.seed,
                                   size=(640, 480))

    def expected_seconds(self, options: GameOptions) -> float | None:
        """How long the round planned from the seed lasts (for the progress bar)."""
        return self.round.round_seconds(Rules.new(self.round, options.seed).shots)

    def setup(self, ctx: GameContext) -> None:
        """Plan the round from the seed, listen to contacts, record the hands."""
        self.logic.rules = Rules.new(self.round, ctx.options.seed)
        ctx.session.subscribe("contact", self.logic.on_contact)
        ctx.session.subscribe("pose", self.logic.trace.on_pose)

    def restart(self, ctx: GameContext) -> None:
        """The r key: take the ball off and start the round again (same shots)."""
        b = self.rules.ball
        if b is not None and ctx.physics is not None:
            ctx.physics.remove(b.obj)
        self.logic.rules = Rules.new(self.round, ctx.options.seed)

    def update(self, ctx: GameContext, dt: float) -> None:
        """One fixed step of the round."""
        self.logic.update(ctx, dt)

    def draw(self, ctx: GameContext, scene: Scene) -> None:
        """Pitch, goal, ball, keeper, score and the camera picture."""
        if getattr(self, "_pitch", None) is None:  # static scenery: built once
            self._pitch = Scene(scene.width, scene.height)
            draw_pitch(self._pitch, self.round.goal)
        scene.extend(self._pitch)
        draw_ball(scene, self.rules)
        super().draw(ctx, scene)
        draw_hud(ctx, scene, self.rules)
        camera_inset(ctx, scene)

    def finish(self, ctx: GameContext) -> None:
        """Save the hand speed and acceleration plot next to the video."""
        self.plot = self.logic.save_plot(ctx)

    def summary(self, ctx: GameContext) -> dict[str, Any]:
        """Shots, saves, goals, contacts per part, hand motion statistics, the plot."""
        out = self.logic.summary()
        out["hand_plot"] = getattr(self, "plot", None)
        return out

    def headline(self, ctx: GameContext) -> str:
        """One line for the terminal."""
        r = self.rules
        return (f"saves {r.saves}, goals {r.goals}, wide {r.wide} of {len(r.shots)} shots; "
                f"best streak {r.best_streak}")

    def extra_files(self, ctx: GameContext) -> dict[str, str]:
        """Files besides the video and the summary."""
        return {"plot": self.plot} if getattr(self, "plot", None) else {}
