"""Frame sources: video files, image folders, capture folders, webcams, open_source."""

from __future__ import annotations

import warnings
from pathlib import Path

import cv2
import numpy as np
import pytest

from bodyplay.capture import (
    Camera,
    CaptureFolderSource,
    FrameSource,
    ImageFolderSource,
    VideoFileSource,
    WebcamSource,
    open_source,
    write_calib,
)
from bodyplay.errors import CaptureError

W, H = 64, 48


def bgr_frame(i: int) -> np.ndarray:
    """A frame whose red channel is high and blue channel encodes the index."""
    im = np.zeros((H, W, 3), np.uint8)
    im[:, :, 2] = 200  # red in BGR
    im[:, :, 0] = 20 * i  # blue
    return im


def write_video(path: Path, n: int, fps: float = 25.0) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, (W, H))
    assert writer.isOpened()
    for i in range(n):
        writer.write(bgr_frame(i))
    writer.release()
    return path


def write_pngs(folder: Path, n: int) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        cv2.imwrite(str(folder / f"{i:06d}.png"), bgr_frame(i))
    return folder


def test_video_source_yields_rgb_frames_with_index_over_fps_timestamps(tmp_path: Path) -> None:
    path = write_video(tmp_path / "v.mp4", 5, fps=25.0)
    with VideoFileSource(path) as src:
        assert isinstance(src, FrameSource)
        assert src.fps == 25.0 and src.cameras is None
        sets = list(src)
    assert [fs.index for fs in sets] == [0, 1, 2, 3, 4]
    assert [fs.t for fs in sets] == pytest.approx([0, 0.04, 0.08, 0.12, 0.16])
    img = sets[0][0].image
    assert img.shape == (H, W, 3) and img.dtype == np.uint8
    assert img[..., 0].mean() > 150 and img[..., 2].mean() < 50  # red first: RGB


def test_video_source_can_be_iterated_twice(tmp_path: Path) -> None:
    src = VideoFileSource(write_video(tmp_path / "v.mp4", 3))
    assert len(list(src)) == 3 and len(list(src)) == 3
    src.close()
    with pytest.raises(CaptureError, match="closed"):
        list(src)


def test_video_source_rejects_missing_file_and_garbage(tmp_path: Path) -> None:
    with pytest.raises(CaptureError, match="no such video"):
        VideoFileSource(tmp_path / "nope.mp4")
    bad = tmp_path / "bad.mp4"
    bad.write_bytes(b"not a video at all")
    with pytest.raises(CaptureError, match="bad.mp4"):
        VideoFileSource(bad)


def test_video_source_rejects_camera_of_other_size(tmp_path: Path) -> None:
    cam = Camera.from_fov("cam0", 640, 480, 60)
    with pytest.raises(CaptureError, match="calibrated for 640x480"):
        VideoFileSource(write_video(tmp_path / "v.mp4", 2), camera=cam)


def test_image_folder_source_reads_in_numeric_order(tmp_path: Path) -> None:
    folder = tmp_path / "imgs"
    folder.mkdir()
    for i in (0, 1, 2, 10):  # 10 must come after 2
        cv2.imwrite(str(folder / f"{i}.png"), bgr_frame(i))
    with ImageFolderSource(folder, fps=10) as src:
        sets = list(src)
    blue = [int(fs[0].image[0, 0, 2]) for fs in sets]  # blue is channel 2 in RGB
    assert blue == [0, 20, 40, 200]
    assert [fs.t for fs in sets] == pytest.approx([0, 0.1, 0.2, 0.3])


def test_image_folder_source_names_unreadable_and_resized_images(tmp_path: Path) -> None:
    folder = write_pngs(tmp_path / "imgs", 2)
    (folder / "000002.png").write_bytes(b"broken")
    with pytest.raises(CaptureError, match="000002.png: unreadable"):
        list(ImageFolderSource(folder, fps=30))
    (folder / "000002.png").unlink()
    cv2.imwrite(str(folder / "000002.png"), np.zeros((10, 10, 3), np.uint8))
    with pytest.raises(CaptureError, match="one size"):
        list(ImageFolderSource(folder, fps=30))
    with pytest.raises(CaptureError, match="no images"):
        ImageFolderSource(tmp_path, fps=30)


def make_capture(folder: Path, counts: dict[str, int], kind: str = "video") -> list[Camera]:
    folder.mkdir(parents=True, exist_ok=True)
    cams = [Camera.from_fov(name, W, H, 60) for name in counts]
    for name, n in counts.items():
        if kind == "video":
            write_video(folder / f"{name}.mp4", n)
        else:
            write_pngs(folder / name, n)
    write_calib(folder / "calib.json", cams)
    return cams


