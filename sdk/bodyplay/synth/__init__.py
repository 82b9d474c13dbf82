"""The synthetic camera: the skinned actor rendered as one or two webcams record it.

Rig (:mod:`~bodyplay.synth.rig`), lighting presets (:mod:`~bodyplay.synth.lighting`),
sensor model (:mod:`~bodyplay.synth.sensor`), backgrounds, occluders, the
:class:`SyntheticCamera` itself and the capture-folder writer used by
``bodyplay synth``. See docs/synth.md.
"""

from bodyplay.synth.backgrounds import background_names, load_background
from bodyplay.synth.camera import SyntheticCamera, SynthFrame
from bodyplay.synth.lighting import LIGHTING_PRESETS, lighting_preset
from bodyplay.synth.occluder import Occlusion, parse_occlusion
from bodyplay.synth.options import (
    SyntheticCameraOptions,
    make_synthetic_camera_options,
    parse_size,
)
from bodyplay.synth.rig import Rig, frame_rig, make_rig_options
from bodyplay.synth.sensor import NOISE_LEVELS, Sensor
from bodyplay.synth.writer import CaptureSummary, read_meta, write_capture

__all__ = [
    "CaptureSummary",
    "LIGHTING_PRESETS",
    "NOISE_LEVELS",
    "Occlusion",
    "Rig",
    "Sensor",
    "SynthFrame",
    "SyntheticCamera",
    "SyntheticCameraOptions",
    "background_names",
    "frame_rig",
    "lighting_preset",
    "load_background",
    "make_rig_options",
    "make_synthetic_camera_options",
    "parse_occlusion",
    "parse_size",
    "read_meta",
    "write_capture",
]
