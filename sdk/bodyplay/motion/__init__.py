"""bodyplay.motion: real motion capture in, bodyplay pose vectors out.

Read BVH files tolerantly (:func:`read_bvh`), retarget them onto the bodyplay
skeleton (:func:`retarget`, :func:`load_clip`), resample and slice the resulting
:class:`MotionClip`, write poses back as BVH (:func:`write_bvh`), solve poses from
17 tracked joints (:func:`poses_from_joints`) and sample poses for the trackers'
databases (:func:`sample_poses`). See docs/motion.md.
"""

from bodyplay.motion.bvh import BVHClip, EndSite, read_bvh, write_bvh
from bodyplay.motion.clip import MotionClip, builtin_clip_path, list_builtin_clips, load_clip
from bodyplay.motion.mapping import (
    BANDAI_MAPPING,
    CMU_MAPPING,
    CMU_MAX_MAPPING,
    JointMapping,
    guess_mapping,
)
from bodyplay.motion.retarget import (
    EXTRA_POINTS,
    RetargetOptions,
    SourceInfo,
    analyze_source,
    poses_from_joints,
    retarget,
    source_joints,
)
from bodyplay.motion.sampling import (
    SAMPLING_MODES,
    random_upper_body,
    sample_poses,
    uniform_subsample,
)

__all__ = [
    "BANDAI_MAPPING",
    "BVHClip",
    "CMU_MAPPING",
    "CMU_MAX_MAPPING",
    "EXTRA_POINTS",
    "EndSite",
    "JointMapping",
    "MotionClip",
    "RetargetOptions",
    "SAMPLING_MODES",
    "SourceInfo",
    "analyze_source",
    "builtin_clip_path",
    "guess_mapping",
    "list_builtin_clips",
    "load_clip",
    "poses_from_joints",
    "random_upper_body",
    "read_bvh",
    "retarget",
    "sample_poses",
    "source_joints",
    "uniform_subsample",
    "write_bvh",
]
