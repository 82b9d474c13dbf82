"""The color-shirt tracker's work in each camera's image (:class:`CameraWork`).

Undistortion, masks and plates, the histogram search, crop, white balance,
classification and database query; with a pose's render, the correspondences,
the pose-assisted reclassification and the refit of ``W``; after a pose, each
camera's gate, search box and room plate. The 3-D side is :mod:`.tracker`'s.
"""

from __future__ import annotations

import copy
import dataclasses

import cv2
import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import NUM_COLORS, PATCHES
from bodyplay.body.skinning import SkinnedMesh
from bodyplay.capture.camera import Camera
from bodyplay.trackers.colorshirt.anchors import Observed
from bodyplay.trackers.colorshirt.colors import ColorModel
from bodyplay.trackers.colorshirt.crossview import CrossView
from bodyplay.trackers.colorshirt.database import PoseDatabase
from bodyplay.trackers.colorshirt.floor import BackgroundPlate, FloorWatch, person_region
from bodyplay.trackers.colorshirt.locate import (
    BackgroundMask,
    ShirtLocation,
    ShirtLocator,
    reduce_box,
)
from bodyplay.trackers.colorshirt.options import ColorShirtOptions
from bodyplay.trackers.colorshirt.prediction import (
    CropWindow,
    PoseRenderer,
    RenderedPose,
    patch_stats,
)
from bodyplay.trackers.colorshirt.views import (
    WHITE_ID,
    CameraState,
    CameraView,
    classify_camera,
    clean_ids,
    make_query,
    nonzero_box,
    prior_penalty_slope,
)
from bodyplay.trackers.colorshirt.whitebalance import ReferenceIlluminations, white_balance_from_ids

__all__ = ["CameraWork"]

_REDUCE = 2
"""Downscale of the frame MOG2 and the floor cue's plate both work on (they share it)."""

_MOVED = 0.01
"""Share of a start candidate's shirt box that MOG2 must see change for it to have
moved (a player sways; a poster does not)."""

_MOVED_REACH = 0.25
"""How far beyond what moved (in located window sizes) a region found there is
classified: the still rest of a shirt whose limb moved."""

_EMPTY_ROOM = 0.5
"""Share of a start candidate's shirt box the room plate must have learned on frames
without a player (the empty room) for a region nothing moved in to be that room."""

_TORSO_PATCHES = np.array([p.id for p in PATCHES if p.bone in ("thorax", "lumbar")])
"""The shirt's torso patches (front, back, flanks)."""

_TOWARDS_CAMERA = np.array([0.0, 0.0, -1.0])
"""A body's forward axis, in a camera's frame, when it faces that camera."""

_SEARCH_REACH = 1.0
"""How far around the shirt's last box (in box sizes) the histogram search looks first."""


def _image_box(cam: Camera, points: NDArray[np.float64]
               ) -> tuple[int, int, int, int] | None:
    """Pixel box of ``points`` projected into ``cam`` (None: none in front of it)."""
    uv = cam.project(points, distort=False)
    uv = uv[np.isfinite(uv).all(axis=1)]
    if not len(uv):
        return None
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    return int(lo[0]), int(lo[1]), int(np.ceil(hi[0])), int(np.ceil(hi[1]))


def _ids_box(view: CameraView) -> tuple[int, int, int, int]:
    """Image box of ``view``'s pixels classified as the shirt's colours (not white)."""
    box = nonzero_box((view.ids > 0) & (view.ids != WHITE_ID))
    assert box is not None
    lo = view.window.to_image(np.array(box[:2], float))
    hi = view.window.to_image(np.array(box[2:], float) + 1.0)
    return int(lo[0]), int(lo[1]), int(hi[0]), int(hi[1])


def _box_share(zone: NDArray[np.bool_] | None, view: CameraView) -> float:
    """The share of ``view``'s shirt box that plate-resolution ``zone`` covers (or 0)."""
    if zone is None:
        return 0.0
    h, w = zone.shape
    x0, y0, x1, y1 = reduce_box(_ids_box(view), _REDUCE, w, h)
    if x1 <= x0 or y1 <= y0:
        return 0.0
    return float(zone[y0:y1, x0:x1].mean())


