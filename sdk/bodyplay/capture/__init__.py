"""Frame sources (webcam, video, image folder, capture folder, synthetic) and cameras."""

from bodyplay.capture.camera import Camera, look_at, read_calib, write_calib

__all__ = ["Camera", "look_at", "read_calib", "write_calib"]

from bodyplay.capture.calibration import (  # noqa: E402
    Board,
    IntrinsicsResult,
    RigCalibration,
    board_pose_in_camera,
    calibrate_intrinsics,
    calibrate_rig,
    find_board_corners,
    read_qualisys_calib,
    rig_geometry,
)
from bodyplay.capture.frames import Frame, FrameSet  # noqa: E402
from bodyplay.capture.jsonl import (  # noqa: E402
    PoseJsonlWriter,
    PoseTrack,
    read_pose_jsonl,
    write_pose_jsonl,
)
from bodyplay.capture.sources import (  # noqa: E402
    CaptureFolderSource,
    FrameSource,
    ImageFolderSource,
    VideoFileSource,
    WebcamSource,
    open_source,
)

__all__ += [
    "Board",
    "CaptureFolderSource",
    "Frame",
    "FrameSet",
    "FrameSource",
    "ImageFolderSource",
    "IntrinsicsResult",
    "PoseJsonlWriter",
    "PoseTrack",
    "RigCalibration",
    "VideoFileSource",
    "WebcamSource",
    "board_pose_in_camera",
    "calibrate_intrinsics",
    "calibrate_rig",
    "find_board_corners",
    "open_source",
    "read_pose_jsonl",
    "read_qualisys_calib",
    "rig_geometry",
    "write_pose_jsonl",
]
