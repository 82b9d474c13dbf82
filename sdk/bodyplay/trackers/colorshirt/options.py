"""Options of the color-shirt tracker (a frozen dataclass validated on creation)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bodyplay.body.shapes import BODY_SHAPES
from bodyplay.errors import ConfigError
from bodyplay.overrides import options_with_overrides
from bodyplay.trackers.colorshirt.bodyselect import ARM_SCALES
from bodyplay.trackers.colorshirt.locate import LocateOptions

__all__ = ["ColorShirtOptions", "options_with_overrides"]


@dataclass(frozen=True)
class ColorShirtOptions:
    """Everything that tunes the color-shirt tracker; defaults follow the paper.

    * ``adaptive_white_balance``: refit ``W`` every frame and keep reference
      illuminations (paper steps 1 and 5); off = ``W`` from the first frame forever.
    * ``pose_prior``: pose-assisted reclassification and the IK priors towards the
      blended and previous poses (steps 3 and 4); off = plain centroid IK.
      Both off is the paper's comparison baseline (its predecessor, [WP09]).
    * ``database_size`` poses in the database (paper: 80,000), cached in
      ``database_cache`` (default ``~/.cache/bodyplay``).
    * ``threshold`` (T = 3) and ``prior_threshold`` (T = 5) of the classifier,
      ``prior_strength`` the 6 of ``C = 6 / s`` (12 here: with the paper's 6 a
      pixel of a patch's colour up to 0.8 shirt sizes from it counted, and rooms
      in shirt colours pulled the patches), ``retry_fraction`` the 40% test.
      ``prior_gain_power``: ``C`` is multiplied by ``g ** prior_gain_power``, ``g``
      the overall gain of the white balance (``det(W) ** (1/3)``, at least 1):
      an image the balance must amplify is noisier, so the pose prior counts more
      (beyond the paper; 0 = the paper).
    * ``wb_smoothing``: weight of the previous ``W`` when the refitted ``W*`` replaces it.
    * ``background_subtraction``: MOG2 foreground mask for search and classification.
    * ``work_size``: largest side (px) of the working crop the shirt is classified in;
      ``crop_margin`` its size relative to the located window; ``blob_fraction``:
      classified blobs smaller than this fraction of the largest are dropped, unless
      they lie within ``blob_attach`` of the shirt's extent of the largest (an arm
      held beside the body, cut off from the torso by its white shoulder cap);
      ``sleeve_attach``: a blob in two sleeve colors is kept within this larger
      fraction of the raised upper arms when it lies over the shirt (both forearms
      raised together over the head, which the head separates from the upper arms;
      beyond the paper).
    * ``min_colors``, ``min_color_fraction``, ``max_mismatch``: when a camera counts
      as seeing the shirt (else the frame is lost); ``min_patch_fraction``: the least
      share of the crop a patch must cover to become an IK anchor.
    * ``white_std_scale``: the white patches' (right shoulder cap, left flank)
      centroid constraints count with this many times the standard deviation of
      the others (beyond the paper, which weighs every patch alike): white is the
      one shirt color that bright background (walls, tile joints) and highlights
      share, and stray white pixels at the shirt's outline pull those centroids
      (1 = the paper).
    * ``measurement_noise``: std (RGB units) of the camera's measurement error that
      a strong white balance amplifies; the classifier widens every color's Gaussian
      by the amplified part (beyond the paper, which uses the fitted covariances as
      they are: 0). Measured on the benchmark: 6 cuts the dim-light error by a fifth;
      10 and more let dark background into the dark colors under dim light.
    * ``max_speed``: fastest plausible root speed (m/s); a fit further than
      ``0.25 m + max_speed * dt`` from the pose reported within the last second is
      reported lost rather than as a jump across the room.
    * ``gate_time``/``gate_speed``: the classification keeps only pixels within
      ``gate_speed`` times the shirt's size per second elapsed (at least a 30th of
      a second) of the shirt's box in the last pose reported, for ``gate_time``
      seconds after it; the search for the shirt starts there too, and the whole
      frame is searched after.
    * ``initial_white_balance``: a 3x3 ``W`` from scribbles (None = automatic).
    * ``color_model``/``prior_model``: JSON files replacing the shipped models.
    * ``body``: body-shape preset of the generic skeleton and mesh (a name of
      ``BODY_SHAPES``), or ``"auto"``: every preset is fitted on the first
      ``body_selection_frames`` frames with a pose and the one whose patch anchors
      reproject best is kept; then its arm-length variants (``ARM_SCALES``, 0.84-1
      times its arms) are compared the same way over ``arm_selection_frames``
      frames (0 = keep the preset's arms). Of the arm lengths, the shortest whose
      mean residual is within ``arm_tolerance`` (a fraction) of the best wins: an
      arm too long still reprojects well by leaning in depth (one camera cannot see
      the lean at all), an arm too short cannot reach the observed sleeves.
      With one camera, a start-up frame counts towards the preset only when the
      floor cue found the feet no further apart in depth than
      ``body_choice_max_stagger`` (m): one view cannot tell a small person near
      from a tall one far, the feet are its only measure of distance, and in a
      staggered stance they do not say where the pelvis is. After twice
      ``body_selection_frames`` frames that do not count, the reference preset
      ``m`` is kept (``inf``: every frame counts).
    * ``floor_cue``: when one camera sees the shirt, a prior on the root's depth
      from where the feet meet the floor (beyond the paper; needs a background
      plate, learned on empty-room frames before the shirt first appears);
      ``floor_offset`` (m) is added to the depth of the root above the feet (the
      nearest pixel of a foot, the lowest in the image, lies in front of the
      pelvis: 11 cm on the validation set's tune half), ``floor_std`` (m) the
      reading's standard deviation.
    * ``depth_accel``: with one camera the floor readings and the body's size
      (the depth at which the skeleton's lengths project as large as the shirt
      looks) are combined over time by one extended Kalman filter on the root's
      depth, its speed and the player's size relative to the reference body
      (:class:`.depth.RootDepthFilter`); this is its acceleration std (m/s²).
      ``shirt_depth_std`` is the std of the shirt's reading as a fraction of the
      depth, ``body_scale_std`` the prior std of the player's size relative to
      the reference body (what a missing floor cue costs, as a fraction of the
      depth); readings more than 3 standard deviations from the prediction
      (feet off the floor, a wrong fit) are left out. The IK holds the root at
      the filter's depth with the std ``depth_pin_std`` (m; the filter already
      weighed the shirt's size) once the feet told it; the filter's std,
      combined with how far the reported root departs from the filter's depth,
      is reported per frame as ``depth_std``.
    * ``stance_cue``: the filter also reads the root's height on the ray through
      where the fit sees it: a player standing on the floor holds the root at
      the legs' length, which ties the player's size to the depth without the
      feet (the camera's calibrated height is the ruler) and tells when the feet
      leave the floor (their floor readings are then left out). Off by default:
      on the validation report half every one-camera median is 0.3-4 cm better
      without it, and on a jumping clip (13_29 after an empty room) the feet's
      depth with it is 8.3 cm off against 7.1 without (docs/colorshirt.md).
    * ``head_cue``: in every camera, the head found in the plate's foreground above
      the collar constrains the head joint in the IK (beyond the paper; needs the
      plate as ``floor_cue`` does); ``head_offset`` (m) is how far the visible head's
      centre lies above the joint, ``head_std`` (m) the constraint's standard
      deviation.
    * ``arm_search``: each arm of the placed blend is replaced by the arm
      configuration (of ``arm_library``, spread over the database's arms) whose
      shirt points best match the classified pixels in every camera, by a
      truncated chamfer distance (``arm_tau`` shirt sizes);
      the best few are blended with weights ``exp(-cost / arm_temperature)``
      (beyond the paper; see :mod:`.armsearch`). ``arm_shortlist``: how many
      candidates per arm the model-to-image cost passes on to the pairwise stage,
      which also charges observed arm pixels left unexplained.
    * ``arm_search_one_camera``: run the arm search when a single camera sees the
      shirt too, once the body is chosen. One view cannot tell an arm's lean in
      depth, so each candidate also pays ``arm_depth_pull`` per (10 cm)² of mean
      squared distance between its elbow and wrist and the blend's (relative to
      the neck): the image picks the arm's outline, the database blend its depth.
    * ``plate_mask``: once the background plate is learned (``floor_cue`` or
      ``head_cue``, from empty-room frames before the shirt appears), only pixels
      that differ from it are classified. MOG2's mask counts the player's last box
      as foreground (so a player who stands still does not fade), which leaves
      the background right next to the shirt unmasked; under dim light the
      classifier took dark floor there for the dark sleeve colors. With at most
      ``plate_mask_alone_cameras`` cameras the plate's mask replaces MOG2's
      (which then only narrows the search): MOG2 absorbs an arm held still once
      one frame missed it, and with one camera no other view makes up for it.
    * ``room_plate``: learn the room from what the player uncovers
      (:class:`.plate.RoomPlate`: still pixels outside the reported pose's
      silhouette, grown by ``room_margin`` times its size, after a good fit) and
      classify only pixels unlike it or not yet learned; works when the player
      starts in view.
    * ``good_residual``: a fit whose patch anchors reproject within this many shirt
      sizes on average is *good*: only good fits teach the room plate, judge the
      body presets, and override the speed gate (two good fits in a row that agree
      with each other take over from a pose reported before them that they are
      too far from).
    * ``start_candidates``: with any number of cameras, whenever no camera tracks
      the shirt (the start, or after ``gate_time`` without a pose), the
      histogram search keeps up to this many shirt-like regions
      per camera, each classified without MOG2's mask. Every combination of one
      region (or none) per camera is a hypothesis; it counts only if MOG2 saw
      motion in each of its regions (with ``background_subtraction``) and its fit
      is plausible with the root within ``start_root_band`` (fractions of the
      body's standing pelvis height: the player starts upright); the track
      starts on the one with the most cameras, then the lowest residual. A
      poster or a fruit bowl more colorful than the shirt does not move and fits
      no upright torso that both cameras see; with one camera the motion test
      and the upright root (on the shirt's-size depth) do the choosing, the
      region a track would find (searched with the motion mask) is offered too,
      the fit must anchor 6 of the 20 patches and the one anchoring the most
      starts (then the lowest residual), and a region that never moved starts
      only if its fit anchors 8 (a player waiting still; else it is held, not
      learned as room). 1: the most colorful region only.
    * ``start_agreement_frames``: with several cameras, a track that one camera
      alone started does not lock the others: each frame its tracked view is
      combined with every other camera's regions (where a track would search
      there, and its whole frame's candidates); the first plausible upright
      hypothesis with more cameras re-starts the track from scratch. Until then
      the lone camera's pose (its depth the shirt's size alone) is tracked but
      not reported. After this many frames without one, it is reported and
      gates every camera as a track does (0: at once).
    """

    adaptive_white_balance: bool = True
    pose_prior: bool = True
    database_size: int = 20_000
    database_cache: str | None = None
    threshold: float = 3.0
    prior_threshold: float = 5.0
    prior_strength: float = 12.0
    prior_gain_power: float = 2.0
    retry_fraction: float = 0.4
    reference_distance: float = 0.5
    wb_smoothing: float = 0.5
    background_subtraction: bool = True
    work_size: int = 128
    crop_margin: float = 2.6
    blob_fraction: float = 0.15
    blob_attach: float = 0.1
    sleeve_attach: float = 0.2
    min_colors: int = 4
    min_color_fraction: float = 0.002
    min_patch_fraction: float = 0.0015
    white_std_scale: float = 3.0
    measurement_noise: float = 6.0
    max_speed: float = 5.0
    gate_time: float = 0.34
    gate_speed: float = 7.5
    max_mismatch: float = 0.5
    initial_white_balance: tuple[tuple[float, float, float], ...] | None = None
    color_model: str | None = None
    prior_model: str | None = None
    body: str = "auto"
    body_selection_frames: int = 20
    arm_selection_frames: int = 10
    arm_tolerance: float = 0.1
    arm_scales: tuple[float, ...] = ARM_SCALES
    body_choice_max_stagger: float = 0.15
    floor_cue: bool = True
    floor_offset: float = 0.11
    floor_std: float = 0.05
    depth_accel: float = 3.0
    shirt_depth_std: float = 0.15
    body_scale_std: float = 0.06
    depth_pin_std: float = 0.01
    stance_cue: bool = False
    head_cue: bool = True
    head_offset: float = 0.02
    head_std: float = 0.02
    arm_search: bool = True
    arm_library: int = 1000
    arm_tau: float = 0.15
    arm_temperature: float = 0.02
    arm_shortlist: int = 24
    arm_search_one_camera: bool = True
    arm_depth_pull: float = 0.01
    plate_mask: bool = True
    room_plate: bool = True
    room_margin: float = 0.1
    good_residual: float = 0.09
    start_candidates: int = 3
    start_root_band: tuple[float, float] = (0.6, 1.3)
    start_agreement_frames: int = 30
    plate_mask_alone_cameras: int = 1
    locate: LocateOptions = field(default_factory=LocateOptions)

    def __post_init__(self) -> None:
        if self.database_size < 20:
            raise ConfigError("database_size must be at least 20 poses (the paper uses 80,000)")
        if not 0 < self.threshold <= self.prior_threshold:
            raise ConfigError("need 0 < threshold <= prior_threshold (paper: 3 and 5)")
        if not 0 <= self.retry_fraction <= 1:
            raise ConfigError("retry_fraction must be within 0..1 (paper: 0.4)")
        if self.reference_distance <= 0 or self.prior_strength < 0:
            raise ConfigError("reference_distance must be > 0 and prior_strength >= 0")
        if not 24 <= self.work_size <= 640:
            raise ConfigError("work_size must be between 24 and 640 pixels")
        if self.crop_margin < 1.0:
            raise ConfigError("crop_margin must be at least 1 (the located window itself)")
        for name, value in (("wb_smoothing", self.wb_smoothing),
                            ("blob_fraction", self.blob_fraction),
                            ("blob_attach", self.blob_attach),
                            ("sleeve_attach", self.sleeve_attach),
                            ("min_color_fraction", self.min_color_fraction),
                            ("min_patch_fraction", self.min_patch_fraction)):
            if not (np.isfinite(value) and 0 <= value < 1):
                raise ConfigError(f"{name} must be a fraction within [0, 1), got {value}")
        if not 1 <= self.min_colors <= 10:
            raise ConfigError("min_colors must be between 1 and 10")
        if self.start_candidates < 1:
            raise ConfigError("start_candidates must be at least 1 (default 3)")
        if not 0 <= self.start_agreement_frames <= 10_000:
            raise ConfigError("start_agreement_frames must be between 0 (a lone camera's "
                              "start gates the others at once) and 10000 (default 30)")
        lo, hi = self.start_root_band
        if not 0 <= lo < hi:
            raise ConfigError("start_root_band must be (low, high) fractions of the standing "
                              "pelvis height with 0 <= low < high (default (0.6, 1.3))")
        if not 0 < self.max_mismatch <= 1:
            raise ConfigError("max_mismatch must be within (0, 1]")
        if self.body != "auto" and self.body not in BODY_SHAPES:
            raise ConfigError(f"unknown body preset {self.body!r}; choose 'auto' or one of "
                              f"{', '.join(BODY_SHAPES)}")
        if not 0 <= self.measurement_noise <= 9:
            raise ConfigError("measurement_noise must be within 0..9 RGB units (default 6; "
                              "larger values let background into the dark shirt colors)")
        if not (np.isfinite(self.gate_time) and self.gate_time > 0):
            raise ConfigError("gate_time must be a positive time in seconds (default 0.34)")
        if not (np.isfinite(self.gate_speed) and self.gate_speed > 0):
            raise ConfigError("gate_speed must be a positive number of shirt sizes per second "
                              "(default 7.5)")
        if not (np.isfinite(self.max_speed) and self.max_speed > 0):
            raise ConfigError("max_speed must be a positive speed in m/s (default 5)")
        if not 1 <= self.body_selection_frames <= 300:
            raise ConfigError("body_selection_frames must be between 1 and 300")
        if not 0 <= self.arm_selection_frames <= 300:
            raise ConfigError("arm_selection_frames must be between 0 (off) and 300")
        if not (np.isfinite(self.prior_gain_power) and 0.0 <= self.prior_gain_power <= 4.0):
            raise ConfigError("prior_gain_power must be within 0 (the paper's C = 6 / s) and 4 "
                              "(default 2)")
        if not (np.isfinite(self.white_std_scale) and 1.0 <= self.white_std_scale <= 20.0):
            raise ConfigError("white_std_scale must be within 1 (white patches count like "
                              "the others, as in the paper) and 20 (default 3)")
        scales = tuple(self.arm_scales)
        if (not scales or not all(np.isfinite(a) and 0.5 <= a <= 1.5 for a in scales)
                or not any(abs(a - 1.0) < 1e-9 for a in scales)):
            raise ConfigError("arm_scales must be arm-length factors within 0.5..1.5 that "
                              f"include 1 (the preset's own arms), got {self.arm_scales}")
        if not (np.isfinite(self.arm_tolerance) and 0.0 <= self.arm_tolerance <= 0.5):
            raise ConfigError("arm_tolerance must be within 0 (the best residual wins) and "
                              "0.5 (default 0.05)")
        if not (np.isfinite(self.floor_offset) and abs(self.floor_offset) <= 0.5):
            raise ConfigError("floor_offset must be within -0.5..0.5 m (default 0.11)")
        if not (np.isfinite(self.depth_accel) and 0.0 < self.depth_accel <= 50.0):
            raise ConfigError("depth_accel must be within 0 and 50 m/s^2 (default 3)")
        for name, value, hi in (("shirt_depth_std", self.shirt_depth_std, 1.0),
                                ("body_scale_std", self.body_scale_std, 0.5),
                                ("depth_pin_std", self.depth_pin_std, 1.0)):
            if not (np.isfinite(value) and 0.001 <= value <= hi):
                raise ConfigError(f"{name} must be within 0.001 and {hi} (default "
                                  f"{getattr(ColorShirtOptions, name)})")
        if not (np.isfinite(self.floor_std) and 0.005 <= self.floor_std <= 1.0):
            raise ConfigError("floor_std must be within 0.005..1 m (default 0.05)")
        if not (np.isfinite(self.head_offset) and abs(self.head_offset) <= 0.2):
            raise ConfigError("head_offset must be within -0.2..0.2 m (default 0.02)")
        if not (np.isfinite(self.head_std) and 0.002 <= self.head_std <= 1.0):
            raise ConfigError("head_std must be within 0.002..1 m (default 0.02)")
        if not 1 <= self.arm_library <= 100_000:
            raise ConfigError("arm_library must be between 1 and 100,000 arm configurations "
                              "(default 1000)")
        if not (np.isfinite(self.arm_temperature) and 0 <= self.arm_temperature <= 1):
            raise ConfigError("arm_temperature must be within 0 (take the best arm) and 1 "
                              "(default 0.02)")
        if not 1 <= self.arm_shortlist <= 200:
            raise ConfigError("arm_shortlist must be between 1 and 200 candidates per arm "
                              "(default 24)")
        if not self.body_choice_max_stagger > 0.0:  # NaN fails too
            raise ConfigError("body_choice_max_stagger must be a positive distance in metres "
                              "(default 0.15; inf lets every one-camera frame judge the body)")
        if not (np.isfinite(self.room_margin) and 0.0 <= self.room_margin <= 1.0):
            raise ConfigError("room_margin must be within 0..1 of the silhouette's size "
                              "(default 0.1)")
        if not (np.isfinite(self.good_residual) and 0.0 < self.good_residual <= 1.0):
            raise ConfigError("good_residual must be within (0, 1] shirt sizes (default 0.09)")
        if not 0 <= self.plate_mask_alone_cameras <= 16:
            raise ConfigError("plate_mask_alone_cameras must be between 0 (always both masks) "
                              "and 16 (default 1: a one-camera rig masks with the plate alone)")
        if not (np.isfinite(self.arm_depth_pull) and 0.0 <= self.arm_depth_pull <= 10.0):
            raise ConfigError("arm_depth_pull must be within 0 (no pull towards the blend's "
                              "arms) and 10 (default 0.01)")
        if not (np.isfinite(self.arm_tau) and 0.01 <= self.arm_tau <= 2.0):
            raise ConfigError("arm_tau must be within 0.01..2 shirt sizes (default 0.15)")
        if self.initial_white_balance is not None:
            W = np.asarray(self.initial_white_balance, dtype=float)
            if W.shape != (3, 3) or not np.all(np.isfinite(W)):
                raise ConfigError("initial_white_balance must be a finite 3x3 matrix")