def _full_size(mask: NDArray[np.bool_], image: NDArray[np.uint8]) -> NDArray[np.bool_]:
    """A plate-resolution ``mask`` at ``image``'s size (nearest neighbour)."""
    return cv2.resize(mask.astype(np.uint8), (image.shape[1], image.shape[0]),
                      interpolation=cv2.INTER_NEAREST) > 0


def _player_region(view: CameraView, cam: Camera) -> NDArray[np.bool_]:
    """Where the player of ``view``'s shirt may stand, at the plates' resolution: the
    floor cue's region around the shirt's classified pixels, down to the image's
    lower edge (:func:`person_region`)."""
    w, h = cam.width // _REDUCE, cam.height // _REDUCE
    region = person_region(_ids_box(view), cam.width, cam.height)
    x0, y0, x1, y1 = reduce_box(region, _REDUCE, w, h)
    out = np.zeros((h, w), bool)
    out[y0:y1, x0:x1] = True
    return out


class CameraWork:
    """The per-camera image steps (see the module docstring): what never changes
    while tracking; each camera's :class:`CameraState` and the body's renderer are
    passed in."""

    def __init__(self, options: ColorShirtOptions, cameras: tuple[Camera, ...],
                 database: PoseDatabase, color_model: ColorModel) -> None:
        self.options = options
        self.cameras = cameras
        self.database = database
        self.color_model = color_model
        """Chooses ``W``."""
        self.noise_model = (
            dataclasses.replace(color_model, measurement_noise=options.measurement_noise)
            if options.measurement_noise > 0 else color_model)
        """The classifier: ``color_model`` with the W-amplified measurement noise."""
        self.locator = ShirtLocator(options.locate)
        self._plate = options.floor_cue or options.head_cue
        """Whether the floor cue's background plate runs (the floor and head cues read it)."""
        self._undistort = [c.undistort_maps() for c in cameras]
        self.crossview = (CrossView(len(cameras)) if options.cross_view and len(cameras) > 1
                          else None)
        self._shirt_vertices: tuple[SkinnedMesh, NDArray[np.intp], NDArray[np.intp]] | None = None
        """The last mesh of :meth:`remember_shirt`, its shirt's and torso's vertex indices."""
        self.facing: NDArray[np.float64] | None = None
        """The tracked body's forward axis in the world: each camera's database query
        keeps to poses facing within ``facing_turn`` of it (None: of the camera)."""

    def new_states(self) -> list[CameraState]:
        """Fresh per-camera states (nothing learned; ``initial_white_balance`` if set)."""
        init = self.options.initial_white_balance
        states = [
            CameraState(BackgroundMask(downscale=_REDUCE),
                        references=ReferenceIlluminations(self.options.reference_distance),
                        floor=FloorWatch(BackgroundPlate(downscale=_REDUCE)))
            for _ in self.cameras
        ]
        if init is not None:
            for st in states:
                st.W = np.asarray(init, dtype=np.float64)
                st.references.add(st.W)
        return states

    # ---- one camera's share of a frame: locate, classify, query ----------------------
    def prepare(self, states: list[CameraState], images: list[NDArray[np.uint8]]) -> None:
        """A new frame set: each camera's image undistorted and reduced, and its room
        plate started (with another camera's view of the room where it has one)."""
        o = self.options
        for i, (st, image) in enumerate(zip(states, images, strict=True)):
            maps = self._undistort[i]
            if maps is not None:
                image = np.asarray(cv2.remap(image, maps[0], maps[1], cv2.INTER_LINEAR),
                                   np.uint8)
            st.image, st.reduced = image, None
            if o.background_subtraction or self._plate or o.room_plate:
                st.reduced = st.background.reduce(image)
        if not o.room_plate:
            return
        alike: list[NDArray[np.bool_] | None] = [None] * len(states)
        if self.crossview is not None:  # only where no empty room was seen (below)
            alike = self.crossview.room([st.reduced for st in states],  # type: ignore[misc]
                                        [st.torso_box if st.last_box is not None else None
                                         for st in states], _REDUCE,
                                        [not st.floor.plate.ready for st in states])
        for st, same in zip(states, alike, strict=True):
            if st.reduced is not None:  # the cross view stands in for an empty room
                st.room.start(st.reduced, None if st.floor.plate.ready else same)

    def views(self, i: int, st: CameraState, t: float, confirmed: bool, count: int,
              tracked: bool = False) -> list[CameraView]:
        """Camera ``i``'s candidate views of the frame at ``t``, best located first
        (``confirmed``: whether the tracker holds a pose reported).

        With ``count`` 1 the region the search finds (near the shirt's last box
        first, with the gate and the motion mask), committed; else up to ``count``
        regions of the whole frame without them (after that region if ``tracked``),
        each with its own white balance: the tracker :meth:`commit`-s the chosen one.
        """
        o = self.options
        image, reduced = st.image, st.reduced
        assert image is not None, "prepare() the frame first"
        mask = st.background.apply(image, reduced) if o.background_subtraction else None
        if reduced is not None and self._plate:
            st.floor.start(reduced, reduced=True)
        if reduced is not None and self._plate and not confirmed and (count <= 1 or
                                                                  st.last_box is not None):
            # until the first pose the plate learns every frame (a start frame once
            # the tracker has judged its regions: :meth:`learn_room`)
            st.floor.no_shirt()
        if mask is not None and st.last_box is not None and st.torso_box is not None:
            # a still player fades into MOG2: the last torso box stays foreground, the
            # rest of the shirt's box only where the room was seen empty
            bx0, by0, bx1, by1 = st.torso_box
            mask[max(by0, 0) : max(by1, 0), max(bx0, 0) : max(bx1, 0)] = True
            empty = st.room.empty_room
            if empty is not None:
                bx0, by0, bx1, by1 = st.last_box
                sl = (slice(max(by0, 0), max(by1, 0)), slice(max(bx0, 0), max(bx1, 0)))
                mask[sl] |= _full_size(empty, image)[sl]
        room = st.room.foreground() if o.room_plate else None
        full = None
        if room is not None:  # pixels the room plate knows as room are not the player
            full = _full_size(room, image)
            mask = full if mask is None else mask & full
        region = None
        if st.last_box is not None:  # search near the shirt's last position first
            bx0, by0, bx1, by1 = st.last_box
            reach = _SEARCH_REACH * max(bx1 - bx0, by1 - by0)
            region = (int(bx0 - reach), int(by0 - reach), int(bx1 + reach), int(by1 + reach))
        out, st.located = [], False
        if count <= 1 or tracked:
            loc = self.locator.locate(image, mask, region)
            st.located = loc.found
            if count <= 1:
                view = self._view_at(i, st, image, mask, loc, t) if loc.found else None
                if view is not None:
                    self.commit(st, view, confirmed)
                return [] if view is None else [view]
            out = [self._trial_view(i, st, image, mask, loc, t)] if loc.found else []
        # MOG2 holds only what moved: the candidates see all but the known room
        # (the tracker asks MOG2 whether each moved, :meth:`moved`), anywhere in
        # the frame (no gate)
        locs = self.locator.candidates(image, full, count)
        st.located = st.located or bool(locs)
        out += [self._trial_view(i, st, image, full, loc, t, anywhere=True)
                for loc in locs]  # each with the white balance it would choose alone
        return [v for v in out if v is not None]

    def moved(self, st: CameraState, view: CameraView) -> bool | None:
        """Whether MOG2 saw this frame change within ``view``'s classified box (None:
        no background model yet)."""
        if not self.options.background_subtraction:
            return None
        share = st.background.moving(_ids_box(view))
        return None if share is None else share >= _MOVED

    def moved_view(self, i: int, st: CameraState, t: float) -> CameraView | None:
        """Camera ``i``'s shirt-like region found within what the room plate saw a
        player move (:meth:`.plate.RoomPlate.moved_zone`), classified there alone: still
        room in the shirt's colours beside the player is left out. None until a player
        moved, or when no region is found there. Call after :meth:`views` this frame."""
        image = st.image
        zone = st.room.moved_zone() if self.options.room_plate else None
        if image is None or zone is None:
            return None
        mask = _full_size(zone, image)
        room = st.room.foreground()
        known = None if room is None else _full_size(room, image)
        loc = self.locator.locate(image, mask if known is None else mask & known, None)
        if not loc.found:
            return None
        # what moved is often a limb: the still rest of the shirt lies within a window
        r = max(1, int(round(_MOVED_REACH * loc.scale)))
        mask = cv2.dilate(mask.astype(np.uint8), cv2.getStructuringElement(
            cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))) > 0
        if known is not None:  # pixels the room plate knows as room are not the player
            mask &= known
        return self._trial_view(i, st, image, mask, loc, t, anywhere=True)

    def moved_share(self, st: CameraState, view: CameraView | None) -> float:
        """The share of ``view``'s shirt box lying where the room plate saw a player move
        (:meth:`.plate.RoomPlate.moved_zone`; 0 before anything moved, or without a
        view): how much of the region is a player rather than still room."""
        if view is None or not self.options.room_plate:
            return 0.0
        return _box_share(st.room.moved_zone(), view)

    def seen_empty(self, st: CameraState, view: CameraView) -> bool:
        """Whether the room plate learned most of ``view``'s shirt box on frames without
        a player (:attr:`.plate.RoomPlate.empty_room`): a region nothing moved in
        there was room while the tracker watched, not a player who came and stood."""
        return _box_share(st.room.empty_room, view) >= _EMPTY_ROOM

    def commit(self, st: CameraState, view: CameraView, confirmed: bool) -> None:
        """``view`` (of :meth:`views`) is the shirt: its camera keeps what it chose."""
        if view.state is not None:
            st.W, st.last_fraction = view.state.W, view.state.last_fraction
            st.references = view.state.references
            view.state = None
        if self._plate:
            st.floor.shirt_at(_ids_box(view), confirmed=confirmed)

    def _trial_view(self, i: int, st: CameraState, image: NDArray[np.uint8],
                    mask: NDArray[np.bool_] | None, loc: ShirtLocation, t: float,
                    anywhere: bool = False) -> CameraView | None:
        """:meth:`_view_at` on a copy of ``st`` (its own white balance; ``anywhere``:
        without the gate and the last box), kept in the view's ``state`` for :meth:`commit`."""
        trial = dataclasses.replace(st, references=copy.deepcopy(st.references))
        if anywhere:
            trial.gate = trial.last_box = None
        view = self._view_at(i, trial, image, mask, loc, t)
        if view is not None:
            view.state = trial
        return view

    def _view_at(self, i: int, st: CameraState, image: NDArray[np.uint8],
                 mask: NDArray[np.bool_] | None, loc: ShirtLocation, t: float
                 ) -> CameraView | None:
        """Crop, classification and database match of the shirt located at ``loc``."""
        o = self.options
        gate = self._gate_box(st, t)
        if gate is not None and not (gate[0] <= loc.x <= gate[2] and gate[1] <= loc.y <= gate[3]):
            return None  # not where the shirt can be: leave W and the plate alone
        h, w = image.shape[:2]
        x0, y0, x1, y1 = loc.box(o.crop_margin)
        if st.last_box is not None:  # the shirt is near where it was a frame ago
            bx0, by0, bx1, by1 = st.last_box
            x0, y0, x1, y1 = min(x0, bx0), min(y0, by0), max(x1, bx1), max(y1, by1)
        x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, w), min(y1, h)
        if x1 - x0 < 8 or y1 - y0 < 8:
            return None
        scale = min(1.0, o.work_size / max(x1 - x0, y1 - y0))
        cw, chh = max(1, round((x1 - x0) * scale)), max(1, round((y1 - y0) * scale))
        crop = np.asarray(cv2.resize(image[y0:y1, x0:x1], (cw, chh),
                                     interpolation=cv2.INTER_AREA), np.uint8)
        cmask = None
        if mask is not None:
            cmask = cv2.resize(mask[y0:y1, x0:x1].astype(np.uint8), (cw, chh),
                               interpolation=cv2.INTER_NEAREST) > 0
        if self._plate and o.plate_mask:  # MOG2 has the player's last box as foreground
            pm = st.floor.crop_foreground((x0, y0, x1, y1), (cw, chh))
            if pm is not None:
                alone = len(self.cameras) <= o.plate_mask_alone_cameras
                cmask = pm if cmask is None or alone else cmask & pm
        window = CropWindow(float(x0), float(y0), float(cw) / (x1 - x0), cw, chh)
        gated = self._gate_mask(st, window, t)
        if gated is not None:
            cmask = gated if cmask is None else cmask & gated
        # the paper's "supposedly foreground": masked pixels inside the located window
        fg = np.zeros((chh, cw), bool)
        half = 0.5 * loc.scale * window.scale
        cx, cy = (loc.x - x0) * window.scale, (loc.y - y0) * window.scale
        fg[max(0, int(cy - half)) : int(cy + half), max(0, int(cx - half)) : int(cx + half)] = True
        if cmask is not None:
            fg &= cmask
        W, ids = classify_camera(st, crop, cmask, fg, self.color_model, self.noise_model, o)
        ids = clean_ids(ids, o.blob_fraction, o.blob_attach, o.sleeve_attach)
        counts = np.bincount(ids.ravel(), minlength=NUM_COLORS + 1)[1:]
        min_px = max(4, int(o.min_color_fraction * ids.size))
        if int(np.count_nonzero(counts >= min_px)) < o.min_colors:
            return None
        box = nonzero_box(ids)
        assert box is not None
        lo, hi = np.array(box[:2], float), np.array(box[2:], float) + 1.0
        extent = float(np.max(hi - lo))
        view = CameraView(i, window, crop, cmask, W, ids, extent)
        facing = None
        if self.options.facing_turn < 180:  # no track: a player who faces the camera
            facing = _TOWARDS_CAMERA if self.facing is None else self.cameras[i].R @ self.facing
        make_query(view, self.database, lo, hi, facing,
                   float(np.cos(np.radians(self.options.facing_turn))))
        return view

    def _gate_box(self, st: CameraState, t: float) -> tuple[float, float, float, float] | None:
        """Image box where the shirt can be at ``t`` (see :meth:`_gate_mask`)."""
        if st.gate is None:
            return None
        gx0, gy0, gx1, gy1 = st.gate
        m = self.options.gate_speed * max(t - st.gate_t, 1 / 30) * max(gx1 - gx0, gy1 - gy0)
        return (gx0 - m, gy0 - m, gx1 + m, gy1 + m)

    def _gate_mask(self, st: CameraState, window: CropWindow,
                   t: float) -> NDArray[np.bool_] | None:
        """Crop mask of where the shirt can be at ``t``: the last reported shirt's box
        grown by ``gate_speed`` times its size per second since (None: no pose
        reported within ``gate_time``)."""
        box = self._gate_box(st, t)
        if box is None:
            return None
        a = window.to_crop(np.array(box[:2], float))
        b = window.to_crop(np.array(box[2:], float))
        out = np.zeros((window.height, window.width), bool)
        out[max(0, int(a[1])): max(0, int(np.ceil(b[1]))),
            max(0, int(a[0])): max(0, int(np.ceil(b[0])))] = True
        return out

    # ---- with the pose's render: correspondences, reclassification, W refit ----------
    def observed_by_color(self, renderer: PoseRenderer, view: CameraView,
                          rend: RenderedPose) -> Observed:
        """Step-2 correspondences: each color's pixels go to its larger rendered patch."""
        lut = np.zeros(NUM_COLORS + 1, np.uint8)
        for k, pats in enumerate(renderer.color_patches):
            lut[k + 1] = max(pats, key=lambda p: rend.stats.count[p])
        st, _ = patch_stats(lut[view.ids])
        return st.count, st.centroid

    def refine_classification(self, renderer: PoseRenderer, view: CameraView,
                              rend: RenderedPose) -> Observed:
        """Step 3: reclassify with the pose prior, then split colors into patches."""
        o = self.options
        C = prior_penalty_slope(o.prior_strength, view.shirt_scale, view.W, o.prior_gain_power)
        min_px = max(3, int(o.min_patch_fraction * view.ids.size))
        dists, patch, color = renderer.patch_distances(rend, min_px)
        cls, owner = self.noise_model.classify_near(view.crop, view.W, o.prior_threshold,
                                                    view.mask, dists, patch, color, C)
        ids = clean_ids(cls, o.blob_fraction, o.blob_attach, o.sleeve_attach)
        view.ids = ids
        # a kept pixel keeps its color (clean_ids only drops pixels): its patch is the
        # one of that color nearest to it
        st, _ = patch_stats(np.where(ids > 0, owner, np.uint8(0)))
        return st.count, st.centroid

    def refit_white_balance(self, st: CameraState, view: CameraView,
                            rend: RenderedPose) -> None:
        """Step 5: ``W*`` from the pixels where the final pose's render (away from
        patch edges) and the classification agree, damped by ``wb_smoothing``;
        stored in ``st`` if it is new."""
        colors = rend.color_ids()
        inner = cv2.erode((colors > 0).astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
        keep = inner & (view.ids == colors)
        if view.mask is not None:
            keep &= view.mask
        ids = np.where(keep, colors, 0).astype(np.uint8)
        W = white_balance_from_ids(view.crop, ids, self.color_model, prior=view.W,
                                   min_colors=4, ridge_fraction=0.05)
        if W is None:
            return
        a = self.options.wb_smoothing
        st.W = a * view.W + (1.0 - a) * W
        st.references.add(st.W)

    # ---- after the frame: what each camera keeps ---------------------------------------
    def remember_shirt(self, states: list[CameraState], renderer: PoseRenderer,
                       q: NDArray[np.float64], t: float) -> None:
        """After a pose is reported: every camera's gate and search box become the
        box of the pose's shirt projected there."""
        mesh = renderer.mesh
        cached = self._shirt_vertices
        if cached is None or cached[0] is not mesh:  # a mesh's indices never change
            cached = self._shirt_vertices = (
                mesh, np.unique(mesh.faces[mesh.face_part > 0]),
                np.unique(mesh.faces[np.isin(mesh.face_part, _TORSO_PATCHES)]))
        every = renderer.vertices(q).astype(np.float64)
        verts, torso = every[cached[1]], every[cached[2]]
        for cam, st in zip(self.cameras, states, strict=True):
            st.torso_box = _image_box(cam, torso)
            box = _image_box(cam, verts) or (0, 0, 0, 0)  # none in front: an empty box
            x0, y0 = max(box[0], 0), max(box[1], 0)
            x1, y1 = min(box[2], cam.width), min(box[3], cam.height)
            if x1 - x0 < 4 or y1 - y0 < 4:
                st.gate = None
                continue
            st.gate, st.gate_t = (x0, y0, x1, y1), t
            pad = 0.15 * max(x1 - x0, y1 - y0)
            st.last_box = (int(x0 - pad), int(y0 - pad), int(x1 + pad), int(y1 + pad))

    def learn_room(self, states: list[CameraState], renderer: PoseRenderer,
                   q: NDArray[np.float64] | None, ever_reported: bool,
                   held: list[CameraView] | None = None) -> None:
        """Every camera's room plate learns what lies outside the dilated silhouette
        of the pose ``q`` just reported; without a pose nothing, except before the
        first pose in a camera that found no shirt (the empty room). ``held``: on a
        start frame, regions that fit a shirt but never moved (maybe a still player):
        no plate learns their player's region as room."""
        o = self.options
        skip: list[NDArray[np.bool_] | None] = []
        for i, cam in enumerate(self.cameras):
            still = [_player_region(v, cam) for v in held or [] if v.index == i]
            skip.append(np.logical_or.reduce(still) if still else None)
        if held is not None and not ever_reported and self._plate:
            for st, sk in zip(states, skip, strict=True):
                if sk is None:  # a start frame (see :meth:`views`) without a still shirt
                    st.floor.no_shirt()
        if not o.room_plate:
            return
        verts = None if q is None else renderer.vertices(q)
        for i, (cam, st) in enumerate(zip(self.cameras, states, strict=True)):
            if verts is None:
                st.room.learn(None, everywhere=not ever_reported and not st.located,
                              ambiguous=skip[i])
                continue
            h, w = cam.height // _REDUCE, cam.width // _REDUCE
            s = 0.5 / _REDUCE  # rendered at half the plate's resolution, then grown
            win = CropWindow(0.0, 0.0, s, max(1, round(cam.width * s)),
                             max(1, round(cam.height * s)))
            sil = renderer.silhouette(verts, cam, win)
            box = nonzero_box(sil)
            if box is None:
                st.room.learn(None)
                continue
            r = max(2, int(round(self.options.room_margin
                                 * max(box[3] - box[1], box[2] - box[0]))))
            grown = cv2.dilate(sil, cv2.getStructuringElement(cv2.MORPH_ELLIPSE,
                                                              (2 * r + 1, 2 * r + 1)))
            person = cv2.resize(grown, (w, h), interpolation=cv2.INTER_NEAREST) > 0
            st.room.learn(person)
