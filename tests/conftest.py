"""Shared fixtures: paths to the shared data, a skeleton, temporary output folders."""

from __future__ import annotations

import importlib.util
import os
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import pytest
from hypothesis import settings

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = REPO.parent / "shared" / "data"

# The default run draws the same damaged inputs every time, so that a CI run passes or
# fails on the code, not on the draw; BODYPLAY_HYPOTHESIS=explore draws new ones.
settings.register_profile("repeatable", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("BODYPLAY_HYPOTHESIS", "repeatable"))


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """../shared/data, or skip the test cleanly when it is absent."""
    if not SHARED_DATA.is_dir():
        pytest.skip(f"shared data not found at {SHARED_DATA}")
    return SHARED_DATA


@pytest.fixture(scope="session")
def skeleton():  # type: ignore[no-untyped-def]
    """The reference 1.75 m skeleton."""
    from bodyplay.body import Skeleton

    return Skeleton()


@pytest.fixture(scope="session")
def patch_pixels():  # type: ignore[no-untyped-def]
    """``patch_pixels(mesh, skeleton, pose, eye)``: (21,) pixel count of each patch id
    (0 = everything else) in a 320x320 id map seen from ``eye`` looking at the chest."""
    import numpy as np

    from bodyplay.capture.camera import Camera, look_at
    from bodyplay.render.idmap import render_idmaps

    def count(mesh, skeleton, pose, eye):  # type: ignore[no-untyped-def]
        verts = mesh.pose(skeleton, np.asarray(pose)[None])
        chest = skeleton.joint_positions(pose)[2]
        R, t = look_at(np.asarray(eye, dtype=float), chest)
        cam = Camera.from_fov("test", 320, 320, 55.0, R, t)
        ids = render_idmaps(verts, mesh.faces, mesh.face_part, cam)[0]
        return np.bincount(ids.ravel(), minlength=21)

    return count


@pytest.fixture(scope="session")
def synth_gl():  # type: ignore[no-untyped-def]
    """Skip cleanly when no headless EGL context can be created (synthetic camera tests)."""
    from bodyplay.render.gl import GLContextError, create_context

    try:
        ctx = create_context(headless=True)
    except GLContextError as exc:
        pytest.skip(f"no EGL OpenGL context: {exc}")
    ctx.release()
    return True


@pytest.fixture(scope="session")
def check_patches_and_views(patch_pixels):  # type: ignore[no-untyped-def]
    """``check(mesh, skeleton)``: assert every shirt patch of ``mesh`` has a plausible
    area and that a camera in front sees the front patches but not their same-colored
    twins on the back (and the reverse from behind). Shared by the generic-mesh and
    actor tests, which must both wear a usable shirt."""
    import numpy as np

    from bodyplay.body.shirt import PATCHES

    front_ids = list(range(1, 11))
    back_ids = list(range(11, 21))
    colors = {p.id: p.color for p in PATCHES}

    def check(mesh, skeleton) -> None:  # type: ignore[no-untyped-def]
        v = mesh.rest_vertices.astype(np.float64)[mesh.faces]
        tri = 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
        area = np.bincount(mesh.face_part, weights=tri, minlength=21)
        assert np.all(area[1:] > 0.004), area  # every patch, at least 40 cm^2
        assert np.all(area[1:] < 0.12), area
        rest = skeleton.rest_pose()
        for eye, seen, hidden in (([0, 1.5, 3.0], front_ids, back_ids),
                                  ([0, 1.5, -3.0], back_ids, front_ids)):
            px = patch_pixels(mesh, skeleton, rest, eye)
            for pid in seen:
                twin = next(q for q in hidden if colors[q] == colors[pid])
                assert px[pid] > 40, (eye, pid, px)
                assert px[twin] < 0.1 * px[pid], (eye, pid, twin, px)

    return check


@pytest.fixture(scope="session")
def silhouette_tree(tmp_path_factory):  # type: ignore[no-untyped-def]
    """A tiny silhouette shape hierarchy (one short CMU clip, one body), built once
    into a temporary cache."""
    from bodyplay.trackers.silhouette import HierarchyOptions, load_or_build_tree

    opts = HierarchyOptions(clips=("131_01",), yaw_offsets_deg=(0.0,), random_share=0.05,
                            bodies=("m",), thresholds=(0.06, 0.04, 0.03), max_poses=400)
    return load_or_build_tree(opts, tmp_path_factory.mktemp("silhouette_cache"))


def load_script(relative: str, with_neighbours: bool = False) -> ModuleType:
    """Import a script of the repository (``benchmarks/x.py``, ``tools/x.py``) that is
    not in a package, under its file name, so that its functions can be specified;
    ``with_neighbours`` lets it import the scripts beside it while it loads."""
    path = REPO / relative
    folder = str(path.parent)
    if with_neighbours:
        sys.path.insert(0, folder)
    try:
        spec = importlib.util.spec_from_file_location(path.stem, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module
        spec.loader.exec_module(module)
    finally:
        if with_neighbours:
            sys.path.remove(folder)
    return module


@pytest.fixture(scope="session")
def script_loader() -> Callable[..., ModuleType]:
    """:func:`load_script`, for tests of the scripts in benchmarks/ and tools/."""
    return load_script

