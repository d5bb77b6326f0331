"""Two reconstructions processed at once on two threads give what each gives alone: they share no state, and the
GIL, released while the engine works, lets them run side by side."""
import re
import sys
import threading
import time

import numpy as np
import pytest

import tissuemosaic as tm


@pytest.fixture(scope="module")
def two_inputs(out_dir):
    inputs = []
    for seed in (3, 4):
        scan = tm.synth.scan(out_dir / f"scan{seed}", frames=25, width=320, height=180, seed=seed)
        rig = tm.Rig.from_file(scan["rig"], rectified=True)
        frames = list(tm.frames(left_frames=scan["left_frames"], right_frames=scan["right_frames"]))
        inputs.append((rig, frames))
    return inputs


def reconstruct(rig, frames):
    reconstruction = tm.Reconstruction(rig, device="cpu")
    poses = [reconstruction.process(left, right, time_s).pose for left, right, time_s in frames]
    model = reconstruction.model()
    return np.stack(poses), model.points.copy(), model.colours.copy()


def same(a, b):
    return all(np.array_equal(x, y) for x, y in zip(a, b))


def test_two_threads_give_what_each_gives_alone(two_inputs):
    alone = [reconstruct(rig, frames) for rig, frames in two_inputs]
    together = [None, None]

    def work(slot):
        together[slot] = reconstruct(*two_inputs[slot])

    threads = [threading.Thread(target=work, args=(slot,)) for slot in (0, 1)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert together[0] is not None and together[1] is not None
    assert len(alone[0][1]) > 1000 and len(alone[1][1]) > 1000
    assert same(together[0], alone[0])
    assert same(together[1], alone[1])
    # Control: the two inputs give different results, so a mix-up between the threads would show.
    assert not same(alone[0], alone[1])


def test_one_reconstruction_from_two_threads_takes_frames_one_at_a_time(two_inputs):
    # Calls on one object are serialised (never a crash); frame order between threads is the caller's business.
    rig, frames = two_inputs[0]
    reconstruction = tm.Reconstruction(rig, device="cpu")
    errors = []

    def work(part):
        try:
            for left, right, time_s in part:
                reconstruction.process(left, right, time_s)
        except Exception as error:  # noqa: BLE001 (reported below)
            errors.append(error)

    threads = [threading.Thread(target=work, args=(frames[slot::2],)) for slot in (0, 1)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors
    assert reconstruction.frame_count == len(frames)


def progress_during(call, repeats):
    """How far a counter on another thread got during each of `repeats` calls of call(). The switch interval is set
    so long that the interpreter never takes the GIL from a thread: the counter, which gives it up at each step
    (time.sleep(0)), advances only while call() has released it, and stands still while call() holds it."""
    counter = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            counter[0] += 1
            time.sleep(0)

    interval = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)
    thread = threading.Thread(target=count)
    thread.start()
    try:
        progress = []
        for _ in range(repeats):
            before = counter[0]
            call()
            progress.append(counter[0] - before)
        return progress
    finally:
        stop.set()
        thread.join()
        sys.setswitchinterval(interval)


def test_the_gil_is_released_while_the_engine_works(two_inputs):
    rig, frames = two_inputs[0]
    reconstruction = tm.Reconstruction(rig, device="cpu")
    frames_left = iter(frames)

    def process():
        left, right, time_s = next(frames_left)
        reconstruction.process(left, right, time_s)

    processing = progress_during(process, 9)
    left, right, _ = frames[0]
    matching = progress_during(lambda: tm.stereo(left, right, device="cpu"), 5)
    # Control: a regular expression that backtracks for a while (about 50 ms) holds the GIL throughout.
    backtracking = re.compile(r"(a|aa)+$")
    holding = progress_during(lambda: backtracking.match("a" * 28 + "b"), 5)
    print("counter steps per call: process", processing, "stereo", matching, "a GIL-holding call", holding)
    assert all(steps > 1 for steps in processing)
    assert all(steps > 1 for steps in matching)
    assert all(steps <= 1 for steps in holding)
