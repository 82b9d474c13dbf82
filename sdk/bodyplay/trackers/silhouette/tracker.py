"""The silhouette tracker: one camera, ordinary clothes (papers/single-camera-silhouette-mocap.txt).

Per frame: undistort -> background subtraction (:mod:`.background`) -> the floor
point G and the window (:mod:`.window`) -> distance transforms at the three levels
(:mod:`.distance`) -> tree-based Bayesian filter over the shape hierarchy
(:mod:`.treefilter`) -> the MAP leaf's pose, placed at G and turned by the line of
sight. The estimated body, dilated, keeps the background model from learning the
player. Body size (:mod:`.bodychoice`): the first ``select_frames`` frames with a
person, counted from the first frame the player moves (``select_motion``; before,
the silhouette is only the first frame's colour segmentation; ``select_wait`` s for
a player who stays still), run a filter per body preset, and the preset whose
template's head top matches the player's stature and fits the silhouette best is
kept.

When there is no first-frame guess of the player (GrabCut took a cup with the
player) and what moves is not a whole person (a player who moves only the arms:
the ray through an elbow meets the floor metres away, or never), the floor
distance is the one at which the templates fit what moves best (:mod:`.shapestart`,
median over ``shape_frames`` frames), until a floor point is seen; at that
moment the first frame's guess is made again in the box a person standing there
can fill (``box_guess``, :meth:`.background.BackgroundModel.guess_in`); a first
guess dropped as not the player's (a treadmill under him) is that box at the first
pose after it, grown to where the templates fit when they put the player nearer
(``box_redo``). A start whose
track is lost before it has lasted ``restart_within`` s is undone (nothing is
protected any more, the still body is held again), and the next floor point must
agree with the templates' distance (``restart_agree``) for ``restart_doubt`` s.

Joint states (DESIGN.md's contract): ``tracked`` when the joint's part shows in the
chosen template, ``inferred`` when the template has it occluded or when the person
has vanished for less than ``lost_after`` seconds (the issue's "predicted"),
``lost`` otherwise.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import cv2
import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from bodyplay.body.joints import JOINT_INDEX, NUM_JOINTS
from bodyplay.body.shapes import BodyShape, body_shape
from bodyplay.body.skeleton import Skeleton
from bodyplay.capture.camera import Camera
from bodyplay.capture.frames import FrameSet
from bodyplay.errors import TimestampError
from bodyplay.trackers.base import (
    JointState,
    TrackerCapabilities,
    TrackResult,
    check_frame_set,
    lost_result,
)
from bodyplay.trackers.silhouette.armfit import ArmFitter, arm_atlas
from bodyplay.trackers.silhouette.background import BackgroundModel, Silhouette
from bodyplay.trackers.silhouette.bodychoice import BodyChoice
from bodyplay.trackers.silhouette.bodywidth import WidthFit
from bodyplay.trackers.silhouette.distance import DistanceMaps, distance_maps
from bodyplay.trackers.silhouette.facing import reflect_output
from bodyplay.trackers.silhouette.headdepth import RunningMedian, head_depth_offset
from bodyplay.trackers.silhouette.hierarchy import PART_JOINTS, ShapeTree, geometry_of
from bodyplay.trackers.silhouette.options import SilhouetteOptions
from bodyplay.trackers.silhouette.shapestart import shape_distance, window_at_distance
from bodyplay.trackers.silhouette.stance import stance_offset
from bodyplay.trackers.silhouette.stature import (
    head_top,
    shifted,
    smallest_template_area,
)
from bodyplay.trackers.silhouette.stilltrack import TrackMotion
from bodyplay.trackers.silhouette.treefilter import FilterStep, TreeFilter
from bodyplay.trackers.silhouette.window import (
    ObservedWindow,
    back_project,
    farthest_person,
    feet_like,
    floor_point,
    observe,
    person_box,
    select_person,
)

__all__ = ["SilhouetteTracker"]

_JOINT_PART = np.zeros(NUM_JOINTS, np.int64)
for _p, _names in enumerate(PART_JOINTS):
    for _n in _names:
        _JOINT_PART[JOINT_INDEX[_n]] = _p


@dataclass
class _Last:
    joints: NDArray[np.float64]
    pose: NDArray[np.float64]
    t: float
    template: NDArray[np.uint8] | None = None
    protect: NDArray[np.bool_] | None = None
    extras: dict[str, object] = field(default_factory=dict)
    shown: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None  # reported, if other


class SilhouetteTracker:
    """Implements :class:`bodyplay.trackers.base.Tracker` (build with
    :func:`bodyplay.trackers.silhouette.create_silhouette_tracker`)."""

    name = "silhouette"
    capabilities = TrackerCapabilities(min_cameras=1, max_cameras=1)

    def __init__(self, options: SilhouetteOptions, cameras: tuple[Camera, ...],
                 tree: ShapeTree) -> None:
        self.options = options
        self.cameras = cameras
        self.tree = tree
        self.geometry = geometry_of(tree.options)
        self._maps = cameras[0].undistort_maps()
        self._cam = cameras[0]
        self._template_R = self.geometry.template_view(2).R
        self.max_distance = options.max_distance or farthest_person(
            self._cam, options.background.working_size, options.min_person_px)
        self.min_start_area = options.start_area * smallest_template_area(tree, self.geometry)
        self._atlas: NDArray[np.float64] | None = None
        if options.arm_candidates:  # built here (0.5 s), not on the first tracked frame
            from bodyplay.trackers.silhouette.poses import mirror_poses

            ref = Skeleton.from_shape("m")
            self._atlas = arm_atlas(ref, [tree.poses, mirror_poses(ref, tree.poses)],
                                    options.arm_candidates, np.random.default_rng(0))
        self.reset()

    @property
    def body_name(self) -> str | None:
        """The body preset in use (None while it is being chosen)."""
        return self._choice.chosen

    def reset(self) -> None:
        """Forget the background, the posterior, the body choice and the last pose."""
        self.background = BackgroundModel(self.options.background)
        want = self.options.body
        names = list(self.tree.bodies) if want == "auto" else [want]
        self._filters = {b: TreeFilter(self.tree, self.tree.bodies[b], self.options)
                         for b in names}
        self._choice = BodyChoice(names, self.tree, self.geometry, self.options,
                                  names[0] if len(names) == 1 else None)
        self._moved = False
        self._t: float | None = None
        self._forget_track()
        self._skeletons = {b: Skeleton.from_shape(b) for b in names}
        self._fitters: dict[str, ArmFitter] = {}
        self._maps_now: tuple[DistanceMaps, ...] = ()
        self._head = RunningMedian(self.options.head_depth_window)
        self._stance = RunningMedian(self.options.stance_window)
        self._restarted = False
        self.reguesses = 0

    def _forget_track(self) -> None:
        """Forget the track (last pose, start time, distance and the readings behind
        it), as before anyone was seen; the background and the body choice stay."""
        self._last: _Last | None = None
        self._started: float | None = None
        self._start_frame = 0
        self._distance: float | None = None
        self._depths: list[tuple[float, float]] = []
        self._shape_ds: list[float] = []
        self._shape_d: float | None = None
        self._bad = 0
        self._width: WidthFit | None = None  # the player's girth, measured per track
        o = self.options
        self._motion = TrackMotion(o.still_window, o.still_motion, o.still_fit,
                                   o.background.min_area)

    # ---- the pipeline -------------------------------------------------------------
    def process(self, frames: FrameSet) -> TrackResult:
        """Estimate the pose for one frame set (one camera)."""
        t0 = time.perf_counter()
        if len(frames) > 1:  # a rig's frame set: this tracker reads its first camera
            frames = FrameSet(frames.frames[:1], frames.t, frames.index)
        check_frame_set(frames, self.cameras)
        if self._t is not None and frames.t <= self._t:
            raise TimestampError(f"frame set t={frames.t} is not after the previous t={self._t}")
        self._t = frames.t
        image = frames[0].image
        if self._maps is not None:
            image = np.asarray(cv2.remap(image, self._maps[0], self._maps[1], cv2.INTER_LINEAR),
                               np.uint8)
        stages: dict[str, float] = {}
        tic = time.perf_counter()
        self._undo_failed_start(frames.t)
        protect = self._last.protect if self._last is not None else None
        sil = self.background.apply(image, protect)
        stages["background"] = time.perf_counter() - tic
        if (self._choice.chosen is None and not self._moved and self.options.select_motion
                and self.background.motion >= self.options.select_motion):
            # the player moves for the first time: the body is chosen from here on
            # (until now the silhouette was only the first frame's colour guess)
            self._moved = True
            self._choice.clear()
        tic = time.perf_counter()
        keep_for = self.options.depth_window
        self._depths = [(t, d) for t, d in self._depths if frames.t - t <= keep_for]
        cap = min((d for _, d in self._depths), default=None)
        if self._distance is not None and self._last is not None:
            # a player does not back away faster than ``max_recession`` m/s
            far = self._distance + self.options.max_recession * (frames.t - self._last.t)
            cap = far if cap is None else min(cap, far)
        # one player: the foreground components the track follows (others are dropped)
        near = self._last.protect if self._last is not None else None
        stands = self._stands_factory(sil.scale)
        person = select_person(sil.foreground, near, stands=stands)
        if near is not None and self.options.still_window:
            person, near = self._check_still(frames.t, sil, person, stands)
        region = sil.region
        if region is not None:  # the guess too: the part of it joined to the player
            anchor = near if near is not None else (person > 0 if person.any() else None)
            region = select_person(region, anchor, stands=stands)
        if person.sum() != sil.foreground.sum() or region is not sil.region:
            dropped = sil.foreground & (1 - person)
            if region is not None:
                region = region & (1 - dropped)
            sil = Silhouette(person, sil.unknown | dropped, sil.scale, region)
        start = self._started is None or frames.t - self._started < self.options.bootstrap_time
        win, ok = self._floor_window(sil, cap, start)
        guessed = self.background.player
        floor_ok = True
        if ok and win is not None and guessed is not None and not self._feet_like(win):
            # the first frame's guess, resolved as the player, took something wide under
            # the player (a treadmill) for the body: only what moved is the player here
            # (the wide base's front edge is no floor contact: until what moved is a
            # whole person, there is no pose)
            floor_ok = False
            self.background.drop_guess()
            g = (guessed & (sil.foreground > 0)).astype(np.uint8)
            if g.any():
                moved = Silhouette(sil.foreground & (1 - g), sil.unknown | g, sil.scale, None)
                win2, ok2 = self._floor_window(moved, cap, start)
                if ok2:  # else what moved is not a whole person yet: no pose
                    sil, win, floor_ok = moved, win2, True
        if (self.options.shape_frames and not self.background.guessing
                and (self._started is None or self._shape_d is not None)):
            # no first guess of the player to find the feet in: when what moves does not
            # stand on the floor as a person, the distance from the shape
            win, ok = self._from_shape(sil, win if ok and floor_ok else None)
            floor_ok = True
        if win is not None and floor_ok:
            self._depths.append((frames.t, win.distance))
        if win is None or not ok or not floor_ok:
            stages["window"] = time.perf_counter() - tic
            return self._absent(frames, sil, t0, stages)
        o = self.options
        bg = self.background
        if o.box_redo and o.box_guess and bg.dropped and not bg.reguessed:
            # the first guess was dropped (it took a treadmill for the figure): the box a
            # person standing here can fill is the guess now, resolved (once per start)
            bg.guess_in(self._redo_box(win, sil), grabcut=False)
        if self._started is None:
            self._started = frames.t
            self._start_frame = self.background.frames
        off = win.ground - self._cam.center
        self._distance = float(np.hypot(off[0], off[2]))
        beta = self.options.beta
        maps = tuple(distance_maps(win.foreground[lv], win.unknown[lv], beta=beta)
                     for lv in range(3))
        stages["distances"] = time.perf_counter() - tic
        tic = time.perf_counter()
        step = self._filter_step(maps, win.foreground[2])  # type: ignore[arg-type]
        self._maps_now = maps
        stages["tree"] = time.perf_counter() - tic
        if step.distance > 4.0 * self.tree.options.thresholds[2]:
            self._bad += 1
            if self._bad >= 5:  # recovery: start over from the initial prior
                for f in self._filters.values():
                    f.reset()
                self._bad = 0
        else:
            self._bad = 0
        tic = time.perf_counter()
        result = self._result(frames, step, win, sil, t0)
        stages["output"] = time.perf_counter() - tic
        result.extras["stages"] = stages
        return result

    def _check_still(self, t: float, sil: Silhouette, person: NDArray[np.uint8],
                     stands: Callable[[NDArray[np.bool_]], bool]
                     ) -> tuple[NDArray[np.uint8], NDArray[np.bool_] | None]:
        """Add this frame's motion to the track's evidence (:mod:`.stilltrack`); when the
        track kept what stood still while what it dropped moved, guess again: what it
        kept is learned as background, the track, the posterior and the body choice
        are forgotten, and the player is chosen anew among the rest of the
        foreground. Returns the player's components and the estimate they were
        chosen near (None after a new guess)."""
        mv = self.background.moving
        kept = person > 0
        dropped = (sil.foreground > 0) & ~kept
        fit = self._last.extras.get("distance") if self._last is not None else None
        self._motion.add(t, int((mv & kept).sum()), int((mv & dropped).sum()), mv.size,
                         float(fit) if isinstance(fit, float | int) else None,
                         float(dropped.mean()))
        if not self._motion.wrong():
            return person, self._last.protect if self._last is not None else None
        held = kept.copy()  # what the track held: its foreground and its template
        if self._last is not None and self._last.template is not None:
            held |= self._last.template > 0
        self.background.release(held, self._start_frame)
        self.reguesses += 1
        self._forget_track()
        for f in self._filters.values():
            f.reset()
        if self.options.body == "auto":  # the body was measured on what was not the player
            self._filters = {b: TreeFilter(self.tree, self.tree.bodies[b], self.options)
                             for b in self.tree.bodies}
            self._choice = BodyChoice(list(self._filters), self.tree, self.geometry,
                                      self.options)
            self._skeletons = {b: Skeleton.from_shape(b) for b in self._filters}
        rest = (sil.foreground > 0) & ~held
        return select_person(rest.astype(np.uint8), None, stands=stands), None

    def _undo_failed_start(self, t: float) -> None:
        """A start that did not hold is no track: when the person is lost (no pose for
        ``lost_after`` s) after a track that lasted under ``restart_within`` s, the
        tracker starts over as if it had never seen anyone (the background model is
        kept, but nothing is protected, so the still body under what moves is held
        again and the distance may come from the shape). A wrong first pose (the
        arms of a player who stands still, taken for a whole person metres away)
        otherwise protected its own spot and was never replaced."""
        last, started = self._last, self._started
        if (last is None or started is None or not self.options.restart_within
                or t - last.t <= self.options.lost_after
                or last.t - started >= self.options.restart_within):
            return
        self._forget_track()
        self._restarted = True
        for f in self._filters.values():
            f.reset()

    def _from_shape(self, sil: Silhouette, seen: ObservedWindow | None
                    ) -> tuple[ObservedWindow | None, bool]:
        """The window when no floor point is seen (:mod:`.shapestart`): ``seen`` (the
        floor point of the silhouette's lowest pixel, when it makes a plausible
        person) is used whenever there is one; else, before the first pose, the
        median over ``shape_frames`` frames of the distance the templates fit best
        at, kept until a floor point is seen. After a failed start
        (:meth:`_undo_failed_start`) the floor point must first agree with that
        distance (within ``restart_agree`` of it) for the new track's first
        ``restart_doubt`` s: the failed start was a floor point that was not the
        feet."""
        o = self.options
        # after a failed start, for ``restart_doubt`` s of the new track, a floor point
        # counts only where the templates' fit agrees with it
        doubt = self._restarted and (self._started is None or self._t is None
                                     or self._t - self._started < o.restart_doubt)
        if seen is not None and not doubt:  # it stands on the floor: as before
            self._restarted = False
            self._shape_d = None
            return seen, True
        if self._started is None:
            held = self.background.held
            known = self.background.known
            if (held is None or not held.any() or not sil.foreground.any() or known is None
                    or known.mean() < 0.25):
                # nothing still and unseen, or what the templates may not cover is not
                # known yet
                return None, False
            d = self._templates_distance(sil)
            if d is not None:
                self._shape_ds.append(d)
            if len(self._shape_ds) < o.shape_frames:
                return None, False  # not sure yet where the player stands
            self._shape_d = float(np.median(self._shape_ds[-3 * o.shape_frames:]))
            if o.box_guess and not self.background.reguessed:
                # where the player stands is known now: the first guess again, in the
                # box a person standing there can fill
                at = window_at_distance(self.geometry, self._cam, sil.foreground, sil.unknown,
                                        sil.scale, self._shape_d)
                if at is not None:
                    self.background.guess_in(self._person_box(at.ground, sil))
        assert self._shape_d is not None
        d = self._shape_d
        if seen is not None and abs(seen.distance - d) <= o.restart_agree * d:
            self._restarted = False  # the floor point the templates agree with
            self._shape_d = None
            return seen, True
        win = window_at_distance(self.geometry, self._cam, sil.foreground, sil.unknown,
                                 sil.scale, self._shape_d)
        return win, win is not None

    def _plausible(self, win: ObservedWindow) -> bool:
        """A person: at least ``min_height`` tall, not wider than the window, standing
        within ``max_distance`` of the camera (:attr:`max_distance`); to start a track,
        also covering at least :attr:`min_start_area` m2 (``start_area``)."""
        if win.distance > self.max_distance:
            return False
        fg = win.foreground[0] if win.region is None else win.region
        rows = np.flatnonzero(fg.any(axis=1))
        if rows.size == 0:
            return False
        tall = (rows[-1] - rows[0] + 1) * self.geometry.mpp(0)
        if (self._started is None
                and float((fg > 0).sum()) * self.geometry.mpp(0) ** 2 < self.min_start_area):
            return False  # a start: not a whole person's worth of silhouette (an arm)
        cols = np.flatnonzero(fg.any(axis=0))
        wide = (cols[-1] - cols[0] + 1) / fg.shape[1]
        return bool(tall >= self.options.min_height and wide < 0.97)

    def _stands_factory(self, scale: float) -> Callable[[NDArray[np.bool_]], bool]:
        """Whether a blob of the working image stands on the floor in view: the ray
        through its lowest pixel (under its mean column) meets the floor between
        0.3 m and ``max_distance`` from the camera."""

        def stands(blob: NDArray[np.bool_]) -> bool:
            ys, xs = np.nonzero(blob)
            if ys.size == 0:
                return False
            u = (float(xs.mean()) + 0.5) / scale - 0.5
            v = (float(ys.max()) + 0.5) / scale - 0.5
            g = floor_point(self._cam, u, v)
            if g is None:
                return False
            d = float(np.hypot(*(g - self._cam.center)[[0, 2]]))
            return 0.3 <= d <= self.max_distance

        return stands

    def _floor_window(self, sil: Silhouette, cap: float | None, start: bool
                      ) -> tuple[ObservedWindow | None, bool]:
        """The window at the floor point, and whether it shows a person.

        At first the lowest of what moves and of the first frame's guess of the
        player; once tracking, what moves, if that is a whole person. The guess
        counts only when its lowest part could be feet: a first frame's GrabCut can
        take a dark treadmill or sofa under the player for the figure."""
        win, ok = None, False
        if not start or sil.region is None:
            win = observe(self.geometry, self._cam, sil.foreground, sil.unknown, sil.scale, cap)
            ok = win is not None and self._plausible(win)
        if not ok and sil.region is not None:
            guess = observe(self.geometry, self._cam, sil.foreground, sil.unknown, sil.scale,
                            cap, sil.region)
            if guess is not None and self._feet_like(guess):
                win, ok = guess, self._plausible(guess)
            elif start:
                win = observe(self.geometry, self._cam, sil.foreground, sil.unknown, sil.scale,
                              cap)
                ok = win is not None and self._plausible(win)
        return win, ok

    def _feet_like(self, win: ObservedWindow) -> bool:
        reg = win.foreground[0] if win.region is None else win.region
        return feet_like(reg, self.geometry.mpp(0), self.options.foot_band,
                         self.options.max_foot_width)

    def _filter_step(self, maps: tuple[object, ...], observed: NDArray[np.uint8]) -> FilterStep:
        """One filter step: the chosen body's, or while the body is chosen every
        preset's, each read by the choice (:mod:`.bodychoice`)."""
        choice = self._choice
        if choice.chosen is not None:
            return self._filters[choice.chosen].step(maps)  # type: ignore[arg-type]
        steps = {}
        for b, f in self._filters.items():
            steps[b] = f.step(maps)  # type: ignore[arg-type]
            choice.add(b, steps[b].distance, observed, steps[b].leaf, steps[b].shift)
        best = choice.best()
        waited = (not self.options.select_motion or self._moved or (
            self._started is not None and self._t is not None
            and self._t - self._started >= self.options.select_wait))
        if choice.frames >= self.options.select_frames and waited:
            choice.chosen = best
            self._filters = {best: self._filters[best]}
            self._skeletons = {best: self._skeletons[best]}
        return steps[best]

    def _result(self, frames: FrameSet, step: FilterStep, win: ObservedWindow, sil: Silhouette,
                t0: float) -> TrackResult:
        body = self._choice.best()
        tree = self.tree
        sk = self._skeletons[body]
        bt = tree.bodies[body]
        R_align = win.views[2].R.T @ self._template_R
        # the template's best position in the window moves the body sideways (and up)
        mpp = self.geometry.mpp(2)
        ground = win.ground + step.shift[0] * mpp * win.views[2].R[0]
        lift = np.array([0.0, max(0.0, -step.shift[1] * mpp), 0.0])
        ratio = sk.pelvis_height / Skeleton.from_shape("m").pelvis_height
        leaf_mask = bt.runs[2].masks(np.array([step.leaf]))[0]  # the MAP leaf, level 3
        placed = shifted(leaf_mask, step.shift)
        # joints: the few best leaves blended by posterior (the MAP leaf's pose vector)
        leaves = step.top[step.weights >= 0.2 * step.weights[0]]
        w = step.weights[: len(leaves)] / step.weights[: len(leaves)].sum()
        joints = np.zeros((NUM_JOINTS, 3))
        pose = np.zeros(sk.pose_dim)
        for k, (leaf, wk) in enumerate(zip(leaves, w, strict=True)):
            q = tree.poses[tree.node_pose[2][leaf]].copy()
            q[1] *= ratio
            J = sk.joint_positions(q) - q[0:3] + bt.offset[leaf]
            joints += wk * (J @ R_align.T + ground + lift)
            if k == 0:
                pose = q.copy()
                pose[0:3] = R_align @ bt.offset[leaf] + ground + lift
                pose[3:6] = (Rotation.from_matrix(R_align) * Rotation.from_rotvec(q[3:6])
                             ).as_rotvec()
        if self.options.arm_candidates:
            joints, pose = self._refine_arms(body, step, joints, pose, R_align, ground + lift,
                                             placed, ratio)
        sight = win.views[2].R[2]  # depth cues move the body along the line of sight
        move = 0.0
        if self.options.head_depth_weight > 0:  # the head top's depth cue
            move += self.options.head_depth_weight * self._head.add(
                frames.t, self._head_offset(leaf_mask, step, win))
        if self.options.stance_weight > 0:  # the feet's depth spread
            g = self.geometry
            off = stance_offset(win.foreground[2], placed, g.floor_row(2), g.mpp(2),
                                win.distance, float(self._cam.center[1]),
                                max(1, int(round(self.options.foot_band / g.mpp(2)))))
            if off is not None:  # offsets within the dead band are segmentation noise
                off = float(np.sign(off)) * max(abs(off) - self.options.stance_deadband, 0.0)
            move += self.options.stance_weight * self._stance.add(frames.t, off)
        if move != 0.0:
            joints = joints + move * sight
            pose = pose.copy()
            pose[0:3] += move * sight
        shape = self._body_shape(body, pose, win)
        if self._last is not None and self.options.smooth > 0 and frames.t - self._last.t < 0.2:
            a = self.options.smooth
            joints = a * self._last.joints + (1 - a) * joints
        occl = tree.occluded[step.leaf]
        states: tuple[JointState, ...] = tuple(
            "inferred" if occl[_JOINT_PART[j]] else "tracked" for j in range(NUM_JOINTS))
        template, protect = back_project(self._cam, win.views[2], sil, leaf_mask, step.shift,
                                         self.options.protect_radius)
        extras: dict[str, object] = {
            "silhouette": sil.foreground, "unknown": sil.unknown, "template": template,
            "silhouette_scale": sil.scale, "leaf": step.leaf, "distance": step.distance,
            "evaluations": step.evaluations, "body": body, "ground": win.ground,
            "shape": shape,
        }
        self._last = _Last(joints, pose, frames.t, template, protect, extras)
        conf = np.where(np.array([s == "tracked" for s in states]), 1.0, 0.5)
        conf *= float(np.exp(-step.distance / (4.0 * tree.options.thresholds[2])))
        if self.options.facing == "away":  # filmed from behind: the front pose reflected
            joints, pose, states, conf = reflect_output(sk, joints, pose, states, conf,
                                                        self._cam.center)
            self._last.shown = (joints, pose)  # the filter and smoothing stay in front space
        extras["facing"] = self.options.facing
        return TrackResult(frames.index, frames.t, joints, states, conf,
                           (time.perf_counter() - t0) * 1000.0, pose, extras)

    def _body_shape(self, body: str, pose: NDArray[np.float64], win: ObservedWindow
                    ) -> BodyShape:
        """The body shape to report: the preset's, its girth measured on the reported
        pose over the track's first ``width_frames`` frames (:mod:`.bodywidth`; the
        preset's own with ``width_frames`` 0)."""
        o = self.options
        if not o.width_frames:
            return body_shape(body)
        if self._width is None:
            self._width = WidthFit(o.width_frames, o.width_max)
        if not self._width.done:
            self._width.add(body, pose, win.views[2], self._maps_now[2].cost)
        return self._width.shape(body)

    def _head_offset(self, leaf_mask: NDArray[np.uint8], step: FilterStep, win: ObservedWindow
                     ) -> float | None:
        """The head-top depth cue of this frame (:func:`.headdepth.head_depth_offset`)."""
        top = head_top(win.foreground[2])
        tt = head_top(leaf_mask)
        if top is None or tt is None:
            return None
        g = self.geometry
        return head_depth_offset(top, tt + step.shift[1], g.floor_row(2), g.mpp(2),
                                 win.distance, float(self._cam.center[1]),
                                 self.options.head_min_lever)

    def _refine_arms(self, body: str, step: FilterStep, joints: NDArray[np.float64],
                     pose: NDArray[np.float64], R_align: NDArray[np.float64],
                     at: NDArray[np.float64], placed: NDArray[np.uint8], ratio: float
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Each arm of the MAP leaf searched on its own (:mod:`.armfit`), with the
        body's fitter (built on first use). ``placed``: the leaf's level-3 template
        moved by its fitted shift; ``ratio``: the body's pelvis height to the tree's."""
        fitter = self._fitters.get(body)
        if fitter is None:
            assert self._atlas is not None  # built in __init__ when arm_candidates > 0
            fitter = ArmFitter(self._skeletons[body], self.geometry, self._atlas,
                               stay=self.options.arm_stay, margin=self.options.arm_margin,
                               body=self.options.arm_body)
            self._fitters[body] = fitter
        q = self.tree.poses[self.tree.node_pose[2][step.leaf]].copy()
        q[1] *= ratio
        return fitter.refine_reported(q, self.tree.bodies[body].offset[step.leaf], placed,
                                      step.shift, self._maps_now[fitter.level].cost,
                                      joints, pose, R_align, at)

    def _person_box(self, ground: NDArray[np.float64], sil: Silhouette) -> NDArray[np.bool_]:
        """Where a person standing at ``ground`` can be, in ``sil``'s working image
        (the box a first guess is made again in: ``box_guess``, ``box_below``, ``box_top``)."""
        o = self.options
        return person_box(self._cam, ground, sil.foreground.shape, sil.scale, o.box_guess,
                          o.box_below, o.box_top)

    def _templates_distance(self, sil: Silhouette) -> float | None:
        """The floor distance at which body ``m``'s templates best fit ``sil``
        (:func:`.shapestart.shape_distance`, level 1); None when none fits."""
        bt = self.tree.bodies.get("m") or next(iter(self.tree.bodies.values()))
        return shape_distance(bt, self.geometry, self._cam, sil.foreground, sil.unknown,
                              sil.scale, 1.0, self.max_distance, beta=self.options.beta,
                              level=1)

    def _redo_box(self, win: ObservedWindow, sil: Silhouette) -> NDArray[np.bool_]:
        """The box a dropped first guess is made again in (``box_redo``): where a
        person standing at the floor point of ``win`` can be, grown by the box at the
        floor distance where the templates fit the silhouette best (:mod:`.shapestart`)
        when that distance is nearer than the floor point by more than
        ``restart_agree`` of it. The floor point after a drop is the lowest pixel of
        what moved (the shins above a still bare foot the dropped guess left as room)
        and may lie metres behind the player; the box standing there has its bottom
        edge above the feet, which would stay room for good."""
        box = self._person_box(win.ground, sil)
        d = self._templates_distance(sil)
        if d is None or win.distance - d <= self.options.restart_agree * d:
            return box  # the templates agree with the floor point, or put the player farther
        at = window_at_distance(self.geometry, self._cam, sil.foreground, sil.unknown,
                                sil.scale, d)
        return box if at is None else box | self._person_box(at.ground, sil)

    def _absent(self, frames: FrameSet, sil: Silhouette, t0: float,
                stages: dict[str, float]) -> TrackResult:
        """No person in view: the last pose as ``inferred`` for ``lost_after`` s, then lost."""
        last = self._last
        ms = (time.perf_counter() - t0) * 1000.0
        if last is not None and frames.t - last.t <= self.options.lost_after:
            inferred: JointState = "inferred"
            joints, pose = last.shown or (last.joints, last.pose)
            res = TrackResult(frames.index, frames.t, joints.copy(),
                              (inferred,) * NUM_JOINTS, np.full(NUM_JOINTS, 0.2), ms,
                              pose.copy(),
                              {"silhouette": sil.foreground, "unknown": sil.unknown,
                               "silhouette_scale": sil.scale, "stages": stages})
            return res
        res = lost_result(frames.index, frames.t, ms)
        res.extras.update({"silhouette": sil.foreground, "unknown": sil.unknown,
                           "silhouette_scale": sil.scale, "stages": stages})
        return res
