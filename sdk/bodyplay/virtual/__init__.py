"""Virtual players: every game runs with no hardware (see docs/virtual-players.md).

A :class:`PoseController` poses the actor over time: :class:`TimelineController`
plays a scripted :class:`~bodyplay.testing.Timeline`; :class:`ReachController` is a
keeper who stands in real mocap idle motion (:class:`IdleMotion`) and reaches for
announced balls with inverse kinematics (:func:`solve_reach`). A
:class:`VirtualPlayerSource` films the posed actor with the synthetic camera (a
frame source for any tracker); :class:`VirtualPoseSource` hands the poses straight
to a session.
"""

from bodyplay.virtual.controller import PoseController, TimelineController
from bodyplay.virtual.idle import DEFAULT_IDLE, IdleMotion
from bodyplay.virtual.reach import (
    STANCES,
    ReachController,
    ReachOptions,
    ReachPlan,
    make_reach_options,
    min_jerk,
)
from bodyplay.virtual.reach_ik import (
    EFFECTORS,
    ReachPose,
    ReachWeights,
    body_axes,
    choose_effector,
    effector_points,
    solve_reach,
)
from bodyplay.virtual.source import VirtualPlayerSource, VirtualPoseSource

__all__ = [
    "DEFAULT_IDLE",
    "EFFECTORS",
    "IdleMotion",
    "PoseController",
    "ReachController",
    "ReachOptions",
    "ReachPlan",
    "ReachPose",
    "ReachWeights",
    "STANCES",
    "TimelineController",
    "VirtualPlayerSource",
    "VirtualPoseSource",
    "body_axes",
    "choose_effector",
    "effector_points",
    "make_reach_options",
    "min_jerk",
    "solve_reach",
]
