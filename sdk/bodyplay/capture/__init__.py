"""Frame sources (webcam, video, image folder, capture folder, synthetic) and cameras."""

from bodyplay.capture.camera import Camera, look_at, read_calib, write_calib

__all__ = ["Camera", "look_at", "read_calib", "write_calib"]
