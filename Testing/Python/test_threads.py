"""Two reconstructions processed at once on two threads give what each gives alone: they share no state, and the
GIL, released while the engine works, lets them run side by side."""
import threading

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
