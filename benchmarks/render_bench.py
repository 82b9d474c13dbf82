"""Renderer speed: numba id maps (batched and single) and moderngl shaded frames.

Run: ``.venv/bin/python benchmarks/render_bench.py`` (``--quick`` for a smoke run).
Prints medians of repeated timings, with the machine and the date; the figures in
docs/benchmarks.md ("## Renderers") come from this script. The mesh is the
~4.6k-triangle primitive stick figure of :mod:`bodyplay.render.scene`.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import time
from collections.abc import Callable

import numba
import numpy as np

from _machine import cpu_model
from bodyplay.capture.camera import Camera, look_at
from bodyplay.render import (
    GLContextError,
    IdMapRenderer,
    IdMapRendererOptions,
    RenderMesh,
    ShadedRenderer,
    ShadedRendererOptions,
    crop_transform,
    project_vertices,
    rasterize_ids,
)
from bodyplay.render.scene import primitive_figure


def _median_rate(fn: Callable[[], object], items: int, repeats: int) -> float:
    """Items per second: ``items`` / median wall time of ``repeats`` calls (after a warm-up)."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return items / statistics.median(times)


def _single_rate(fn: Callable[[int], object], n: int, repeats: int) -> float:
    """Calls per second of ``fn(i)`` for i in 0..n-1, median over ``repeats`` rounds."""
    fn(0)
    rates = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for i in range(n):
            fn(i)
        rates.append(n / (time.perf_counter() - t0))
    return statistics.median(rates)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmarks and print one line per figure."""
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--batch", type=int, default=2000, help="poses per batched call")
    ap.add_argument("--repeats", type=int, default=7, help="timed repeats (median taken)")
    ap.add_argument("--frames", type=int, default=60, help="shaded frames per repeat")
    ap.add_argument("--quick", action="store_true", help="small sizes, for a smoke test")
    args = ap.parse_args(argv)
    if args.quick:
        args.batch, args.repeats, args.frames = 200, 2, 5

    fig = primitive_figure(args.batch, seed=0)
    R, t = look_at([0.3, 1.2, 3.2], [0.0, 0.95, 0.0])
    cam = Camera.from_fov("cam0", 640, 480, 60.0, R, t)
    n_tri = len(fig.faces)
    print("# bodyplay renderer benchmark")
    print(f"date: {datetime.datetime.now().astimezone().isoformat(timespec='seconds')}")
    print(f"machine: {cpu_model()}, {os.cpu_count()} cores, numba {numba.__version__} "
          f"({numba.get_num_threads()} threads), Python {platform.python_version()}")
    if hasattr(os, "getloadavg"):
        print("load average at start: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(f"mesh: {n_tri} triangles, {fig.vertices.shape[1]} vertices; batch {args.batch}; "
          f"median of {args.repeats}")

    uvz_full = project_vertices(fig.vertices, cam)
    crop40 = crop_transform(uvz_full, 40).uvz
    uvz160 = project_vertices(fig.vertices, cam.with_size(160, 120))
    cases = [("40x40 crop", crop40, 40, 40), ("160x120", uvz160, 160, 120)]
    for name, uvz, w, h in cases:
        for cull in (False, True):

            def batched(uvz: np.ndarray = uvz, w: int = w, h: int = h, cull: bool = cull) -> object:
                return rasterize_ids(uvz, fig.faces, fig.face_ids, w, h, cull_backfaces=cull)

            rate = _median_rate(batched, len(uvz), args.repeats)
            print(f"id maps {name:11s} batched  cull={cull!s:5s}: {rate:9.0f} maps/s")
        n_single = min(len(uvz), 300)

        def single(i: int, uvz: np.ndarray = uvz, w: int = w, h: int = h) -> object:
            return rasterize_ids(uvz[i], fig.faces, fig.face_ids, w, h)

        rate = _single_rate(single, n_single, args.repeats)
        print(f"id maps {name:11s} single rasterize_ids:  {rate:9.0f} maps/s")
        r = IdMapRenderer(IdMapRendererOptions(w, h), fig.faces, fig.face_ids)

        def single_renderer(i: int, uvz: np.ndarray = uvz, r: IdMapRenderer = r) -> object:
            return r.render_uvz(uvz[i])

        rate = _single_rate(single_renderer, n_single, args.repeats)
        print(f"id maps {name:11s} single IdMapRenderer:  {rate:9.0f} maps/s")

    bg = (np.random.default_rng(0).random((480, 640, 3)) * 255).astype(np.uint8)
    n_frames = min(args.frames, args.batch)
    try:
        for samples in (0, 4):
            with ShadedRenderer(ShadedRendererOptions(640, 480, samples=samples)) as sr:
                def frame(i: int, sr: ShadedRenderer = sr) -> object:
                    mesh = RenderMesh(fig.vertices[i % n_frames], fig.faces, fig.colors)
                    return sr.render(mesh, cam, background=bg)

                rate = _single_rate(frame, n_frames, args.repeats)
                renderer = sr.ctx.info["GL_RENDERER"]
            print(f"shaded 640x480 msaa={samples}: {rate:7.1f} frames/s ({renderer})")
        with ShadedRenderer(ShadedRendererOptions(640, 480)) as sr:

            def gl_ids(i: int, sr: ShadedRenderer = sr) -> object:
                return sr.render_ids(fig.vertices[i % n_frames], fig.faces, fig.face_ids, cam)

            rate = _single_rate(gl_ids, n_frames, args.repeats)
        print(f"GL render_ids 640x480: {rate:7.1f} maps/s")
    except GLContextError as exc:
        print(f"shaded: skipped, {exc}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
