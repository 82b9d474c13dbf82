"""Specifications of the game loop (bodyplay.app.run_game) on scripted pose input."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest

from bodyplay.app import Game, GameContext, Scene, make_game_options, run_game
from bodyplay.body.skeleton import Skeleton
from bodyplay.runtime.sources import ArrayPoseSource

pytestmark = pytest.mark.gl


class _Counter(Game):
    name = "counter"

    def setup(self, ctx: GameContext) -> None:
        self.updates = 0
        self.pauses: list[tuple[float, bool]] = []
        self.values: list[float] = []

    def update(self, ctx: GameContext, dt: float) -> None:
        self.updates += 1
        self.values.append(float(ctx.rng.random()))

    def on_pause(self, ctx: GameContext, paused: bool) -> None:
        self.pauses.append((ctx.t, paused))

    def draw(self, ctx: GameContext, scene: Scene) -> None:
        scene.look((0, 1.3, 4.0), (0, 1.0, 0))
        scene.floor()
        super().draw(ctx, scene)
        scene.text(f"{self.updates}", (10, 30))

    def summary(self, ctx: GameContext) -> dict[str, Any]:
        return {"updates": self.updates, "checksum": round(sum(self.values), 9)}


def _standing(seconds: float, fps: float = 30.0, lost: tuple[float, float] | None = None
              ) -> ArrayPoseSource:
    sk = Skeleton()
    j = sk.joint_positions(sk.rest_pose())
    n = int(seconds * fps)
    arr = np.repeat(j[None], n, 0)
    t = np.arange(n) / fps
    if lost is not None:
        arr[(t >= lost[0]) & (t < lost[1])] = np.nan
    return ArrayPoseSource(arr, fps=fps)


def test_game_steps_at_update_hz_independent_of_the_camera_rate(tmp_path: Path) -> None:
    game = _Counter()
    opts = make_game_options(headless=True, out=tmp_path, update_hz=120, progress=False)
    res = run_game(game, opts, source=_standing(2.0, fps=30.0))
    # 60 frames at 30 fps span 59/30 s of capture time: 236 steps of 1/120 s
    assert game.updates == 236
    assert res.summary["game_steps"] == 236


def test_run_writes_video_and_summary_with_stage_times(tmp_path: Path) -> None:
    opts = make_game_options(headless=True, out=tmp_path, progress=False)
    res = run_game(_Counter(), opts, source=_standing(1.0))
    data = json.loads((tmp_path / "summary.json").read_text())
    assert data["frames"] == 30 and data["tracking_share"] == 1.0
    assert set(data["timing"]["stage_seconds"]) == {"capture", "tracking", "physics", "game",
                                                     "render", "video"}
    assert res.video_path is not None
    cap = cv2.VideoCapture(str(res.video_path))
    n = int(cap.get(cv2.CAP_PROP_FRAME_COUNT))
    ok, img = cap.read()
    cap.release()
    assert ok and n == 30 and img.shape == (480, 640, 3)
    assert img[:, :, 1].mean() > 40  # not a black frame: floor and sky were drawn


def test_same_seed_and_input_give_the_same_summary(tmp_path: Path) -> None:
    a = run_game(_Counter(), make_game_options(headless=True, out=tmp_path / "a", seed=3,
                                               video=False, progress=False),
                 source=_standing(1.0))
    b = run_game(_Counter(), make_game_options(headless=True, out=tmp_path / "b", seed=3,
                                               video=False, progress=False),
                 source=_standing(1.0))
    strip = ("timing", "options", "video")
    assert {k: v for k, v in a.summary.items() if k not in strip} == {
        k: v for k, v in b.summary.items() if k not in strip
    }


def test_lost_tracking_pauses_game_time_until_the_player_returns(tmp_path: Path) -> None:
    game = _Counter()
    opts = make_game_options(headless=True, out=tmp_path, video=False, progress=False)
    res = run_game(game, opts, source=_standing(3.0, lost=(1.0, 2.0)))
    assert [p for _, p in game.pauses] == [True, False]
    assert res.summary["pauses"] == 1
    # about one second of the three was paused (lost after 3 frames, found at once)
    assert 0.8 < res.summary["paused_seconds"] < 1.0
    span = 89 / 30  # first to last frame
    assert res.context.t == pytest.approx(span - res.summary["paused_seconds"], abs=1 / 60)


def test_rendered_frame_shows_the_avatar_in_its_color(tmp_path: Path) -> None:
    from bodyplay.app import SceneRenderer

    sk = Skeleton()
    j = sk.joint_positions(sk.rest_pose())
    s = Scene(320, 240)
    s.look((0, 1.0, 4.0), (0, 1.0, 0))
    s.avatar(j)
    with SceneRenderer(320, 240) as r:
        img = r.render(s)
    orange = (img[:, :, 0] > 150) & (img[:, :, 2] < 100)
    ys, xs = np.nonzero(orange)
    assert orange.sum() > 500
    assert abs(xs.mean() - 160) < 20  # centred: the figure stands at the origin


class _FakeWindow:
    """Stands in for the pygame window: a headless context and scripted key actions."""

    def __init__(self, actions: dict[int, str]) -> None:
        from bodyplay.render.gl import create_context

        self.ctx = create_context(headless=True)
        self.actions = actions
        self.polls = 0
        self.flips = 0

    def poll(self) -> list[str]:
        self.polls += 1
        a = self.actions.get(self.polls)
        return [a] if a else []

    def flip(self) -> None:
        self.flips += 1

    def close(self) -> None:
        self.ctx.release()


def test_pause_key_does_not_resume_a_game_paused_for_a_lost_player(tmp_path: Path) -> None:
    game = _Counter()
    # the player is lost from 1 s (frame 30, paused at 32); p at frame 40 changes nothing
    win = _FakeWindow({40: "pause"})
    opts = make_game_options(headless=False, out=tmp_path, video=False, progress=False,
                             realtime=False)
    res = run_game(game, opts, source=_standing(3.0, lost=(1.0, 2.0)), window=win)
    assert [p for _, p in game.pauses] == [True, False]  # lost, found: nothing else
    assert res.context.pause_reason == ""
    win.close()


def test_window_keys_pause_resume_and_quit(tmp_path: Path) -> None:
    game = _Counter()
    win = _FakeWindow({10: "pause", 20: "pause", 40: "quit"})
    opts = make_game_options(headless=False, out=tmp_path, video=False, progress=False,
                             realtime=False)
    res = run_game(game, opts, source=_standing(3.0), window=win)
    assert [p for _, p in game.pauses] == [True, False]
    assert res.context.frames == 39  # quit before the 40th frame
    assert win.flips == 39  # a window shows every frame
    # ten frames paused: 38 frame gaps of play minus 10 paused = 28 frames of game time
    assert res.context.t == pytest.approx(28 / 30, abs=1 / 60)
    win.close()


class _Flaky(_Counter):
    def update(self, ctx: GameContext, dt: float) -> None:
        super().update(ctx, dt)
        if self.updates % 7 == 0:
            raise RuntimeError("a bug in one step")


def test_a_failing_game_step_is_logged_and_skipped(tmp_path: Path) -> None:
    opts = make_game_options(headless=True, out=tmp_path, video=False, progress=False)
    res = run_game(_Flaky(), opts, source=_standing(1.0))
    assert res.summary["game_errors"] == res.summary["updates"] // 7 > 0


class _Broken(_Counter):
    def update(self, ctx: GameContext, dt: float) -> None:
        raise RuntimeError("always")


def test_a_game_failing_every_step_stops_with_a_game_error(tmp_path: Path) -> None:
    from bodyplay.app import GameError

    opts = make_game_options(headless=True, out=tmp_path, video=False, progress=False)
    with pytest.raises(GameError, match="update failed 30 times"):
        run_game(_Broken(), opts, source=_standing(2.0))
