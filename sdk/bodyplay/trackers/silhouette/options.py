"""Options of the silhouette tracker and of its shape hierarchy (frozen, validated)."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

from bodyplay.errors import ConfigError
from bodyplay.optiontypes import check_option_types

__all__ = ["BackgroundOptions", "HierarchyOptions", "SilhouetteOptions", "LEVEL_SIZES"]

LEVEL_SIZES: tuple[tuple[int, int], ...] = ((60, 80), (120, 160), (240, 320))
"""(width, height) of the matching window at tree levels 1..3: the paper's pyramid
80x60 / 160x120 / 320x240 in pixel count, turned upright around the person."""


@dataclass(frozen=True)
class BackgroundOptions:
    """The per-pixel Gaussian background model (paper section 2.2, last paragraph).

    ``threshold`` is the Mahalanobis distance above which a pixel is foreground;
    ``intensity_weight`` scales the intensity channel against the two
    intensity-normalized chromaticities (small: shadows change intensity, not hue);
    ``learn_after`` is how many frames a pixel must stay still (and away from the
    player) before its value is learned as background, ``relearn_after`` the same
    for a pixel already learned that now differs; ``rate`` the adaptation rate
    of learned background pixels (slow light changes); ``min_std`` the noise floor;
    ``open_px``/``close_px`` the morphological clean-up; ``min_area`` the smallest
    blob share of the image kept; ``working_size`` the short side of the image the
    model works on (the paper: 640x480 down-sampled to 320x240); ``bootstrap``: take
    the first frame's likely figure (GrabCut) as the player until it is learned,
    ``hold_guess`` the frames it is kept from learning while the tracker has no pose;
    ``hold_below``: while the tracker has no pose (for at most ``hold_guess``
    frames), the pixels under and beside what has moved since (each column from its
    highest moved pixel down) are not learned either (the still legs and torso of a
    player who moves the arms, when there is no first guess to hold them);
    ``resolve_every``: every that many frames the unknown pixels inside the guess are
    labelled player or background by GrabCut seeded with the learned model
    (``resolve_iterations`` iterations; 0 turns it off and leaves them "don't care"),
    ``guess_margin`` the pixels around the first guess that are not taken as known
    background from the first frame; ``guess_expiry``: still pixels resolved as the
    player that stay outside the tracker's estimate of the body for that many frames
    are learned as background after all (0: never); ``resolve_outside``: once the
    tracker has an estimate, the still unknown pixels farther than this many
    working-image pixels outside it (the estimate as passed, already dilated by the
    tracker's ``protect_radius``) are sure background in each resolution, not only
    after ``guess_expiry`` frames: furniture beside the player in the colours of the
    clothes then teaches GrabCut what is not the player (None: off);
    ``learn_away``: a known pixel that differs is relearned (``relearn_after``) only
    once it has also been outside the tracker's estimate for this many frames in a
    row, not the first frame the estimate leaves it (a foot held still under the
    estimate for 3 s was learned as background the frame a step moved the estimate
    away; 0: as before).
    """

    threshold: float = 4.0
    intensity_weight: float = 0.35
    learn_after: int = 12
    relearn_after: int = 90
    rate: float = 0.02
    min_std: float = 0.012
    open_px: int = 1
    close_px: int = 2
    min_area: float = 0.002
    working_size: int = 240
    bootstrap: bool = True
    hold_guess: int = 60
    hold_below: bool = True
    resolve_every: int = 5
    guess_margin: int = 3
    resolve_iterations: int = 2
    guess_expiry: int = 30
    resolve_outside: int | None = 10
    learn_away: int = 12

    def __post_init__(self) -> None:
        check_option_types(self)
        if self.threshold <= 0 or self.min_std <= 0 or not 0 < self.rate < 1:
            raise ConfigError("background threshold and min_std must be > 0, rate in (0, 1)")
        if self.learn_after < 1 or self.relearn_after < self.learn_after:
            raise ConfigError("background learn_after must be at least 1 frame and "
                              "relearn_after at least learn_after")
        if self.resolve_outside is not None and self.resolve_outside < 0:
            raise ConfigError("background resolve_outside must be >= 0 pixels or None (off)")
        if self.resolve_every < 0 or self.guess_margin < 0 or self.guess_expiry < 0:
            raise ConfigError("background resolve_every, guess_margin and guess_expiry must "
                              "be >= 0")
        if self.learn_away < 0:
            raise ConfigError("background learn_away must be >= 0 frames (0: off)")
        if self.working_size < 60:
            raise ConfigError("background working_size must be at least 60 pixels")


@dataclass(frozen=True)
class HierarchyOptions:
    """What the shape hierarchy is built from (everything here enters its cache key).

    ``clips``: motion clips (built-in names or BVH paths; default the vendored CMU
    clips); ``clip_fps`` the rate they are read at (the tracker's frame rate, for
    the transition histograms); ``yaw_offsets_deg``: each clip is also turned by
    these yaws relative to facing the camera; ``dedup_deg`` the paper's 5-degree
    rule; ``random_share``: joint-limit-aware random poses added, as a share of the
    clip poses; ``thresholds``: Algorithm 1's t_L per level (normalized
    core-weighted XOR distance at that level's resolution); ``bodies``: body-size
    presets templates are rendered for; ``metres_per_px``: window scale at level 3;
    ``camera_height``/``camera_distance``: the canonical view templates are
    rendered from; ``mirror``: every clip is also used mirrored left-right (a wave
    of the right hand gives one of the left; the mirrored clips enter the
    transition histograms as sequences of their own); ``recombine_share``:
    recombined motion (:mod:`.recombine`: each body part of a stretch of real
    motion follows, with probability ``recombine_swap``, another stretch of any
    clip or its mirror, time-warped, or with probability ``recombine_random``
    moves between random configurations within the joint limits), as a share
    of the clip frames (0: none); ``clamp``: clip poses are
    projected into the skeleton's joint limits (off: kept as the clips have them,
    for motions past those limits, such as the ninja's arm swung over the head:
    the shoulder's limit is 1.7 rad from the T-pose, its hit 1.9).
    """

    clips: tuple[str, ...] = ()
    clip_fps: float = 30.0
    yaw_offsets_deg: tuple[float, ...] = (-35.0, 0.0, 35.0)
    max_yaw_deg: float = 80.0
    dedup_deg: float = 5.0
    random_share: float = 0.15
    thresholds: tuple[float, float, float] = (0.04, 0.028, 0.022)
    bodies: tuple[str, ...] = ("xs", "s", "m", "l", "xl")
    metres_per_px: float = 0.009
    camera_height: float = 1.2
    camera_distance: float = 3.0
    max_poses: int = 12_000
    seed: int = 0
    mirror: bool = False
    recombine_share: float = 0.0
    recombine_swap: float = 0.5
    recombine_random: float = 0.2
    clamp: bool = True
    membership: tuple[str, str, str] = ("prototype", "prototype", "prototype")
    membership_beta: float = 5.0

    def __post_init__(self) -> None:
        check_option_types(self)
        if len(self.membership) != 3 or any(m not in ("prototype", "member", "both")
                                            for m in self.membership):
            raise ConfigError("membership must name, per level 1..3, 'prototype', 'member' "
                              f"or 'both', got {self.membership!r}")
        if self.membership_beta <= 0:
            raise ConfigError("membership_beta must be > 0")
        if not 0 <= self.recombine_share <= 10:
            raise ConfigError("recombine_share must be within 0..10 (a share of the clip frames)")
        if not (0 <= self.recombine_swap <= 1 and 0 <= self.recombine_random <= 1
                and self.recombine_swap + self.recombine_random <= 1):
            raise ConfigError("recombine_swap and recombine_random are probabilities whose "
                              "sum is at most 1")
        if len(self.thresholds) != 3 or any(t <= 0 for t in self.thresholds):
            raise ConfigError("thresholds must be three positive distances (levels 1..3)")
        if not self.bodies:
            raise ConfigError("the hierarchy needs at least one body preset")
        if self.dedup_deg <= 0 or self.clip_fps <= 0 or self.max_poses < 10:
            raise ConfigError("dedup_deg and clip_fps must be > 0, max_poses >= 10")
        if not 0 <= self.random_share <= 2:
            raise ConfigError("random_share must be within 0..2")

    def key_items(self) -> list[tuple[str, object]]:
        """The options as sorted (name, value) pairs, for the cache key (``mirror`` and
        the recombination only when on, ``clamp`` only when off, so the hierarchies
        cached before they existed stay valid)."""
        items = asdict(self)
        if not self.mirror:
            del items["mirror"]
        if not self.recombine_share:
            for k in ("recombine_share", "recombine_swap", "recombine_random"):
                del items[k]
        if self.clamp:
            del items["clamp"]
        if all(m == "prototype" for m in self.membership):
            del items["membership"], items["membership_beta"]
        return sorted(items.items())


@dataclass(frozen=True)
class SilhouetteOptions:
    """Options of the silhouette tracker (see docs/silhouette.md).

    ``body``: a body preset or ``"auto"`` (chosen on the first ``select_frames``
    frames with a person once the player has moved: ``select_motion``, the share of
    the background model's working image that must change in one frame, 0: count
    from the first frame; a player who stands still until ``select_wait`` seconds
    after the start is measured still: until something moves, the silhouette is only
    the first frame's colour segmentation); ``sigma``: likelihood scale per level relative to that
    level's clustering threshold; ``keep``: posterior share (of the best node)
    below which a subtree is pruned, ``max_expand`` the most nodes expanded per
    level, ``explore`` how many best-fitting nodes are expanded whatever their
    prior; ``shift_search``: the level-1 grid of positions tried around the floor
    point, (x, y) pixels each way (a level-1 pixel is 3.6 cm; y > 0 also lets a body
    preset taller than the player stand a little lower); ``occlusion_m``:
    eq. 14's m; ``transition_weight``: share of the
    prediction from the training transition histograms (the rest from the
    first-order Gaussian model, eq. 13-14); ``transition_frames``: how many frames
    ahead the histogram reaches (the prediction averages its 1..n-frame
    transitions, so a filter that missed a frame of a fast motion, a hit's swing
    under motion blur, still predicts where the motion goes; 1 is the paper's);
    ``uniform``: prior mass spread over all leaves (recovery after failure);
    ``fit_prior``: share of the prior given to the leaves scored at the finest
    level in proportion to their likelihood this frame (an observation-driven
    proposal, as in the boosted particle filter: a pose the prediction cannot
    reach, a thin arm swung up while the filter still holds it down, wins when it
    fits clearly better; 0, the default, is the paper's prediction alone);
    ``lost_after``: seconds without a person before every joint is reported lost
    (before, the prediction is reported ``inferred``);
    ``min_height``/``max_distance``: a silhouette shorter, or a floor point farther
    from the camera (m), is not a person (the automatic start);
    ``max_distance`` 0 (the default) takes it from the calibration: the distance at
    which a person 1.7 m tall is ``min_person_px`` pixels tall in the background
    model's working image (about 6 m for a 640x480 webcam of 60 degrees, 13 m for
    the Sports2D clip's camera; was a fixed 6 m);
    ``depth_window``: seconds over which the nearest floor distance
    is kept (jumps lift the feet); ``smooth``: share of the previous joints kept
    (exponential smoothing of the discrete templates); ``max_recession``: m/s the
    floor point may move away from the camera (feet hidden by a bow or a lost leg
    would put it metres away); ``bootstrap_time``: seconds after the start during
    which the first frame's guess of the player counts for the floor point;
    ``restart_within``: a track lost (no person for ``lost_after`` s) before it has
    lasted this many seconds was a wrong start (the arms of a player who stands
    still, taken for a whole person metres away, protected their own spot): the
    tracker starts over as if it had seen no one, the background model kept (0:
    off); after such a restart, for the new track's first ``restart_doubt`` s, a
    floor point under the silhouette counts only where it lies within
    ``restart_agree`` (a share) of the distance at which the templates fit what
    moves (:mod:`.shapestart`); until then that distance is used;
    ``still_window``: a track whose kept foreground did not move over this many
    seconds (under a tenth of ``still_motion`` of the image per frame) while the
    foreground it dropped moved (at least ``still_motion`` per frame), or while its
    median distance (eq. 11) was at least ``still_fit`` and something else stood
    in view, follows something that is not the player (a photo of a person beside
    them): what it held is learned as background and the tracker guesses again
    (:mod:`.stilltrack`; 0: off; ``still_fit`` 0: only the motion rule);
    ``protect_radius``: how far (share of the working image's short side, so that
    portrait footage is not over-protected) the estimated body is dilated into the
    region the background model must not learn (0.04 gave
    24.6 / 24.7 cm median / worst on the tune clips, 0.12 gave 20.0 / 21.4: a wide
    margin keeps limbs the pose missed from being learned as background);
    ``beta``: eq. 10's weight on silhouette pixels a template leaves uncovered (the
    paper's 1 lets a pose with a thin raised arm left out beat the arm 2 px off;
    5, as in the core-weighted XOR the paper cites, follows raised arms: tune clips
    15.4 / 23.2 -> 12.4 / 18.8 cm median / worst);
    ``body_cue``: how the body preset is chosen when ``body="auto"``: "stature"
    (of the presets whose chosen templates' head tops are within
    ``stature_tolerance`` m of the observed head top, median over the frames, of
    the best match, the one of smallest mean distance) or "distance" (smallest mean
    distance alone);
    ``head_gap``/``shoulder_width``: a frame's stature reading is the head top only
    where the observed silhouette shows a head: its head top at least ``head_gap``
    of the template's head-to-shoulder height above its own shoulder row (the
    highest row whose run through the middle is ``shoulder_width`` m wide); where
    the room took the head (the silhouette ends at the shoulders), the shoulder rows
    are compared instead (0, the default: the head top always; 0.7 chose the actor's
    preset on 7 of 10 tune-room captures instead of 3, but did not carry over to
    the report rooms: docs/silhouette-history.md, section 2);
    ``max_foot_width``/``foot_band``: the first frame's guess of the player counts
    for the floor point only when no row of its lowest ``foot_band`` m is wider,
    filled, than ``max_foot_width`` m (feet and shins; GrabCut can take a dark treadmill
    or sofa under the player for the figure, which would put the player too near);
    ``arm_candidates``: size of the arm atlas each arm of the chosen pose is
    searched in on its own after the tree filter (:mod:`.armfit`; 0 turns the
    refinement off), ``arm_stay`` the cost per window pixel (level 2) an atlas arm's
    elbow and wrist move from the tree's arm, ``arm_margin`` how much cheaper (sum
    of eq. 11's per-pixel term) it must be to replace it (on the tune clips: off
    12.9 cm mean of clip medians, 11.1 with these); ``arm_body``: what the arms are
    scored against, ``"torso"`` the leaf rendered without its arms (:mod:`.armless`:
    only what the torso, head and legs do not cover is the arms' to win or lose;
    silhouette within 3.6 cm of their outline is their own misfit and credits no arm)
    or ``"template"``, before 2026-11-28, the leaf's template less its arms' capsules
    (a leaf whose arm hangs in front of the torso credits that arm with the torso it
    hides, and a raised arm the silhouette shows loses to it). ``"torso"``: tune
    captures' mean over three tree seeds 11.8 -> 10.3 cm, built-from 8.07 -> 7.83, and
    on a fresh draw of the rooms nobody tuned on 23.5 -> 23.2
    (docs/silhouette-history.md, sections 16, 17, 20);
    ``width_frames``: the body's girth (torso and limbs' thickness; not its joints)
    is measured on the reported pose over that many frames after the body is
    chosen (:mod:`.bodywidth`: the preset's mesh at girth factors 0.9 to
    ``width_max`` scored by eq. 11 in the window, the median of the frames'
    cheapest) and reported as ``extras["shape"]`` (0: the preset's own shape);
    ``head_depth_weight``: share of the head-top depth cue (:mod:`.headdepth`) blended
    into the root's distance from the camera (0: the floor point alone),
    ``head_depth_window`` the seconds its median is taken over, ``head_min_lever``
    the least height (m) of the template's head top above the camera for the cue
    to count; ``stance_weight``: share of the stance cue (:mod:`.stance`: the two
    feet's floor rows, observed against the template's, in the lowest ``foot_band``
    m) applied to the root's distance (0: the template's own stance; 1, the geometric
    value), ``stance_window`` the seconds its median is taken over,
    ``stance_deadband`` the metres taken off each frame's offset (a couple of
    pixels of segmentation at the feet read as a stance; the nine tune captures
    11.6 / 18.9 / 11.1 cm median / worst / mean of clip medians, 10.5 / 18.7 / 10.4
    with the cue and no dead band, 10.7 / 18.4 / 10.2 with 0.04 m; docs/silhouette-history.md, 8);
    ``shape_frames``: when there is no first-frame guess of the player (GrabCut
    found no figure, or the guess was dropped) and the silhouette does not stand on
    the floor as a person (the arms of a player who stands still), the floor
    distance is the median over
    that many frames of the distance at which the templates fit what moves best
    (:mod:`.shapestart`; 0: off, wait for a whole person to move), kept until a
    floor point is seen;
    ``box_guess``: at that moment, when there is no first guess, the first frame's
    guess is made again inside the box a person standing at that floor point can
    fill (``box_guess`` m either side of the line of sight, from under the floor to
    ``box_top`` m; :meth:`.background.BackgroundModel.guess_in`), and resolved like a
    first guess (0: off);
    ``box_redo``: when the first guess was dropped (it took a treadmill or a sofa
    under the player for the figure), the box a person standing at the first floor
    point can fill is the guess (the same box, ``box_guess`` > 0; grown by the box at
    the distance where the templates fit best, :mod:`.shapestart`, when that is nearer
    than the floor point by more than ``restart_agree``: the floor point of what moved
    lies behind the player when the still feet were left as room), resolved like a
    first guess: the first frame's copy of the player left in the room (the ghost)
    and the still body are resolved again instead of staying foreground and
    background (False: the dropped guess's pixels stay "don't care" and are learned);
    ``facing``: "front" (the tree's poses, facing the camera) or "away": the camera
    films the player from behind, and every reported pose is the front pose with
    its depth reflected about the root and left and right swapped (:mod:`.facing`;
    the silhouette, the template and the filter are unchanged);
    ``cache``: hierarchy cache folder.
    """

    body: str = "auto"
    hierarchy: HierarchyOptions = field(default_factory=HierarchyOptions)
    background: BackgroundOptions = field(default_factory=BackgroundOptions)
    sigma: float = 0.25
    keep: float = 0.02
    max_expand: tuple[int, int] = (24, 48)
    shift_search: tuple[int, int] = (1, 0)
    explore: int = 3
    occlusion_m: float = 5.0
    transition_weight: float = 0.5
    transition_frames: int = 1
    uniform: float = 0.02
    fit_prior: float = 0.0
    select_frames: int = 45
    select_motion: float = 0.002
    select_wait: float = 3.0
    min_height: float = 0.9
    max_distance: float = 0.0
    min_person_px: float = 80.0
    lost_after: float = 0.5
    depth_window: float = 0.4
    max_recession: float = 0.5
    bootstrap_time: float = 1.0
    restart_within: float = 1.0
    restart_agree: float = 0.25
    restart_doubt: float = 3.0
    still_window: float = 1.0
    still_motion: float = 0.002
    still_fit: float = 0.5
    smooth: float = 0.5
    protect_radius: float = 0.12
    beta: float = 5.0
    body_cue: str = "stature"
    stature_tolerance: float = 0.05
    head_gap: float = 0.0
    shoulder_width: float = 0.26
    max_foot_width: float = 0.6
    foot_band: float = 0.25
    arm_candidates: int = 1000
    arm_stay: float = 3.0
    arm_margin: float = 100.0
    arm_body: str = "torso"
    width_frames: int = 30
    width_max: float = 1.4
    head_depth_weight: float = 0.0
    head_depth_window: float = 0.5
    head_min_lever: float = 0.3
    stance_weight: float = 1.0
    stance_window: float = 0.5
    stance_deadband: float = 0.04
    shape_frames: int = 5
    start_area: float = 0.75
    box_guess: float = 0.9
    box_top: float = 2.3
    box_below: float = 0.0
    box_redo: bool = True
    facing: str = "front"
    cache: str | None = None

    def __post_init__(self) -> None:
        check_option_types(self)
        if not 0 <= self.head_depth_weight <= 1 or self.head_depth_window < 0:
            raise ConfigError("head_depth_weight must be in [0, 1] (0: floor point alone) and "
                              "head_depth_window >= 0 seconds")
        if not 0 <= self.stance_weight <= 1:
            raise ConfigError("stance_weight must be in [0, 1] (0: the template's own stance)")
        if self.facing not in ("front", "away"):
            raise ConfigError(f"facing must be 'front' or 'away', got {self.facing!r}")
        if self.stance_window < 0 or self.stance_deadband < 0:
            raise ConfigError("stance_window must be >= 0 seconds and stance_deadband >= 0 m")
        if not 0 <= self.start_area <= 1:
            raise ConfigError(f"start_area must be a share of the smallest template's area in "
                              f"[0, 1] (0: off), got {self.start_area!r}")
        if self.box_guess < 0 or self.box_top <= 0:
            raise ConfigError("box_guess must be >= 0 metres (0: off) and box_top > 0 metres")
        if self.shape_frames < 0:
            raise ConfigError("shape_frames must be >= 0 (0: no start from the shape)")
        if self.head_min_lever <= 0:
            raise ConfigError("head_min_lever must be > 0 metres")
        if self.arm_candidates < 0 or self.arm_stay < 0 or self.arm_margin < 0:
            raise ConfigError("arm_candidates (0: no per-arm refinement), arm_stay and "
                              "arm_margin must be >= 0")
        if self.arm_body not in ("torso", "template"):  # armfit.ARM_BODIES
            raise ConfigError(f"arm_body must be 'torso' or 'template', got {self.arm_body!r}")
        if self.width_frames < 0 or not 1.0 <= self.width_max <= 2.0:
            raise ConfigError("width_frames must be >= 0 (0: the preset's own girth) and "
                              f"width_max within 1..2, got {self.width_frames}, {self.width_max}")
        if self.sigma <= 0 or self.occlusion_m < 1:
            raise ConfigError("sigma must be > 0 and occlusion_m >= 1")
        if not isinstance(self.transition_frames, int) or not 1 <= self.transition_frames <= 10:
            raise ConfigError(f"transition_frames must be a whole number of frames in 1..10 "
                              f"(1: the paper's one-frame histogram), got "
                              f"{self.transition_frames!r}")
        if not 0 <= self.transition_weight <= 1 or not 0 < self.uniform < 1:
            raise ConfigError("transition_weight must be in 0..1 and uniform in (0, 1)")
        if not 0 <= self.fit_prior < 1:
            raise ConfigError(f"fit_prior must be a share of the prior in [0, 1) (0: the "
                              f"prediction alone), got {self.fit_prior!r}")
        if min(self.shift_search) < 0:
            raise ConfigError("shift_search must be non-negative pixel counts")
        if not 0 < self.keep < 1 or min(self.max_expand) < 1:
            raise ConfigError("keep must be in (0, 1) and max_expand at least 1")
        if self.body_cue not in ("stature", "distance"):
            raise ConfigError(f"body_cue must be 'stature' or 'distance', got {self.body_cue!r}")
        if self.stature_tolerance < 0:
            raise ConfigError("stature_tolerance must be >= 0 metres")
        if not 0 <= self.head_gap <= 1:
            raise ConfigError(f"head_gap must be within 0..1, got {self.head_gap}")
        if not 0.1 <= self.shoulder_width <= 0.6:
            raise ConfigError(f"shoulder_width must be within 0.1..0.6 m, got "
                              f"{self.shoulder_width}")
        if self.max_distance < 0 or self.min_person_px <= 0:
            raise ConfigError("max_distance must be >= 0 metres (0: from the calibration) "
                              "and min_person_px > 0")
        if self.max_foot_width <= 0 or self.foot_band <= 0:
            raise ConfigError("max_foot_width and foot_band must be > 0 metres")
        if self.beta <= 0:
            raise ConfigError("beta (eq. 10's weight on uncovered silhouette pixels) must be "
                              f"> 0, got {self.beta}")
        if not 0 <= self.protect_radius < 1:
            raise ConfigError("protect_radius must be a share of the image height in [0, 1)")
        if self.restart_within < 0 or self.restart_agree <= 0 or self.restart_doubt < 0:
            raise ConfigError("restart_within and restart_doubt must be >= 0 seconds (0: no "
                              "restart, no doubt) and restart_agree > 0 (a share of the "
                              "distance)")
        if self.still_window < 0 or not 0 < self.still_motion < 1 or self.still_fit < 0:
            raise ConfigError("still_window must be >= 0 seconds (0: off), still_motion a "
                              "share of the image in (0, 1) and still_fit >= 0")
        if not 0 <= self.select_motion < 1 or self.select_wait < 0:
            raise ConfigError("select_motion must be a share of the image in [0, 1) and "
                              "select_wait >= 0 seconds")
        if self.select_frames < 1 or self.lost_after < 0 or not 0 <= self.smooth < 1:
            raise ConfigError("select_frames >= 1, lost_after >= 0 and smooth in [0, 1)")
        if self.explore < 0 or self.min_height <= 0 or self.box_below < 0:
            raise ConfigError(f"explore must be >= 0 nodes, min_height > 0 metres and box_below "
                              f">= 0 metres, got {self.explore}, {self.min_height}, "
                              f"{self.box_below}")
        if self.depth_window < 0 or self.max_recession < 0 or self.bootstrap_time < 0:
            raise ConfigError(f"depth_window and bootstrap_time must be >= 0 seconds and "
                              f"max_recession >= 0 m/s, got {self.depth_window}, "
                              f"{self.bootstrap_time}, {self.max_recession}")
