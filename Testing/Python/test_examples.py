"""The two example scripts on synthetic data: stereo scored on a folder of pairs with ground truth, and a video
reconstructed into a model, scored against the true surface."""
import numpy as np
import tissuemosaic as tm
from examples import run_example


def stereo_meets_bars(report):
    # Measured 2026-11-28 (320x180, seeds 1 and 2): density 0.984, bad-2 0.002, mean error 0.143 px. Requirement:
    # density >= 0.9, bad-2 <= 0.05 (docs/STEREO.md's synthetic figures). Regression: twice the measured shortfall
    # and error (density >= 0.968, mean error <= 0.29 px); bad-2 <= 0.01 (5x: a few pixels more at this size).
    return (report["mean_density"] >= 0.968 and report["mean_bad2"] <= 0.01
            and report["mean_mean_abs_error_px"] <= 0.29)


def test_stereo_example_on_synthetic_pairs(out_dir):
    for seed in (1, 2):
        tm.synth.pair(width=320, height=180, seed=seed, out=out_dir / "pairs" / f"seed{seed}")
    report = run_example("stereo_on_pairs.py", out_dir / "pairs", "--device", "cpu")
    print(report)
    assert sorted(report["scenes"]) == ["seed1", "seed2"]
    assert stereo_meets_bars(report)
    # Control: a ground truth 3 px off fails the same bars.
    for seed in (1, 2):
        folder = out_dir / "pairs" / f"seed{seed}"
        tm.write_pfm(folder / "disparity.pfm", tm.read_pfm(folder / "disparity.pfm") + 3.0)
    assert not stereo_meets_bars(run_example("stereo_on_pairs.py", out_dir / "pairs", "--device", "cpu"))


def test_reconstruct_example_on_a_video(out_dir, with_gui):
    scan = tm.synth.scan(out_dir / "scan", frames=40, width=320, height=180, seed=3, video=out_dir / "scan.avi")
    model, trajectory = out_dir / "model.ply", out_dir / "keyframes.txt"
    report = run_example("reconstruct_video.py", "--video", scan["video"], "--calib", scan["rig"], "--rectified",
                         "--device", "cpu", "--out", model, "--trajectory", trajectory,
                         "--start-tum", scan["trajectory"])
    print({key: value for key, value in report.items() if key != "timing"})
    assert report["frames"] == 40 and report.get("tracked", 0) >= 35
    assert report["model_points"] > 5000 and model.stat().st_size > 0 and trajectory.stat().st_size > 0
    if not with_gui:
        return
    # Started at the true first pose, the model and its key frames are in the reference's frame already.
    figures = tm.evaluate(model, scan["surface"], trajectory=trajectory, reference_trajectory=scan["trajectory"],
                          trajectory_alignment="none")
    print(figures)
    # Measured 2026-11-28: RMSE 0.47 mm, coverage 0.887, ATE 0.17 mm. Requirement: within 1 mm RMS of the true
    # surface (320x180 from an MJPG video is coarser than docs/EVALUATION.md's 960x540), half of it covered.
    # Regression: twice the RMSE (0.94, inside the requirement) and twice the uncovered share (coverage >= 0.77).
    assert figures["rmse_mm"] <= 0.94
    assert figures["coverage"] >= 0.77
    assert figures["ate_mm"] <= 0.5  # requirement 1 mm; regression 2 x 0.17 (rounded up)
    # Control: the same model 5 mm deeper fails the same bar.
    points = tm.read_model(model).points + np.array([0, 0, 5.0], np.float32)
    moved = tm.evaluate(points, scan["surface"], trajectory_alignment="none")
    assert moved["rmse_mm"] > 1.0
