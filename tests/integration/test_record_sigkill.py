"""A recording survives its process being SIGKILLed mid-run, losing at most one frame."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from bodyplay.record import read_recording

CHILD = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    from bodyplay.record import RecorderOptions, record_session
    from bodyplay.runtime import ArrayPoseSource, FixedClock, create_session

    n = 100000
    joints = np.zeros((n, 17, 3)) + np.arange(n)[:, None, None] * 1e-3
    s = create_session(source=ArrayPoseSource(joints), clock=FixedClock())
    record_session(s, sys.argv[1], RecorderOptions(fsync="never"))

    def announce(e):
        sys.stdout.write(f"{e.frame}\\n")
        sys.stdout.flush()
        time.sleep(0.002)

    s.subscribe("pose", announce)  # after the recorder: the line is written first
    s.run()
    """
)


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="needs POSIX signals")
def test_recording_is_readable_after_sigkill_losing_at_most_the_frame_in_flight(
    tmp_path: Path,
) -> None:
    path = tmp_path / "killed.jsonl"
    proc = subprocess.Popen([sys.executable, "-c", CHILD, str(path)], stdout=subprocess.PIPE,
                            text=True)
    assert proc.stdout is not None
    last = -1
    deadline = time.monotonic() + 60
    try:
        while last < 40 and time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            last = int(line)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    assert last >= 40, "the child never got going"
    rec = read_recording(path)
    frames = [p.frame for p in rec.poses]
    # every frame announced is on disk, in order, with its data intact
    assert frames[: last + 1] == list(range(last + 1))
    assert frames == list(range(len(frames)))
    np.testing.assert_allclose(rec.joints()[:, 0, 0], np.arange(len(frames)) * 1e-3, atol=1e-6)
