"""Specifications of plugin discovery through entry points."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import tomllib
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest

from bodyplay.errors import PluginError
from bodyplay.plugins import GROUPS, PluginRegistry
from bodyplay.runtime import ArrayPoseSource, FixedClock, create_session

ROOT = Path(__file__).resolve().parents[2]

PLUGIN_CODE = textwrap.dedent(
    '''
    import numpy as np

    class Shift:
        """A joint filter that lifts every joint by `dy` metres."""

        def __init__(self, dy=0.5):
            self.dy = dy

        def filter(self, t, joints, state=None):
            return np.asarray(joints) + np.array([0.0, self.dy, 0.0])

        def reset(self):
            pass

    class NotAFilter:
        def smooth(self, joints):
            return joints

    def make_broken():
        return 42

    VALUE = 3
    '''
)


def _install_dist_info(root: Path) -> None:
    """A minimal installed distribution: module + .dist-info with entry points."""
    (root / "tinyplug.py").write_text(PLUGIN_CODE)
    info = root / "tinyplug-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: tinyplug\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(
        "[bodyplay.filters]\n"
        "shift = tinyplug:Shift\n"
        "not_a_filter = tinyplug:NotAFilter\n"
        "broken = tinyplug:make_broken\n"
        "value = tinyplug:VALUE\n"
        "missing = tinyplug_nowhere:Thing\n"
    )


@pytest.fixture
def plugin_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    _install_dist_info(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield tmp_path
    sys.modules.pop("tinyplug", None)


def test_installed_plugin_is_found_and_loaded_through_the_registry(plugin_path: Path) -> None:
    reg = PluginRegistry()
    assert "shift" in reg.names("filters")
    flt = reg.create("filters", "shift", dy=1.0)
    out = flt.filter(0.0, np.zeros((17, 3)))
    assert out[0, 1] == 1.0


def test_session_resolves_filter_names_through_its_registry(plugin_path: Path) -> None:
    s = create_session(source=ArrayPoseSource(np.zeros((3, 17, 3))), filters=["shift"],
                       clock=FixedClock(), plugins=PluginRegistry())
    pose = s.step()
    assert pose is not None and pose.joints[5, 1] == pytest.approx(0.5)


def test_missing_plugin_error_lists_available_names(plugin_path: Path) -> None:
    with pytest.raises(PluginError, match=r"no filter named 'nope'.*shift"):
        PluginRegistry().load("filters", "nope")


def test_plugin_that_fails_to_import_names_its_entry_point(plugin_path: Path) -> None:
    with pytest.raises(PluginError, match=r"missing = 'tinyplug_nowhere:Thing'.*failed to load"):
        PluginRegistry().load("filters", "missing")


def test_plugin_class_of_the_wrong_kind_is_rejected_at_load(plugin_path: Path) -> None:
    with pytest.raises(PluginError, match=r"NotAFilter.*lacks filter, reset"):
        PluginRegistry().load("filters", "not_a_filter")


def test_plugin_object_that_is_not_a_factory_is_rejected(plugin_path: Path) -> None:
    with pytest.raises(PluginError, match="value.*not a factory"):
        PluginRegistry().load("filters", "value")


def test_factory_making_the_wrong_kind_of_object_is_rejected_at_create(
    plugin_path: Path,
) -> None:
    with pytest.raises(PluginError, match=r"'broken'.*made int.*lacks filter"):
        PluginRegistry().create("filters", "broken")


def test_unknown_group_is_a_plugin_error() -> None:
    with pytest.raises(PluginError, match="renderers"):
        PluginRegistry().names("renderers")


def test_registries_do_not_share_in_process_registrations() -> None:
    class F:
        def filter(self, t, joints, state=None):  # type: ignore[no-untyped-def]
            return joints

        def reset(self) -> None:
            pass

    a, b = PluginRegistry(entry_points=[]), PluginRegistry(entry_points=[])
    a.register("filters", "mine", F)
    assert a.names("filters") == ("mine",) and b.names("filters") == ()


def test_builtin_entry_points_in_pyproject_resolve_to_objects_of_their_kind() -> None:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    groups = data["project"].get("entry-points", {})
    eps = [
        metadata.EntryPoint(name, value, group)
        for group, table in groups.items()
        if group in GROUPS
        for name, value in table.items()
    ]
    assert any(ep.group == "bodyplay.sources" for ep in eps)
    reg = PluginRegistry(entry_points=eps)
    for ep in eps:
        assert callable(reg.load(ep.group, ep.name))


@pytest.mark.slow
def test_pip_installed_plugin_package_is_loaded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch
                                                ) -> None:
    pytest.importorskip("wheel", reason="building the plugin package needs the wheel package")
    pkg = tmp_path / "src"
    (pkg / "tinyplug").mkdir(parents=True)
    (pkg / "tinyplug" / "__init__.py").write_text(PLUGIN_CODE)
    (pkg / "pyproject.toml").write_text(textwrap.dedent(
        """
        [build-system]
        requires = ["setuptools>=68"]
        build-backend = "setuptools.build_meta"
        [project]
        name = "tinyplug"
        version = "0.1"
        [project.entry-points."bodyplay.filters"]
        shift = "tinyplug:Shift"
        """))
    target = tmp_path / "site"
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation",
         "--no-index", "--target", str(target), str(pkg)],
        check=True,
    )
    monkeypatch.syspath_prepend(str(target))
    try:
        flt = PluginRegistry().create("filters", "shift", dy=2.0)
        assert flt.filter(0.0, np.zeros((17, 3)))[3, 1] == 2.0
    finally:
        sys.modules.pop("tinyplug", None)
