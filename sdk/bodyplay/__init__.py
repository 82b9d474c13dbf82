"""bodyplay: a person in front of one or two webcams as game input.

The public API is re-exported here; everything else is private to its module.
Typical use::

    import bodyplay

    with bodyplay.create_session(source=bodyplay.ClipPoseSource("13_29")) as session:
        @session.on("gesture")
        def on_gesture(event: bodyplay.GestureEvent) -> None:
            print(event.t, event.gesture, event.phase)

        session.run()
"""

from bodyplay.body import (
    BODY_SHAPES,
    JOINT_NAMES,
    UPPER_BODY,
    Actor,
    BodyShape,
    Skeleton,
    SkinnedMesh,
    body_mesh,
    body_shape,
    load_actor,
)
from bodyplay.capture import (
    Camera,
    CaptureFolderSource,
    Frame,
    FrameSet,
    ImageFolderSource,
    PoseTrack,
    VideoFileSource,
    WebcamSource,
    look_at,
    open_source,
    read_calib,
    read_pose_jsonl,
    write_calib,
    write_pose_jsonl,
)
from bodyplay.cloth import Cloth, ClothOptions, ClothStep, Garment
from bodyplay.errors import (
    BodyplayError,
    BVHError,
    CalibrationError,
    CaptureError,
    ConfigError,
    PluginError,
    SessionError,
    TimestampError,
    UnknownEventError,
)
from bodyplay.evaluation import EvalResult, evaluate
from bodyplay.events import (
    ContactEvent,
    Event,
    EventBus,
    GestureEvent,
    PoseEvent,
    TrackingEvent,
)
from bodyplay.motion import MotionClip, load_clip, read_bvh, retarget, write_bvh
from bodyplay.physics import PhysicsObject, PhysicsOptions, PhysicsWorld, attach_physics
from bodyplay.plugins import PluginRegistry
from bodyplay.record import ReplaySource, read_recording, record_session
from bodyplay.runtime import (
    ArrayPoseSource,
    ClipPoseSource,
    FixedClock,
    ManualClock,
    PoseSample,
    Session,
    SessionOptions,
    SystemClock,
    create_session,
)
from bodyplay.testing import ScriptedPlayer, Timeline, scripted_session
from bodyplay.trackers import Tracker, TrackerCapabilities, TrackResult, create_tracker
from bodyplay.virtual import (
    IdleMotion,
    PoseController,
    ReachController,
    ReachOptions,
    TimelineController,
    VirtualPlayerSource,
    VirtualPoseSource,
    make_reach_options,
)

__version__ = "0.1.0"

__all__ = [
    "BODY_SHAPES",
    "JOINT_NAMES",
    "UPPER_BODY",
    "Actor",
    "ArrayPoseSource",
    "BVHError",
    "BodyShape",
    "BodyplayError",
    "CalibrationError",
    "Camera",
    "CaptureError",
    "CaptureFolderSource",
    "ClipPoseSource",
    "Cloth",
    "ClothOptions",
    "ClothStep",
    "ConfigError",
    "ContactEvent",
    "EvalResult",
    "Event",
    "EventBus",
    "FixedClock",
    "Frame",
    "FrameSet",
    "Garment",
    "GestureEvent",
    "IdleMotion",
    "ImageFolderSource",
    "ManualClock",
    "MotionClip",
    "PhysicsObject",
    "PhysicsOptions",
    "PhysicsWorld",
    "PluginError",
    "PluginRegistry",
    "PoseController",
    "PoseEvent",
    "PoseSample",
    "PoseTrack",
    "ReachController",
    "ReachOptions",
    "ReplaySource",
    "ScriptedPlayer",
    "Session",
    "SessionOptions",
    "SessionError",
    "Skeleton",
    "SkinnedMesh",
    "SystemClock",
    "Timeline",
    "TimelineController",
    "TimestampError",
    "TrackResult",
    "Tracker",
    "TrackerCapabilities",
    "TrackingEvent",
    "UnknownEventError",
    "VideoFileSource",
    "VirtualPlayerSource",
    "VirtualPoseSource",
    "WebcamSource",
    "attach_physics",
    "body_mesh",
    "body_shape",
    "create_session",
    "create_tracker",
    "evaluate",
    "load_actor",
    "load_clip",
    "make_reach_options",
    "look_at",
    "open_source",
    "read_bvh",
    "read_calib",
    "read_pose_jsonl",
    "read_recording",
    "record_session",
    "retarget",
    "scripted_session",
    "write_bvh",
    "write_calib",
    "write_pose_jsonl",
]
