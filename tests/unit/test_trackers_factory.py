"""Specifications of creating trackers by plugin name."""

from __future__ import annotations

import pytest

from bodyplay.errors import PluginError
from bodyplay.plugins import PluginRegistry
from bodyplay.trackers import create_tracker


def test_the_color_shirt_tracker_is_registered_as_a_plugin() -> None:
    assert "colorshirt" in PluginRegistry().names("trackers")


def test_create_tracker_with_an_unknown_name_lists_the_installed_trackers() -> None:
    with pytest.raises(PluginError, match="colorshirt"):
        create_tracker("kinect", cameras=())
