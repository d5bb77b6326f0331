"""1000 frames through Reconstruction.process leak no memory: the resident set stops growing once the model is
built. A still scope over a still scene (the same pair each frame) keeps the engine's own state (key frames, model)
constant, so what grows is a leak of the binding or the engine per frame."""
import numpy as np

import tissuemosaic as tm

FRAMES = 1000
WARM_UP = 200
# A leak of one 192x108 RGB frame (61 kB) per frame would add 49 MB over the 800 frames measured. Measured
# 2026-11-28: 0.84 MB (1 kB a frame: the allocators' arenas settling). The limit, 4 MB (5 kB a frame), is the
# regression bar and the requirement's reading of "no leak" at once.
LIMIT_MB = 4.0


def resident_mb() -> float:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise AssertionError("no VmRSS in /proc/self/status")


def run(frames, keep=None):
    pair = tm.synth.pair(width=192, height=108, seed=5)
    reconstruction = tm.Reconstruction(pair["rectified_rig"], device="cpu")
    left, right = pair["left"], pair["right"]
    rss = {}
    for index in range(frames):
        result = reconstruction.process(left, right, index / 30.0)
        assert result.status in ("tracked", "relocalised")
        if keep is not None:
            keep.append(left.copy())  # the control's deliberate leak
        if index % 100 == 0:
            reconstruction.model()  # the model's copy must be freed too
        if index + 1 in (WARM_UP, frames):
            rss[index + 1] = resident_mb()
    return rss[frames] - rss[WARM_UP], reconstruction


def test_thousand_frames_do_not_grow_memory():
    growth_mb, reconstruction = run(FRAMES)
    print(f"resident memory growth over frames {WARM_UP}..{FRAMES}: {growth_mb:.2f} MB")
    assert reconstruction.frame_count == FRAMES
    assert len(reconstruction.trajectory()) >= 1
    assert growth_mb < LIMIT_MB


def test_the_measure_sees_a_leak():
    # Control: keeping each frame's copy (61 kB) shows as growth far beyond the limit (12 MB over 200 frames).
    kept = []
    growth_mb, _ = run(400, keep=kept)
    assert len(kept) == 400
    assert growth_mb > LIMIT_MB
