"""Options of the color-shirt tracker (a frozen dataclass validated on creation)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bodyplay.body.shapes import BODY_SHAPES
from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types
from bodyplay.overrides import options_with_overrides
from bodyplay.trackers.colorshirt.bodyselect import ARM_SCALES
from bodyplay.trackers.colorshirt.locate import LocateOptions

__all__ = ["ColorShirtOptions", "options_with_overrides"]


@dataclass(frozen=True)
class ColorShirtOptions:
    """Everything that tunes the color-shirt tracker; defaults follow the paper.

    One line per option here; what each does in docs/colorshirt.md ("Options"),
    why it exists, with the figures that chose the defaults, in
    docs/colorshirt-history.md ("Options in detail").

    * ``adaptive_white_balance``: refit ``W`` every frame, keep reference
      illuminations (paper steps 1 and 5); ``pose_prior``: pose-assisted
      reclassification and IK priors (steps 3 and 4). Both off: the paper's baseline.
    * ``database_size`` poses (paper: 80,000), cached in ``database_cache``;
      ``database_yaw`` (degrees): how far from facing the camera they turn;
      ``facing_turn`` (degrees): while tracking, only poses facing within this of
      the last pose are searched (180: all).
    * ``threshold``/``prior_threshold``: the classifier's ``T`` (3 and 5);
      ``prior_strength``: the 6 of ``C = 6 / s``; ``prior_gain_power``: ``C`` grows
      with the white balance's gain to this power (a noisier image); ``retry_fraction``:
      the 40% test; ``reference_distance``: when a new reference ``W`` is stored;
      ``wb_smoothing``: weight of the previous ``W``.
    * ``background_subtraction``: MOG2 foreground mask for search and classification.
    * ``work_size``/``crop_margin``: the working crop; ``blob_fraction``,
      ``blob_attach``, ``sleeve_attach``: which classified blobs are kept.
    * ``min_colors``, ``min_color_fraction``, ``max_mismatch``: when a camera sees
      the shirt; ``min_patch_fraction``: the least share of a patch to anchor the IK.
    * ``white_std_scale``: the white patches' constraints count with this many times
      the others' std (white is what bright background shares).
    * ``measurement_noise``: RGB std of camera noise that a strong ``W`` amplifies;
      the classifier widens every color's Gaussian by it.
    * ``max_speed`` (m/s): a fit further than ``0.25 m + max_speed * dt`` from the
      last reported pose is reported lost; ``gate_time``/``gate_speed``: how long and
      how widely the last reported shirt's box gates classification and search.
    * ``initial_white_balance``: a 3x3 ``W`` from scribbles (None = automatic);
      ``color_model``/``prior_model``: JSON files replacing the shipped models.
    * ``body``: a preset of ``BODY_SHAPES`` or ``"auto"`` (chosen over
      ``body_selection_frames`` frames, then the arm lengths ``arm_scales`` over
      ``arm_selection_frames``, the shortest within ``arm_tolerance`` of the best);
      ``body_choice_max_stagger`` (m): with one camera, a frame judges the presets
      only when the feet stand no further apart in depth.
    * ``floor_cue``: the root's depth from where the feet meet the floor
      (``floor_offset``, ``floor_std``, m); ``depth_accel``, ``shirt_depth_std``,
      ``body_scale_std``, ``depth_pin_std``: the one-camera root-depth filter
      (:class:`.depth.RootDepthFilter`) and how tightly the IK holds its depth;
      ``turn_std`` (rad): how tightly a one-camera rig's fits hold the trunk's turn
      about the vertical at the blend's (0: as loosely as the other rotations).
    * ``head_cue``: the head above the collar anchors the head joint
      (``head_offset``, ``head_std``, m).
    * ``arm_search``: each arm chosen from ``arm_library`` arms by a truncated
      chamfer (``arm_tau``), blended by ``arm_temperature``, ``arm_shortlist`` per
      arm to the pairwise stage (:mod:`.armsearch`); with one camera each candidate
      pays ``arm_depth_pull`` for leaving the blend's depth.
    * ``plate_mask``: classify only pixels unlike the learned background plate (it
      replaces MOG2's mask with at most ``plate_mask_alone_cameras`` cameras);
      ``room_plate``: learn the room from what the player uncovers (silhouette grown
      by ``room_margin``), so a player may start in view; ``cross_view``: with two
      cameras or more, pixels another camera shows as the same room are room too.
    * ``good_residual``: a fit reprojecting within this many shirt sizes is *good*
      (teaches the room plate, judges the body, overrides the speed gate).
    * ``start_candidates``: shirt-like regions per camera tried when nothing is
      tracked, a start's root within ``start_root_band`` of the standing pelvis
      height; ``start_agreement_frames``: how long one camera alone of several (its
      start, or a track the others lost) waits for another to agree, unreported.
    * ``locate``: the histogram search (:class:`.locate.LocateOptions`).
    """

    adaptive_white_balance: bool = True
    pose_prior: bool = True
    database_size: int = 20_000
    database_cache: str | None = None
    database_yaw: float = 80.0
    facing_turn: float = 180.0
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
    turn_std: float = 0.0
    head_cue: bool = True
    head_offset: float = 0.02
    head_std: float = 0.02
    arm_search: bool = True
    arm_library: int = 1000
    arm_tau: float = 0.15
    arm_temperature: float = 0.02
    arm_shortlist: int = 24
    arm_depth_pull: float = 0.01
    plate_mask: bool = True
    room_plate: bool = True
    cross_view: bool = True
    room_margin: float = 0.1
    good_residual: float = 0.09
    start_candidates: int = 3
    start_root_band: tuple[float, float] = (0.6, 1.3)
    start_agreement_frames: int = 30
    plate_mask_alone_cameras: int = 1
    locate: LocateOptions = field(default_factory=LocateOptions)

    def __post_init__(self) -> None:
        check_option_types(self)
        for name, lo, hi, lo_open, unit in _RANGES:
            value = getattr(self, name)
            finite = isinstance(value, int) or bool(np.isfinite(value))  # ints of any size
            if not (finite and (lo < value if lo_open else lo <= value)
                    and value <= hi):
                interval = f"({lo}, {hi}]" if lo_open else f"[{lo}, {hi}]"
                what = "a positive number" if hi == _INF else f"within {interval}"
                raise ConfigError(f"{name} must be {what}{unit}, got {value} "
                                  f"(default {getattr(ColorShirtOptions, name)})")
        for name in _FRACTIONS:
            value = getattr(self, name)
            if not (np.isfinite(value) and 0 <= value < 1):
                raise ConfigError(f"{name} must be a fraction within [0, 1), got {value}")
        if self.database_size < 20:
            raise ConfigError("database_size must be at least 20 poses (the paper uses 80,000)")
        if not 0 < self.threshold <= self.prior_threshold:
            raise ConfigError("need 0 < threshold <= prior_threshold (paper: 3 and 5)")
        if self.reference_distance <= 0 or self.prior_strength < 0:
            raise ConfigError("reference_distance must be > 0 and prior_strength >= 0")
        if self.crop_margin < 1.0:
            raise ConfigError("crop_margin must be at least 1 (the located window itself)")
        if self.start_candidates < 1:
            raise ConfigError("start_candidates must be at least 1 (default 3)")
        lo, hi = self.start_root_band
        if not 0 <= lo < hi:
            raise ConfigError("start_root_band must be (low, high) fractions of the standing "
                              "pelvis height with 0 <= low < high (default (0.6, 1.3))")
        if self.body != "auto" and self.body not in BODY_SHAPES:
            raise ConfigError(f"unknown body preset {self.body!r}; choose 'auto' or one of "
                              f"{', '.join(BODY_SHAPES)}")
        scales = tuple(self.arm_scales)
        if (not scales or not all(np.isfinite(a) and 0.5 <= a <= 1.5 for a in scales)
                or not any(abs(a - 1.0) < 1e-9 for a in scales)):
            raise ConfigError("arm_scales must be arm-length factors within 0.5..1.5 that "
                              f"include 1 (the preset's own arms), got {self.arm_scales}")
        if not self.body_choice_max_stagger > 0.0:  # NaN fails too
            raise ConfigError("body_choice_max_stagger must be a positive distance in metres "
                              "(default 0.15; inf lets every one-camera frame judge the body)")
        if self.initial_white_balance is not None:
            W = np.asarray(self.initial_white_balance, dtype=float)
            if W.shape != (3, 3) or not np.all(np.isfinite(W)):
                raise ConfigError("initial_white_balance must be a finite 3x3 matrix")


_FRACTIONS = ("wb_smoothing", "blob_fraction", "blob_attach", "sleeve_attach",
              "min_color_fraction", "min_patch_fraction")
"""Options that must be a fraction within [0, 1)."""

_INF = float("inf")
_RANGES: tuple[tuple[str, float, float, bool, str], ...] = (
    ("retry_fraction", 0, 1, False, ""),
    ("work_size", 24, 640, False, " pixels"),
    ("min_colors", 1, 10, False, " colors"),
    ("start_agreement_frames", 0, 10_000, False,
     " frames (0: a lone camera's start gates the others at once)"),
    ("max_mismatch", 0, 1, True, ""),
    ("database_yaw", 0, 180, True, " degrees (180: every way round)"),
    ("facing_turn", 0, 180, True, " degrees (180: every pose)"),
    ("measurement_noise", 0, 9, False,
     " RGB units (larger values let background into the dark shirt colors)"),
    ("gate_time", 0, _INF, True, " (seconds)"),
    ("gate_speed", 0, _INF, True, " (shirt sizes per second)"),
    ("max_speed", 0, _INF, True, " (m/s)"),
    ("body_selection_frames", 1, 300, False, " frames"),
    ("arm_selection_frames", 0, 300, False, " frames (0: off)"),
    ("prior_gain_power", 0.0, 4.0, False, " (0: the paper's C = 6 / s)"),
    ("white_std_scale", 1.0, 20.0, False, " (1: white patches count like the others)"),
    ("arm_tolerance", 0.0, 0.5, False, " (0: the best residual wins)"),
    ("floor_offset", -0.5, 0.5, False, " m"),
    ("depth_accel", 0.0, 50.0, True, " m/s^2"),
    ("shirt_depth_std", 0.001, 1.0, False, ""),
    ("body_scale_std", 0.001, 0.5, False, ""),
    ("depth_pin_std", 0.001, 1.0, False, " m"),
    ("turn_std", 0.0, 3.2, False, " rad (0: held as loosely as the other rotations)"),
    ("floor_std", 0.005, 1.0, False, " m"),
    ("head_offset", -0.2, 0.2, False, " m"),
    ("head_std", 0.002, 1.0, False, " m"),
    ("arm_library", 1, 100_000, False, " arm configurations"),
    ("arm_temperature", 0, 1, False, " (0: take the best arm)"),
    ("arm_shortlist", 1, 200, False, " candidates per arm"),
    ("room_margin", 0.0, 1.0, False, " of the silhouette's size"),
    ("good_residual", 0.0, 1.0, True, " shirt sizes"),
    ("plate_mask_alone_cameras", 0, 16, False,
     " cameras (0: always both masks; 1: a one-camera rig masks with the plate alone)"),
    ("arm_depth_pull", 0.0, 10.0, False, " (0: no pull towards the blend's arms)"),
    ("arm_tau", 0.01, 2.0, False, " shirt sizes"),
)
"""Numeric options checked against a range: (name, low, high, low excluded, unit)."""
