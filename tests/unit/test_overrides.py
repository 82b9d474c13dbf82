"""Specifications of ``NAME=VALUE`` option overrides (``bodyplay track --set``), one
parser for every tracker's options and their nested options."""

from __future__ import annotations

import pytest

from bodyplay.errors import ConfigError
from bodyplay.overrides import options_with_overrides
from bodyplay.trackers.colorshirt import ColorShirtOptions
from bodyplay.trackers.silhouette import SilhouetteOptions


def test_overrides_reach_the_nested_options_of_the_silhouette_tracker() -> None:
    opts = options_with_overrides(SilhouetteOptions(), [
        "max_distance=12", "background.learn_after=8", "background.resolve_outside=none",
        "background.hold_below=false", "hierarchy.yaw_offsets_deg=-20,0,20",
        "hierarchy.bodies=s,m",
    ])
    assert opts.max_distance == 12.0
    assert opts.background.learn_after == 8 and opts.background.resolve_outside is None
    assert opts.background.hold_below is False
    assert opts.hierarchy.yaw_offsets_deg == (-20.0, 0.0, 20.0)
    assert opts.hierarchy.bodies == ("s", "m")


def test_overrides_read_tuples_as_their_element_type() -> None:
    opts = options_with_overrides(SilhouetteOptions(), ["shift_search=2,1"])
    assert opts.shift_search == (2, 1) and all(isinstance(v, int) for v in opts.shift_search)
    cs = options_with_overrides(ColorShirtOptions(), ["locate.scales=[0.2, 0.3]"])
    assert cs.locate.scales == (0.2, 0.3)


def test_overrides_without_items_return_the_options_unchanged() -> None:
    base = SilhouetteOptions()
    assert options_with_overrides(base, []) is base


@pytest.mark.parametrize(("item", "message"), [
    ("max_distanse=12", "unknown silhouette option 'max_distanse'.*max_distance.*background.NAME"),
    ("background.learn_aftr=3", "unknown background option 'learn_aftr'.*learn_after"),
    ("hierarchy=3", "unknown silhouette option 'hierarchy'"),
    ("background.learn_after=soon", "learn_after: cannot read 'soon'; expected a number"),
    ("background.hold_below=maybe", "hold_below: cannot read 'maybe'; expected true or false"),
    ("shift_search=1,x", "shift_search: cannot read"),
    ("max_distance", "NAME=VALUE"),
])
def test_overrides_name_what_was_wrong_and_the_valid_choices(item: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        options_with_overrides(SilhouetteOptions(), [item])


def test_overrides_still_run_the_options_own_validation() -> None:
    with pytest.raises(ConfigError, match="learn_after"):
        options_with_overrides(SilhouetteOptions(), ["background.learn_after=0"])
