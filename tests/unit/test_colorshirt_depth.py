"""Specifications of one camera's root depth filter: the feet and the body's size."""

from __future__ import annotations

import pytest

from bodyplay.trackers.colorshirt.depth import RootDepthFilter


def _standing(depth: float = 3.0, frames: int = 30, scale: float = 1.0,
              f: RootDepthFilter | None = None) -> RootDepthFilter:
    """A filter that saw the feet at ``depth`` and the shirt of a player ``scale``
    times the reference body's size for ``frames`` frames at 30 fps."""
    f = f or RootDepthFilter()
    for k in range(frames):
        f.begin(0, k / 30, depth)
        f.end(k / 30, depth / scale)
    return f


def test_depth_filter_holds_the_depth_with_a_growing_uncertainty_while_no_cue_reads() -> None:
    f = RootDepthFilter()
    f.begin(0, 0.0, None)
    assert f.posterior(None) is None  # nothing known yet
    f = _standing()
    std0 = f.std()
    f.begin(0, 1.1, None)
    held = f.posterior(None)
    assert held is not None and held[0] == pytest.approx(3.0, abs=0.01)
    f.begin(0, 1.5, None)
    later = f.posterior(None)
    assert later is not None and std0 is not None and later[1] > held[1] > std0
    f.begin(0, 3.0, None)
    assert f.depth() is None  # lapsed after the horizon


def test_depth_filter_barely_moves_for_feet_in_the_air() -> None:
    f = _standing()
    depth = 3.0
    for k, rise in enumerate((0.05, 0.12, 0.2, 0.3, 0.4, 0.5, 0.4, 0.3, 0.2, 0.1, 0.05)):
        f.begin(0, 1.0 + k / 30, 3.0 + rise)  # a hop: the feet read up to 50 cm too far
        post = f.posterior(3.0)
        assert post is not None
        depth = post[0]
        f.end(1.0 + k / 30, 3.0)
        assert depth == pytest.approx(3.0, abs=0.1)  # (the symmetric gate alone: 0.16 m)
    f.begin(0, 1.5, 2.5)  # a reading half a metre too near is no hop: left out
    f.posterior(3.0)
    f.end(1.5, 3.0)
    assert f.t_floor < 1.5


def test_depth_filter_follows_a_player_walking_towards_the_camera() -> None:
    f = _standing(3.5, frames=1)
    speed = 0.8  # m/s
    for k in range(1, 60):
        t = k / 30
        f.begin(0, t, 3.5 - speed * t)
        f.end(t, 3.5 - speed * t)
        assert f.t_floor == t  # every floor reading taken in
    assert f.depth() == pytest.approx(3.5 - speed * 59 / 30, abs=0.03)
    f.begin(0, 2.1, None)  # feet lost: it goes on walking
    post = f.posterior(None)
    assert post is not None and post[0] == pytest.approx(3.5 - speed * 2.1, abs=0.05)


def test_depth_filter_restarts_from_the_feet_when_they_keep_disagreeing() -> None:
    f = _standing()
    for k in range(30, 70):
        f.begin(0, k / 30, 2.2)
    assert f.depth() == pytest.approx(2.2, abs=0.05)


def test_depth_filter_learns_the_players_size_from_the_feet_and_then_holds_with_the_shirt(
) -> None:
    f = _standing(3.0, frames=90, scale=1.08)  # a player 8% larger than the reference
    errors = []
    for k in range(90, 150):  # the feet leave the floor or vanish; the player walks in
        t = k / 30
        depth = 3.0 - 0.5 * (t - 3.0)
        f.begin(0, t, None)
        post = f.posterior(depth / 1.08)
        assert post is not None
        errors.append(abs(post[0] - depth))
        f.end(t, depth / 1.08)
    assert max(errors) < 0.1 and max(errors[-10:]) < 0.03  # lags, then follows


def test_without_the_feet_the_depth_is_the_shirts_with_the_body_sizes_uncertainty() -> None:
    f = RootDepthFilter(scale_std=0.06, shirt_bias=0.0, shirt_bias_std=0.04)
    for k in range(90):  # a player 5% larger than the reference, the feet never seen
        f.begin(0, k / 30, None)
        f.end(k / 30, 3.0 / 1.05)
    depth, std = f.posterior(3.0 / 1.05) or (0.0, 0.0)
    assert depth == pytest.approx(3.0 / 1.05, abs=0.01)  # the reference body's size
    # the missing cue costs what the filter says: the size's and the shirt's own
    # uncertainty of the depth (6% and 4%)
    assert 0.9 * 0.072 * depth < std < 1.1 * 0.072 * depth
    assert abs(depth - 3.0) < 2 * std


def test_depth_filter_leaves_out_a_wrong_fit_of_the_shirt() -> None:
    f = _standing()
    post = f.posterior(1.5)  # a fit half as far as the feet say
    assert post is not None and post[0] == pytest.approx(3.0, abs=0.02)


def test_depth_filter_stops_when_two_cameras_see_the_shirt_and_waits_when_none_does() -> None:
    f = _standing()
    f.begin(None, 1.1, None, cameras_seeing=0)  # lost frame: nothing changes
    assert f.depth() == pytest.approx(3.0, abs=0.01)
    f.begin(0, 1.2, None, cameras_seeing=2)
    assert f.std() is None
    f.begin(1, 1.3, None)
    assert f.posterior(None) is None  # another camera starts afresh