@pytest.mark.parametrize("kind", ["video", "png"])
def test_capture_folder_yields_synchronized_sets_in_calib_order(tmp_path: Path, kind: str) -> None:
    make_capture(tmp_path / "cap", {"cam0": 4, "cam1": 4}, kind)
    with CaptureFolderSource(tmp_path / "cap") as src:
        assert src.cameras is not None and [c.name for c in src.cameras] == ["cam0", "cam1"]
        sets = list(src)
    assert len(sets) == 4
    assert all([f.camera for f in fs] == ["cam0", "cam1"] for fs in sets)
    assert all(f.t == fs.t and f.index == fs.index for fs in sets for f in fs)


def test_capture_folder_warns_and_stops_at_shortest_camera(tmp_path: Path) -> None:
    make_capture(tmp_path / "cap", {"cam0": 5, "cam1": 3}, "png")
    with pytest.warns(UserWarning, match="cam0=5, cam1=3"):
        src = CaptureFolderSource(tmp_path / "cap")
    assert len(list(src)) == 3


def test_capture_folder_png_rate_comes_from_truth_jsonl(tmp_path: Path) -> None:
    make_capture(tmp_path / "cap", {"cam0": 2}, "png")
    (tmp_path / "cap" / "truth.jsonl").write_text(
        '{"frame": 0, "t": 0.0, "joints": {}}\n{"frame": 1, "t": 0.02, "joints": {}}\n'
    )
    assert CaptureFolderSource(tmp_path / "cap").fps == pytest.approx(50.0)


def test_capture_folder_rejects_missing_calib_frames_and_size(tmp_path: Path) -> None:
    folder = tmp_path / "cap"
    folder.mkdir()
    write_video(folder / "cam0.mp4", 2)
    with pytest.raises(CaptureError, match="lacks calib.json"):
        CaptureFolderSource(folder)
    write_calib(folder / "calib.json", [Camera.from_fov(n, W, H, 60) for n in ("cam0", "cam1")])
    with pytest.raises(CaptureError, match="no cam1.mp4"):
        CaptureFolderSource(folder)
    write_calib(folder / "calib.json", [Camera.from_fov("cam0", 2 * W, 2 * H, 60)])
    with pytest.raises(CaptureError, match="with_size"):
        CaptureFolderSource(folder)


class FakeDevice:
    """Stands in for cv2.VideoCapture on a webcam: serves n frames."""

    def __init__(self, n: int, opened: bool = True) -> None:
        self.n, self.opened, self.released, self.i = n, opened, False, 0

    def isOpened(self) -> bool:  # noqa: N802 - OpenCV's name
        return self.opened

    def set(self, prop: int, value: float) -> bool:
        return True

    def get(self, prop: int) -> float:
        return {cv2.CAP_PROP_FRAME_WIDTH: W, cv2.CAP_PROP_FRAME_HEIGHT: H}.get(prop, 0.0)

    def read(self) -> tuple[bool, np.ndarray | None]:
        if self.i >= self.n:
            return False, None
        self.i += 1
        return True, bgr_frame(self.i)

    def release(self) -> None:
        self.released = True


def test_webcam_timestamps_come_from_the_injected_clock() -> None:
    ticks = iter([100.0, 100.05, 100.09])
    device = FakeDevice(3)
    src = WebcamSource(1, clock=lambda: next(ticks), opener=lambda i: device)
    frames = iter(src)
    sets = [next(frames) for _ in range(3)]
    with pytest.raises(CaptureError, match="webcam 1: no frame"):  # unplugged: an error,
        next(frames)                                               # not the end
    assert [fs.t for fs in sets] == pytest.approx([0.0, 0.05, 0.09])
    assert sets[0][0].camera == "cam1" and src.size == (W, H)
    src.close()
    assert device.released


def test_webcam_that_cannot_open_fails_clearly() -> None:
    with pytest.raises(CaptureError, match="cannot open webcam 7"):
        WebcamSource(7, opener=lambda i: FakeDevice(0, opened=False))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(CaptureError, match="cannot open webcam 99"):
            WebcamSource(99)  # the real OpenCV backend, no such device here


def test_open_source_reads_webcam_and_webcam_colon_index_as_a_webcam() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(CaptureError, match="cannot open webcam 98"):
            open_source("webcam:98")  # the real OpenCV backend, no such device here
        with pytest.raises(CaptureError, match="cannot open webcam 97"):
            open_source(" WebCam:97 ")
    with pytest.raises(CaptureError, match="must be a number, as in webcam:1"):
        open_source("webcam:front")


def test_open_source_picks_the_source_by_what_it_is_given(tmp_path: Path) -> None:
    make_capture(tmp_path / "cap", {"cam0": 2})
    assert isinstance(open_source(tmp_path / "cap"), CaptureFolderSource)
    assert isinstance(open_source(str(tmp_path / "cap" / "cam0.mp4")), VideoFileSource)
    src = open_source(write_pngs(tmp_path / "imgs", 2), fps=12)
    assert isinstance(src, ImageFolderSource) and src.fps == 12
    with pytest.raises(CaptureError, match="no such file"):
        open_source(tmp_path / "missing")
    with pytest.raises(CaptureError, match="cannot open webcam 98"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        open_source("98")
