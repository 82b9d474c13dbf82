"""Specifications of the body's width measured from the silhouette (bodywidth)."""

from __future__ import annotations

import numpy as np
import pytest

from bodyplay.body.mesh import body_mesh
from bodyplay.body.shapes import body_shape
from bodyplay.body.skeleton import Skeleton
from bodyplay.errors import ConfigError
from bodyplay.render.idmap import project_vertices, rasterize_ids
from bodyplay.trackers.silhouette.bodywidth import WidthFit, girth_factors, widened
from bodyplay.trackers.silhouette.distance import distance_maps
from bodyplay.trackers.silhouette.options import SilhouetteOptions
from bodyplay.trackers.silhouette.window import WindowGeometry


def _pose(body: str) -> np.ndarray:
    """Preset ``body`` standing at the canonical floor point, arms a little out."""
    sk = Skeleton.from_shape(body)
    q = sk.rest_pose().copy()
    q[1] = sk.pelvis_height
    q[3 + 3 * sk.node_index("l_shoulder") + 2] = -1.1
    q[3 + 3 * sk.node_index("r_shoulder") + 2] = 1.1
    return sk.clamp(q[None])[0]


def _seen(body: str, factor: float) -> tuple[np.ndarray, object]:
    """The window (level 2) silhouette of ``body`` at girth ``factor`` in :func:`_pose`,
    and the window's view."""
    view = WindowGeometry().template_view(2)
    sk = Skeleton.from_shape(widened(body_shape(body), factor))
    mesh = body_mesh(sk)
    ids = rasterize_ids(project_vertices(mesh.pose(sk, _pose(body)[None])[0], view), mesh.faces,
                        None, view.width, view.height)
    return (ids > 0).astype(np.uint8), view


@pytest.mark.parametrize("factor", [1.0, 1.2])
def test_width_fit_reads_the_girth_of_the_body_the_silhouette_shows(factor: float) -> None:
    seen, view = _seen("m", factor)
    assert 0 < seen.mean() < 0.5  # the whole body in the window
    fit = WidthFit(frames=3, width_max=1.4)
    cost = distance_maps(seen, beta=5.0).cost
    fit.add("m", _pose("m"), view, cost)  # type: ignore[arg-type]
    assert fit.readings == [pytest.approx(factor)]
    assert fit.factor == pytest.approx(factor)
    assert fit.shape("m").girth == pytest.approx(body_shape("m").girth * factor)


def test_width_fit_keeps_the_median_of_its_first_frames_and_then_stops_reading() -> None:
    thin, view = _seen("m", 1.0)
    wide, _ = _seen("m", 1.3)
    fit = WidthFit(frames=3, width_max=1.4)
    for seen in (wide, thin, wide):
        fit.add("m", _pose("m"), view, distance_maps(seen, beta=5.0).cost)  # type: ignore[arg-type]
    assert fit.done and fit.factor == pytest.approx(1.3)
    fit.add("m", _pose("m"), view, distance_maps(thin, beta=5.0).cost)  # type: ignore[arg-type]
    assert len(fit.readings) == 3 and fit.factor == pytest.approx(1.3)


def test_width_fit_reads_no_wider_than_width_max() -> None:
    seen, view = _seen("m", 1.4)
    fit = WidthFit(frames=1, width_max=1.2)
    fit.add("m", _pose("m"), view, distance_maps(seen, beta=5.0).cost)  # type: ignore[arg-type]
    assert fit.factor == pytest.approx(1.2)


def test_a_widened_body_keeps_its_joints_and_thickens_its_mesh() -> None:
    base = body_shape("l")
    wide = widened(base, 1.3)
    assert wide.height == base.height and wide.breadth == base.breadth
    q = _pose("l")
    a, b = Skeleton.from_shape(base), Skeleton.from_shape(wide)
    assert np.array_equal(a.joint_positions(q), b.joint_positions(q))
    xa = np.ptp(body_mesh(a).pose(a, q[None])[0][:, 2])  # front-to-back depth of the body
    xb = np.ptp(body_mesh(b).pose(b, q[None])[0][:, 2])
    assert xb > 1.1 * xa


def test_girth_factors_run_from_thinner_than_the_preset_to_width_max() -> None:
    f = girth_factors(1.4)
    assert f[0] == pytest.approx(0.9) and f[-1] == pytest.approx(1.4)
    assert 1.0 in f and np.allclose(np.diff(f), 0.1)
    assert list(girth_factors(1.0)) == [pytest.approx(0.9), pytest.approx(1.0)]


def test_silhouette_options_reject_a_negative_width_fit_or_a_width_max_under_1() -> None:
    with pytest.raises(ConfigError, match="width_frames"):
        SilhouetteOptions(width_frames=-1)
    with pytest.raises(ConfigError, match="width_max"):
        SilhouetteOptions(width_max=0.95)
    assert SilhouetteOptions(width_frames=0).width_frames == 0


def test_tracker_reports_the_preset_shape_when_the_width_fit_is_off(silhouette_tree) -> None:  # type: ignore[no-untyped-def]
    from bodyplay.capture.camera import Camera
    from bodyplay.trackers.silhouette import create_silhouette_tracker

    cam = Camera.from_fov("cam0", 320, 240, 60.0)
    off = create_silhouette_tracker(SilhouetteOptions(body="m", arm_candidates=0,
                                                      width_frames=0), (cam,),
                                    tree=silhouette_tree)
    assert off._body_shape("m", _pose("m"), None) == body_shape("m")  # type: ignore[arg-type]
