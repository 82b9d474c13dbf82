"""Scripted goalkeeper rounds: pose-level virtual keepers (no camera, no tracker)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
from apps.goalkeeper.game import GoalkeeperGame, GoalkeeperOptions, part_group

from bodyplay.app import GameContext
from bodyplay.runtime.sources import PoseSample

pytestmark = pytest.mark.gl  # the summary's hand plot is drawn, no GL needed; video off


def test_reaching_keeper_saves_most_shots(play_goalkeeper: Any) -> None:
    s = play_goalkeeper(reach=True).summary
    assert s["shots"] == 20
    assert s["saves"] >= 15, s["shot_log"]
    assert s["saves"] + s["goals"] + s["wide"] == 20


def test_still_keeper_saves_few_shots(play_goalkeeper: Any) -> None:
    s = play_goalkeeper(reach=False).summary
    assert s["shots"] == 20
    assert s["saves"] <= 6, s["shot_log"]


def test_difficulty_ramps_over_the_round(play_goalkeeper: Any) -> None:
    log = play_goalkeeper(reach=True).summary["shot_log"]
    first, last = log[:5], log[-5:]
    assert np.mean([e["speed"] for e in last]) > 1.4 * np.mean([e["speed"] for e in first])
    assert np.mean([abs(e["spin"]) for e in last]) > np.mean([abs(e["spin"]) for e in first])


def test_same_seed_and_input_give_the_same_summary(play_goalkeeper: Any) -> None:
    a = play_goalkeeper(reach=True, shots=6, seed=5).summary
    b = play_goalkeeper(reach=True, shots=6, seed=5).summary
    drop = ("timing", "options", "video", "hand_plot")
    assert {k: v for k, v in a.items() if k not in drop} == {
        k: v for k, v in b.items() if k not in drop
    }


class _ContactLog(GoalkeeperGame):
    """The game plus an independent log of every contact event on the session bus."""

    def setup(self, ctx: GameContext) -> None:
        self.events: list[Any] = []
        ctx.session.subscribe("contact", self.events.append)
        super().setup(ctx)


def test_every_save_has_a_contact_event_with_hand_arm_body_or_head(
    play_goalkeeper: Any,
) -> None:
    game = _ContactLog(GoalkeeperOptions(shots=12))
    s = play_goalkeeper(reach=True, game=game).summary
    saves = [e for e in s["shot_log"] if e["outcome"] == "save"]
    assert len(saves) >= 8 and s["saves"] == len(saves)
    begins = {(round(ev.t, 4), ev.part, ev.obj) for ev in game.events if ev.phase == "begin"}
    for e in saves:
        assert (e["t"], e["part"], f"ball{e['shot']}") in begins, e
        assert part_group(e["part"]) in ("hand", "arm", "body", "head")
    assert sum(s["saves_by"].values()) == s["saves"]


class _Blackout:
    """A pose source that reports nobody between ``start`` and ``end`` seconds."""

    def __init__(self, source: Any, start: float, end: float) -> None:
        self.source, self.start, self.end = source, start, end

    def __iter__(self) -> Iterator[PoseSample]:
        for s in self.source:
            if self.start <= s.t < self.end:
                j = np.full_like(s.joints, np.nan)
                yield PoseSample(s.t, s.frame, j, ("lost",) * 17, np.zeros(17))
            else:
                yield s


def test_lost_tracking_mid_round_pauses_instead_of_letting_goals_in(
    play_goalkeeper: Any,
) -> None:
    from bodyplay.virtual import ReachController, VirtualPoseSource

    clean = play_goalkeeper(reach=True, shots=4).summary["shot_log"]
    second = clean[1]  # the player vanishes just after the second kick, for 3 s
    lost = (second["kicked_t"] + 0.1, second["kicked_t"] + 3.1)
    assert second["t"] < lost[0] + 1.0  # unpaused, that ball is decided within the gap
    ctl = ReachController()
    src = _Blackout(VirtualPoseSource(ctl, upper_body_only=True, noise=0.01), *lost)
    s = play_goalkeeper(reach=True, shots=4, source=src, controller=ctl).summary
    assert s["pauses"] == 1
    assert 2.8 < s["paused_seconds"] < 3.0
    resolved = [e["t"] for e in s["shot_log"]]
    assert not any(lost[0] <= t < lost[1] for t in resolved), s["shot_log"]
    assert s["shot_log"][1]["t"] >= lost[1]  # the ball waited for the keeper
    assert s["shots"] == 4  # and the round went on after the player came back


def test_restart_key_starts_the_round_again(tmp_path: Any) -> None:
    from bodyplay.app import make_game_options, run_game
    from bodyplay.render.gl import create_context
    from bodyplay.virtual import ReachController, VirtualPoseSource

    class Window:
        def __init__(self) -> None:
            self.ctx = create_context(headless=True)
            self.polls = 0

        def poll(self) -> list[str]:
            self.polls += 1
            return ["restart"] if self.polls == 150 else []  # after two shots (5 s)

        def flip(self) -> None:
            pass

        def close(self) -> None:
            pass

    ctl = ReachController()
    game = GoalkeeperGame(GoalkeeperOptions(shots=3), controller=ctl)
    opts = make_game_options(headless=False, realtime=False, out=tmp_path, video=False,
                             progress=False)
    win = Window()
    s = run_game(game, opts, source=VirtualPoseSource(ctl, upper_body_only=True),
                 window=win).summary
    win.ctx.release()
    assert s["shots"] == 3 and [e["shot"] for e in s["shot_log"]] == [0, 1, 2]
    assert s["shot_log"][0]["kicked_t"] > 5.0  # the first shot was kicked again
