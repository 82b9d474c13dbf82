"""The color-shirt tracker: the paper's per-frame pipeline behind the Tracker protocol.

Each camera's image steps are :mod:`.camerawork`'s; here the cameras' views become
one pose (blend, placement, 6-DOF fit, reclassification, IK), with the start, the
body choice and the gates. A frame no camera sees a shirt in is :func:`lost_result`.
"""

from __future__ import annotations

import copy
import time
from typing import cast

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.joints import UPPER_BODY
from bodyplay.body.rotations import rotvec_to_matrix
from bodyplay.body.skeleton import NODE_NAMES, Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import TimestampError
from bodyplay.trackers.base import TrackerCapabilities, TrackResult, check_frame_set, lost_result
from bodyplay.trackers.colorshirt.anchors import Observed, patch_anchors
from bodyplay.trackers.colorshirt.armsearch import ArmSearches
from bodyplay.trackers.colorshirt.bodyselect import (
    BodyFit,
    BodyModel,
    BodySelection,
    arm_variants,
    reprojection_residual,
)
from bodyplay.trackers.colorshirt.camerawork import CameraWork
from bodyplay.trackers.colorshirt.colors import ColorModel
from bodyplay.trackers.colorshirt.database import PoseDatabase
from bodyplay.trackers.colorshirt.depth import RootDepthFilter
from bodyplay.trackers.colorshirt.floor import FloorReading, floor_reading
from bodyplay.trackers.colorshirt.gates import SpeedGate, plausible
from bodyplay.trackers.colorshirt.head import HeadPoint, head_anchors
from bodyplay.trackers.colorshirt.ik import PatchAnchors, PriorModel, RootPrior
from bodyplay.trackers.colorshirt.options import ColorShirtOptions
from bodyplay.trackers.colorshirt.placement import DatabasePlacement
from bodyplay.trackers.colorshirt.report import pose_result
from bodyplay.trackers.colorshirt.start import MOVED_SHARE, StartChoice, StartFit, choose_start
from bodyplay.trackers.colorshirt.views import CameraView

__all__ = ["ColorShirtTracker", "CameraView"]

_PLACEMENT_STD = 1.0
"""Metres: how loosely a lone camera's first 6-DOF fit is held at the database
placement's root (two cameras: 0.3)."""


def _torso_length(skeleton: Skeleton) -> float:
    """Pelvis to neck (m) of ``skeleton`` standing upright (its bone offsets)."""
    chain = [NODE_NAMES.index(n) for n in ("lumbar", "thorax", "neck")]
    return float(np.linalg.norm(skeleton.offsets[chain].sum(axis=0)))


class ColorShirtTracker:
    """Upper-body tracker for the color shirt (see the module docstring).

    Create it with :func:`bodyplay.trackers.colorshirt.create_colorshirt_tracker`.
    """

    name = "colorshirt"

    def __init__(
        self,
        options: ColorShirtOptions,
        cameras: tuple[Camera, ...],
        database: PoseDatabase,
        color_model: ColorModel,
        prior: PriorModel,
        skeleton: Skeleton,
        bodies: dict[str, BodyModel] | None = None,
    ) -> None:
        self.options = options
        self.cameras = cameras
        self.capabilities = TrackerCapabilities(
            joints=UPPER_BODY, min_cameras=1, max_cameras=4, needs_calibration=True
        )
        self.database = database
        self.color_model = color_model
        self.prior = prior
        self._work = CameraWork(options, cameras, database, color_model)
        self._presets = dict(bodies) if bodies else {}
        """Candidate body presets (``body="auto"``); empty: the fixed ``skeleton``."""
        self._fixed = self._presets.get("m") or BodyModel.build(options.body, cameras, skeleton)
        """The reference body (the database's), reported while the start-up chooses."""
        self._use(self._fixed)
        self.placement = DatabasePlacement(database, cameras)
        self._arms = ArmSearches(database.poses, options.arm_library)
        self.reset()

    # ---- state ---------------------------------------------------------------------
    def reset(self) -> None:
        """Forget the previous pose, learned illuminations and backgrounds."""
        self._cams = self._work.new_states()
        self._prev: NDArray[np.float64] | None = None
        self._ever_reported = False
        self._last_t: float | None = None
        self._gate = SpeedGate(self.options.max_speed, self.options.good_residual)
        self._floor = FloorReading()
        self._depth = self._new_depth()
        self._lone: int | None = None
        """The camera that alone sees the shirt this frame (None: none or several)."""
        self._held: list[CameraView] = []
        """Start regions that fit a shirt but never moved (:meth:`_start_views`)."""
        self._alone: tuple[int, int] | None = None
        """The camera of several that alone tracks the player, and for how many frames."""
        self._unscored: int | None = None
        """One camera: frames since its track started on a region lying in nothing that
        moved (:data:`.start.MOVED_SHARE`; None: it did not, or that was long ago)."""
        self._selection: BodySelection | None = None
        self._arm_stage_started = False
        self._bodies = dict(self._presets)
        self._reference = "m"
        """The preset reported while the start-up frames choose."""
        if self._bodies:
            self._selection = BodySelection(
                tuple(self._bodies), self.options.body_selection_frames)
            self._use(self._bodies.get(self._reference, next(iter(self._bodies.values()))))
        self.diagnostics: dict[str, object] = {}
        """Intermediate results of the last frame (blend, observed centroids, ...)."""

    def _use(self, body: BodyModel) -> None:
        """Make ``body`` the skeleton, mesh and solver of the fits that follow."""
        self.body = body
        self.skeleton = body.skeleton
        self.renderer = body.renderer
        self.solver = body.solver

    def _new_depth(self) -> RootDepthFilter:
        """A one-camera root depth filter that knows nothing yet."""
        o = self.options
        return RootDepthFilter(o.depth_accel, o.floor_std, o.shirt_depth_std, o.body_scale_std)

    @property
    def body_name(self) -> str:
        """Name of the body preset in use (the reference ``m`` while choosing)."""
        return self.body.name

    # ---- the frame -------------------------------------------------------------------
    def process(self, frames: FrameSet) -> TrackResult:
        """Estimate the upper-body pose for one synchronized frame set."""
        t0 = time.perf_counter()
        check_frame_set(frames, self.cameras)
        if self._last_t is not None and not frames.t > self._last_t:
            raise TimestampError(
                f"frame set {frames.index} at t={frames.t} is not after t={self._last_t}; "
                "feed frames in time order (or call reset())"
            )
        self._last_t = frames.t
        for st in self._cams:
            if st.gate is not None and frames.t - st.gate_t > self.options.gate_time:
                st.gate = st.last_box = None  # lost too long: search the whole frame
        confirmed = self._gate.reported is not None
        self._work.prepare(self._cams, [fr.image for fr in frames])
        starting, fresh = self._starting(), False
        # the last pose's forward (its root rotation's z axis) limits the database's turn
        prev = self._prev if self.options.facing_turn < 180 else None
        self._work.facing = None if prev is None else rotvec_to_matrix(prev[3:6])[:, 2]
        if starting:
            views, fresh = self._start_views(frames, confirmed)
            if fresh and self._alone is not None:  # a new hypothesis replaces a lone
                self._forget_track()  # camera's track
        else:
            views = [v for i in range(len(frames))
                     for v in self._work.views(i, self._cams[i], frames.t, confirmed, 1)]
            moved = self._moved_restart(views, frames.t)
            if moved is not None:  # the track lies in still room, the player moved
                views, fresh = moved, True
                self._forget_track()
                self._depth = self._new_depth()
        views = [v for v in views if v.distance <= self.options.max_mismatch]
        self.diagnostics = {}
        root_height = (float(self._prev[1]) if self._prev is not None
                       else self.skeleton.pelvis_height)
        self._floor = floor_reading(self.cameras, self._cams, views, self.options, root_height)
        lone = self._lone = views[0].index if len(views) == 1 else None
        self._depth.begin(lone, frames.t, self._floor.depth, len(views))
        if not views:
            return self._lost(frames, t0, starting)
        fit: BodyFit | None
        self._start_arm_selection()
        if self._selection is not None and self._selection.chosen is None:
            fit = self._select_body(views)
        else:
            fit = self._estimate(views, self._prev)
            if not self._plausible(fit.q, fit.views):
                fit = None
        if fit is not None and self.options.adaptive_white_balance:
            # also a fit the speed gate rejects: how W catches up after a light switch
            for v, r in zip(fit.views, fit.rendered, strict=True):
                self._work.refit_white_balance(self._cams[v.index], v, r)
        if fit is not None and not self._gate.admits(
                frames.t, fit.q[:3], fit.residual,
                confirmed=len(fit.views) > 1 or len(self.cameras) == 1):
            self.diagnostics["rejected"] = "speed"
            fit = None
        self.diagnostics["body"] = self.body_name
        if self._selection is not None:
            self.diagnostics["body_residuals"] = self._selection.means()
        if fit is None:
            return self._lost(frames, t0, starting)
        self._prev = fit.q
        self._gate.report(frames.t, fit.q[:3])
        if (fresh or self._alone is not None or len(fit.views) == 1) and len(self.cameras) > 1:
            alone = 0 if fresh or self._alone is None else self._alone[1] + 1
            self._alone = None if len(fit.views) > 1 else (fit.views[0].index, alone)
        self._work.remember_shirt(self._cams, self.renderer, fit.q, frames.t)
        good = fit.residual <= self.options.good_residual
        if self._unconfirmed():
            # one camera alone in a rig of several: its depth is the shirt's size alone,
            # so it is tracked, not reported, and no plate learns this frame
            self.diagnostics["rejected"] = "unconfirmed"
            self._ever_reported = True
            self._work.learn_room(self._cams, self.renderer, None, True)
            return lost_result(frames.index, frames.t, 1000.0 * (time.perf_counter() - t0))
        self._work.learn_room(self._cams, self.renderer, fit.q if good else None,
                              self._ever_reported)
        self._ever_reported = True
        if lone is not None:
            self._depth.end(frames.t, cast("float | None", self.diagnostics.get("shirt_depth")))
        return self._result(frames, fit.q, fit.seen, fit.views, t0)

    def _forget_track(self) -> None:
        """A start chose afresh: the last pose and every body's previous fit are no prior."""
        self._prev = None
        self._gate.clear()
        if self._selection is not None:
            self._selection.previous.clear()

    def _lost(self, frames: FrameSet, t0: float, starting: bool) -> TrackResult:
        """No pose this frame; the room plates learn what they may without one."""
        self._prev = None
        self._work.learn_room(self._cams, self.renderer, None, self._ever_reported,
                              self._held if starting else None)
        return lost_result(frames.index, frames.t, 1000.0 * (time.perf_counter() - t0))

    # ---- start-up: where the player is ---------------------------------------------
    def _starting(self) -> bool:
        """Whether the next frame starts a track: no camera tracks the shirt, or one
        camera of several alone does (:meth:`_unconfirmed`)."""
        return self.options.start_candidates > 1 and (
            self._unconfirmed() or all(st.last_box is None for st in self._cams))

    def _unconfirmed(self) -> bool:
        """Whether one camera of several alone tracks the player, for fewer than
        ``start_agreement_frames`` frames: tracked, not reported."""
        return self._alone is not None and self._alone[1] < self.options.start_agreement_frames

    def _start_views(self, frames: FrameSet, confirmed: bool
                     ) -> tuple[list[CameraView], bool]:
        """The views a track starts from (:func:`.start.choose_start` over every
        camera's candidate regions; a camera that alone tracks gives its tracked
        view), and whether a hypothesis chose them afresh. Regions that fit a shirt
        but never moved are held (``_held``): the room plates must not learn them."""
        o = self.options
        lone = None if self._alone is None else self._alone[0]
        cands = [self._work.views(i, self._cams[i], frames.t, confirmed,
                                  1 if i == lone else o.start_candidates,
                                  lone is not None or len(self.cameras) == 1)
                 for i in range(len(frames))]
        if len(self.cameras) == 1:  # also the region within what the player moved
            found = self._work.moved_view(0, self._cams[0], frames.t)
            cands[0] += [] if found is None else [found]
        cands = [[v for v in c if v.distance <= o.max_mismatch] for c in cands]
        tracked = [] if lone is None else cands[lone]
        start = self._choose(cands, tracked, lone)
        if len(self.cameras) == 1 and start.views is not None:
            lying = self._work.moved_share(self._cams[0], start.views[0]) >= MOVED_SHARE
            self._unscored = None if lying else 0
        self._held = start.held
        chosen = tracked if start.views is None else start.views
        for i, st in enumerate(self._cams):  # a camera without a chosen region: room
            st.located = any(v.index == i for v in chosen)
        for v in chosen:
            if v.index != lone:
                self._work.commit(self._cams[v.index], v, confirmed)
        return chosen, start.views is not None

    def _choose(self, cands: list[list[CameraView]], tracked: list[CameraView],
                lone: int | None) -> StartChoice:
        """:func:`.start.choose_start` over ``cands`` (per camera), each combination
        fitted without the depth filter (``_lone`` is None while it judges)."""
        o = self.options
        moved = {id(v): self._work.moved(self._cams[v.index], v)
                 for i, c in enumerate(cands) if i != lone for v in c}
        band = (o.start_root_band[0] * self.skeleton.pelvis_height,
                o.start_root_band[1] * self.skeleton.pelvis_height)
        saved, self._lone = self._lone, None  # judged without the depth filter

        def fit(chosen: list[CameraView]) -> StartFit | None:
            f = self._estimate([copy.copy(v) for v in chosen], None)
            if not np.isfinite(f.residual) or not self._plausible(f.q, f.views):
                return None
            return f.q, len(f.seen), f.residual

        start = choose_start(cands, tracked, lone, lambda v: bool(moved[id(v)]), fit, band,
                             o.background_subtraction,
                             lambda v: self._work.seen_empty(self._cams[v.index], v),
                             lambda v: self._work.moved_share(self._cams[v.index], v))
        self._lone, self.diagnostics = saved, {}
        return start

    def _moved_restart(self, views: list[CameraView], t: float) -> list[CameraView] | None:
        """One camera whose track started on a region lying in nothing that moved (a
        first frame, clutter that outranked a still player), for at most
        ``start_agreement_frames`` frames: once the room plate saw a player move and the
        tracked region (``views``: this frame's) lies mostly outside it (still room: a
        shelf instead of the player, or room in the shirt's colours grown onto the
        player), the region found within what moved, committed, if a start accepts it.
        None: the track goes on (once it lies in what moved it is no longer checked)."""
        if self._unscored is None or len(self.cameras) != 1:
            return None
        self._unscored += 1
        if self._unscored > self.options.start_agreement_frames:
            self._unscored = None
            return None
        st, work = self._cams[0], self._work
        if not st.room.saw_a_player_move():
            return None
        if views and work.moved_share(st, views[0]) >= MOVED_SHARE:
            self._unscored = None  # the track lies in what moved: the player's
            return None
        found = work.moved_view(0, st, t)
        if (found is None or found.distance > self.options.max_mismatch
                or work.moved_share(st, found) < MOVED_SHARE):
            return None  # nothing found there
        start = self._choose([[found]], [], None)
        if start.views is None:
            return None
        self._unscored = None
        work.commit(st, found, self._gate.reported is not None)
        return [found]

    # ---- start-up: the body choice ---------------------------------------------------
    def _select_body(self, views: list[CameraView]) -> BodyFit | None:
        """Start-up: fit every candidate preset on its own copies of the views, keep
        the one reprojecting best; until the choice the best so far is reported (the
        reference body before any frame judged). With one camera only frames whose
        feet tell the distance judge, without the arm search (then refitted with it)."""
        sel = self._selection
        assert sel is not None
        fits: dict[str, tuple[BodyFit, dict[str, object]]] = {}
        stagger, limit = self._floor.stagger, self.options.body_choice_max_stagger
        judging = not (len(views) == 1 and not self._arm_stage_started and np.isfinite(limit)
                       and (stagger is None or stagger > limit))
        racing = list(sel.active)
        # the reference is reported (so fitted) until a frame has judged the candidates
        extra = ([self._reference] if self._reference in self._bodies
                 and self._reference not in racing else [])
        if not judging:  # only the body reported is fitted (its fit is all the frame gives)
            shown = (sel.best() if sel.seen > 0 or self._reference not in self._bodies
                     else self._reference)
            for name in racing + extra:
                if name != shown:
                    sel.previous[name] = None
            racing = [shown]
        elif sel.seen == 0 and not self._arm_stage_started:
            racing += extra
        placed = self._placed(views)  # body-independent: once for all candidates
        for name in racing:
            self._use(self._bodies[name])
            fit = self._estimate([copy.copy(v) for v in views], sel.previous.get(name),
                                 search_one=not judging, placed=placed)
            if not self._plausible(fit.q, fit.views):
                sel.previous[name] = None
                continue
            sel.previous[name] = fit.q
            fits[name] = (fit, self.diagnostics)
        if not judging:
            sel.skip(self._reference)  # one view, no measure of distance: size unknown
        else:
            sel.add({name: fitted.residual for name, (fitted, _) in fits.items()})
        if sel.chosen is not None:
            best = sel.chosen
        elif sel.seen > 0 or self._arm_stage_started or self._reference not in self._bodies:
            best = sel.best()
        else:
            best = self._reference
        self._use(self._bodies[best])
        if best not in fits:
            self.diagnostics = {}
            return None
        fit, judged = fits[best]
        o = self.options
        if judging and len(views) == 1 and o.arm_search:  # report with the arm search
            report = self._estimate([copy.copy(v) for v in views], sel.previous.get(best),
                                    search_one=True, placed=placed)
            if self._plausible(report.q, report.views):
                return report
        self.diagnostics = judged
        return fit

    def _start_arm_selection(self) -> None:
        """Second start-up stage: once the preset is chosen, its arm-length variants
        are compared like the presets were, over ``arm_selection_frames`` frames."""
        n = self.options.arm_selection_frames
        sel = self._selection
        if n <= 0 or sel is None or sel.chosen is None or self._arm_stage_started:
            return
        self._arm_stage_started = True
        variants = arm_variants(self._bodies[sel.chosen], self.cameras,
                                tuple(self.options.arm_scales))
        previous = sel.previous.get(sel.chosen)
        self._reference = sel.chosen
        self._bodies = variants
        self._selection = BodySelection(tuple(variants), n,
                                        tolerance=self.options.arm_tolerance)
        for name in variants:
            self._selection.previous[name] = previous

    # ---- pose estimation -------------------------------------------------------------
    def _plausible(self, q: NDArray[np.float64], views: list[CameraView]) -> bool:
        """Whether an estimate of the active body can be reported (:func:`.gates.plausible`)."""
        q_b = self.diagnostics.get("q_blend")
        return plausible(self.skeleton, self.cameras, q, views,
                         None if q_b is None else np.asarray(q_b))

    def _placed(self, views: list[CameraView]) -> NDArray[np.float64]:
        """The database's blend placed in the world (the same for every body)."""
        lead = min(views, key=lambda v: v.distance)
        return self.placement.place(lead, [v for v in views if v is not lead])

    def _estimate(self, views: list[CameraView], prev_q: NDArray[np.float64] | None,
                  search_one: bool = True, placed: NDArray[np.float64] | None = None
                  ) -> BodyFit:
        """Blend, 6-DOF fit, reclassification and IK of the active body for one frame
        (:attr:`diagnostics` start afresh).

        ``search_one``: whether a frame one camera sees gets the arm search;
        ``placed``: :meth:`_placed` of ``views`` if already known.
        """
        o = self.options
        self.diagnostics = {}
        q_b = self._placed(views) if placed is None else placed.copy()
        anchors, _ = self._anchors(q_b, views, refine=False)
        q_b, root_priors = self._place_root(q_b, anchors)
        self.diagnostics["arms"] = []
        one = len(views) == 1
        if o.arm_search and (not one or search_one):
            q_b, self.diagnostics["arms"] = self._arms.search(
                self.body.name, self.renderer, q_b, self.cameras, views, prev_q,
                o.arm_tau, o.arm_temperature, o.arm_shortlist,
                pull=o.arm_depth_pull if one else 0.0)
        self.diagnostics["q_blend"] = q_b
        anchors, observed = self._anchors(q_b, views, refine=o.pose_prior)
        shirt_only = anchors
        heads, found = head_anchors(self.skeleton, q_b, self.cameras, self._cams, views, o)
        anchors = anchors.join(heads)
        self.diagnostics["heads"] = found
        self.diagnostics["observed"] = [(v, counts, cents) for v, (counts, cents)
                                        in zip(views, observed, strict=True)]
        q = q_b
        prior = self.prior if o.pose_prior else None
        prev = prev_q if o.pose_prior else None
        if len(anchors) >= 3:
            q = self.solver.solve_ik(q_b, anchors, prior, prev, root_priors=root_priors,
                                     turn_std=self._turn_std())
        size = {v.index: v.shirt_scale / v.window.scale for v in views}
        self.diagnostics["anchors"] = anchors
        # the residual that judges the body (and a good fit): the shirt's anchors only,
        # the heads found are no measure of a preset (its neck's length is generic)
        size_px = np.array([size[int(c)] for c in shirt_only.camera], dtype=np.float64)
        resid = reprojection_residual(self.solver, q, shirt_only, size_px)
        self.diagnostics["residual"] = resid
        return BodyFit(q, {int(p) for p in anchors.patch}, resid, views, self.renderer,
                    self.cameras)

    def _place_root(self, q: NDArray[np.float64], anchors: PatchAnchors
                    ) -> tuple[NDArray[np.float64], tuple[RootPrior, ...]]:
        """6-DOF fit of the placed blend; with one camera, the root moved along its ray
        to the depth filter's estimate, and the IK's prior on the root's depth.

        A loosely held first fit (:data:`_PLACEMENT_STD`) gives the filter its shirt
        reading; a one-camera rig refits the blend at the filter's depth, pinned with
        ``depth_pin_std`` once the feet told it. A lone view in a rig of several only
        gets the filter's depth as the IK's prior.
        """
        placed = q
        index = self._lone
        rig1 = len(self.cameras) == 1
        near = 0.3 if rig1 else None  # None: 3.3 per metre (not exactly 1 / 0.3)
        if index is None:
            return self.solver.solve_global(placed, anchors, position_std=near), ()
        q = self.solver.solve_global(placed, anchors,
                                     position_std=_PLACEMENT_STD if rig1 else None)
        cam = self.cameras[index]
        z = float(cam.world_to_camera(q[:3])[2])
        reading = z * self._depth_scale() if z > 0.3 else None
        self.diagnostics["shirt_depth"] = reading
        post = self._depth.posterior(reading)
        if post is None:
            return q, ()
        depth, std = post
        self.diagnostics["depth_post"] = post
        feet = self._depth.feet_known()
        if not (feet or rig1):
            return q, (RootPrior.camera_depth(cam, depth, std),)
        priors = (RootPrior.camera_depth(cam, depth, self.options.depth_pin_std if feet else std),)
        z0 = float(cam.world_to_camera(placed[:3])[2])
        if z0 > 0.3:  # along the ray through the root: the shirt stays where it is seen
            placed = placed.copy()
            placed[:3] = cam.center + (placed[:3] - cam.center) * (depth / z0)
        return self.solver.solve_global(placed, anchors, root_priors=priors,
                                        position_std=near, turn_std=self._turn_std()), priors

    def _turn_std(self) -> float | None:
        """How tightly a one-camera rig's fits at the filter's depth hold the trunk's turn
        at the blend's (``turn_std``; None: as loosely as the other rotations)."""
        t = self.options.turn_std
        return t if len(self.cameras) == 1 and t > 0 else None

    def _anchors(self, q: NDArray[np.float64], views: list[CameraView], refine: bool
                 ) -> tuple[PatchAnchors, list[Observed]]:
        """Render ``q`` in every view, match the classified patches to it (``refine``:
        after the pose-assisted reclassification), and anchor those both show."""
        verts = self.renderer.vertices(q)
        rendered = [self.renderer.render(verts, self.cameras[v.index], v.window) for v in views]
        observe = self._work.refine_classification if refine else self._work.observed_by_color
        observed = [observe(self.renderer, v, r) for v, r in zip(views, rendered, strict=True)]
        return patch_anchors(self.renderer, self.solver, self.cameras, q, views, rendered,
                             observed, self.prior.centroid, self.options), observed

    def _depth_scale(self) -> float:
        """The reference body's torso length over the active body's (the filter's
        scale is the player's size relative to the reference)."""
        return _torso_length(self._fixed.skeleton) / _torso_length(self.skeleton)

    def _result(self, frames: FrameSet, q: NDArray[np.float64], seen: set[int],
                views: list[CameraView], t0: float) -> TrackResult:
        heads = cast(list[tuple[int, HeadPoint]], self.diagnostics.get("heads", []))
        depth_std = None
        if len(views) == 1 and "depth_post" in self.diagnostics:
            # the IK's departure from the filter's depth counts as uncertainty too
            post, std = cast("tuple[float, float]", self.diagnostics["depth_post"])
            z = float(self.cameras[views[0].index].world_to_camera(q[:3])[2])
            depth_std = float(np.hypot(std, z - post))
        extras: dict[str, object] = {
            "feet": [(v.index, self._cams[v.index].floor.last_feet) for v in views],
            "floor_cue": self._floor.depth is not None,
            "depth_std": depth_std,
            "arms": self.diagnostics.get("arms", [])}
        return pose_result(frames, self.skeleton, q, seen, views, self.cameras, heads,
                           self.options, 1000.0 * (time.perf_counter() - t0), extras)
