"""The API against the engine's ground truth and the command line: Rig, stereo, frames, synth, parameters,
evaluate, the file helpers."""
import json
import subprocess

import numpy as np
import pytest

import tissuemosaic as tm
from examples import example_module

first_tum_pose = example_module("reconstruct_video").first_tum_pose


@pytest.fixture(scope="module")
def pair(out_dir):
    return tm.synth.pair(width=320, height=180, seed=2, out=out_dir / "pair")


def nan_equal(a, b):
    return np.array_equal(np.isnan(a), np.isnan(b)) and np.array_equal(a[~np.isnan(a)], b[~np.isnan(b)])


def test_help_and_stubs():
    assert "RGB" in tm.stereo.__doc__ and "bgr" in tm.stereo.__doc__
    assert "T_world_camera" in tm.FrameResult.pose.__doc__
    import pathlib
    stubs = pathlib.Path(tm.__file__).with_name("__init__.pyi").read_text()
    for name in tm.__all__:
        assert name in stubs, name


def test_stereo_matches_ground_truth_and_the_cli(pair, out_dir, cli):
    result = tm.stereo(pair["left"], pair["right"], device="cpu", explain=True)
    assert result.disparity.dtype == np.float32 and result.disparity.shape == (180, 320)
    score = tm.score_disparity(result.disparity, pair["disparity"])
    # The synthetic pair is matched nearly whole and within 2 px nearly everywhere (docs/STEREO.md's figures).
    assert score["density"] > 0.9 and score["bad2"] < 0.05
    assert result.explanation["pixels"] == 320 * 180
    assert result.depth_mm is None  # no rig, no depth
    # The same disparity as `tissuemosaic stereo`, bit for bit.
    subprocess.run([cli, "stereo", "--left", out_dir / "pair" / "left.png", "--right", out_dir / "pair" / "right.png",
                    "--device", "cpu", "--out", out_dir / "cli.pfm"], check=True, stdout=subprocess.DEVNULL)
    assert nan_equal(tm.read_pfm(out_dir / "cli.pfm"), result.disparity)
    # A fixed range is honoured.
    fixed = tm.stereo(pair["left"], pair["right"], device="cpu", disparity_range=(0, 40))
    assert fixed.disparity_range == (0, 40)


def test_rgb_and_bgr_give_the_same_disparity(pair):
    rgb = tm.stereo(pair["left"], pair["right"], device="cpu").disparity
    bgr = tm.stereo(np.ascontiguousarray(pair["left"][:, :, ::-1]), np.ascontiguousarray(pair["right"][:, :, ::-1]),
                    device="cpu", bgr=True).disparity
    assert nan_equal(rgb, bgr)
    swapped = tm.stereo(pair["left"], pair["right"], device="cpu", bgr=True).disparity  # control: colours mixed up
    assert not nan_equal(rgb, swapped)


def test_raw_pair_with_its_rig_gives_depth(pair, out_dir):
    rig = tm.Rig.from_file(out_dir / "pair" / "rig.yml")
    assert rig.layout and rig.image_size == (320, 180) and not rig.frames_rectified
    result = tm.stereo(pair["left_raw"], pair["right_raw"], rig=rig, device="cpu")
    known = ~np.isnan(result.depth_mm) & ~np.isnan(pair["depth_mm"])
    assert known.mean() > 0.8
    # Depth within 1 % of the true depth (about 85 mm) at most pixels.
    error = np.abs(result.depth_mm[known] - pair["depth_mm"][known]) / pair["depth_mm"][known]
    assert np.median(error) < 0.01
    intrinsics = rig.intrinsics()
    assert intrinsics["width"] == 320 and intrinsics["baseline_mm"] == pytest.approx(5.0, rel=0.05)
    maps = rig.maps()
    map_x, map_y = maps["left"]
    assert map_x.shape == (180, 320) and map_x.dtype == np.float32
    assert 0 <= map_x[90, 160] < 320 and 0 <= map_y[90, 160] < 180
    left, right = rig.rectify(pair["left_raw"], pair["right_raw"])
    assert left.shape == (180, 320, 3)


def test_pinhole_rig(pair):
    rig = tm.Rig.rectified(focal_px=333.0, baseline_mm=5.0, image_size=(320, 180))
    intrinsics = rig.intrinsics()
    assert (intrinsics["cx_px"], intrinsics["cy_px"], intrinsics["doffs_px"]) == (159.5, 89.5, 0.0)
    assert rig.frames_rectified and rig.layout is None
    with pytest.raises(tm.Error, match="no rectification maps"):
        rig.maps()


def test_frames_read_the_cli_inputs(out_dir):
    scan = tm.synth.scan(out_dir / "scan", frames=6, width=320, height=180, seed=3, video=out_dir / "scan.avi")
    folders = list(tm.frames(left_frames=scan["left_frames"], right_frames=scan["right_frames"], fps=10))
    assert [round(time_s, 6) for _, _, time_s in folders] == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
    assert folders[0][0].shape == (180, 320, 3) and folders[0][0].dtype == np.uint8
    video = tm.frames(video=scan["video"], layout="sbs")
    assert video.frame_size == (320, 180) and video.frame_count == 6
    assert len(list(video)) == 6
    first_bgr = next(iter(tm.frames(left_frames=scan["left_frames"], right_frames=scan["right_frames"], bgr=True)))
    assert np.array_equal(first_bgr[0][:, :, ::-1], folders[0][0])
    assert len(list(tm.frames(left_frames=scan["left_frames"], right_frames=scan["right_frames"], max_frames=2))) == 2


def test_live_model_follows_breathing_tissue(out_dir, cli):
    # A still scope over a 3 mm swell: with the deformation on, live_model() is model() moved where the tissue is
    # (the same points, the swell's risen); without it, live_model() is model().
    folder = out_dir / "breathing"
    subprocess.run([cli, "synth", "scan", "--out", str(folder), "--frames", "12", "--width", "320", "--height", "240",
                    "--supersampling", "1", "--min-speed", "0", "--max-speed", "0", "--breathing-mm", "3",
                    "--breathing-period-s", "0.8", "--breathing-radius-mm", "14"], check=True, capture_output=True)
    rig = tm.Rig.from_file(folder / "rig.yml", rectified=True)
    rigid = tm.Reconstruction(rig, device="cpu")
    deforming = tm.Reconstruction(rig, params={"fusion": {"deformation": "on"}}, device="cpu")
    for left, right, time_s in tm.frames(left_frames=folder / "left", right_frames=folder / "right", fps=30):
        rigid.process(left, right, time_s)
        deforming.process(left, right, time_s)
    assert np.array_equal(rigid.live_model().points, rigid.model().points)
    rest, live = deforming.model().points, deforming.live_model().points
    assert rest.shape == live.shape and len(rest) > 1000
    moved = np.linalg.norm(live - rest, axis=1)
    assert moved.max() > 1.0, "the swell rose: some points must have moved"
    assert np.median(moved) < 0.5, "most tissue is still"


def test_parameters_as_a_dict(pair):
    defaults = tm.default_params()
    assert defaults["stereo"]["znccWindowPx"] == 11  # the paper's 11x11 window
    reconstruction = tm.Reconstruction(pair["rectified_rig"], params=defaults, device="cpu")
    assert reconstruction.process(pair["left"], pair["right"], 0.0).status == "tracked"
    census = tm.stereo(pair["left"], pair["right"], params={"stereo": {"method": "ad-census"}}, device="cpu")
    paper = tm.stereo(pair["left"], pair["right"], device="cpu")
    assert not nan_equal(census.disparity, paper.disparity)


def test_frame_result(pair):
    reconstruction = tm.Reconstruction(pair["rectified_rig"], device="cpu", keep_disparity=True)
    first = reconstruction.process(pair["left"], pair["right"], 0.0)
    assert first.status == "tracked" and first.is_key_frame and first.frame_index == 0
    assert first.pose.shape == (4, 4) and np.array_equal(first.pose, np.eye(4))
    assert first.disparity.shape == (180, 320)
    second = reconstruction.process(pair["left"], pair["right"], 1 / 30)
    assert second.agreement["level"] in ("none", "good", "fair", "poor")
    assert second.engine_ms > 0 and second.times_ms["total"] > 0
    timing = reconstruction.timing()
    assert timing["key_frames"]["count"] + timing["other_frames"]["count"] == 2
    assert "stereo" in reconstruction.timing_table()
    start = np.eye(4)
    start[:3, 3] = [1.0, 2.0, 3.0]
    moved = tm.Reconstruction(pair["rectified_rig"], device="cpu", start_pose=start)
    assert np.array_equal(moved.process(pair["left"], pair["right"], 0.0).pose, start)


def test_evaluate_gives_the_cli_figures(out_dir, cli, with_gui):
    if not with_gui:  # a build without the VTK logic says so (test_errors checks the message)
        with pytest.raises(ValueError):
            tm.evaluate(np.zeros((3, 3)), out_dir / "none.ply")
        return
    scan = tm.synth.scan(out_dir / "eval_scan", frames=20, width=320, height=180, seed=3)
    # Started at the true first pose, the model lies on the reference (a misplaced one takes 10 s to score).
    reconstruction = tm.Reconstruction(tm.Rig.from_file(scan["rig"], rectified=True), device="cpu",
                                       start_pose=first_tum_pose(scan["trajectory"]))
    for left, right, time_s in tm.frames(left_frames=scan["left_frames"], right_frames=scan["right_frames"]):
        reconstruction.process(left, right, time_s)
    reconstruction.save(out_dir / "eval.ply")
    figures = tm.evaluate(out_dir / "eval.ply", scan["surface"])
    printed = subprocess.run([cli, "eval", "--model", out_dir / "eval.ply", "--reference", scan["surface"], "--json"],
                             check=True, capture_output=True, text=True).stdout
    assert figures == json.loads(printed)
    assert list(figures)[:6] == ["rmse_mm", "mean_mm", "p95_mm", "coverage", "ate_mm", "rpe_mm"]
    # From memory (the Model) the same figures as from the file.
    assert tm.evaluate(reconstruction.model(), scan["surface"]) == figures
    assert figures["points"] == len(reconstruction.model()) and figures["rmse_mm"] < 1.0


LAYOUTS = {
    # docs/CALIBRATION.md's minimal examples, the same rig in four layouts (ROS: 780 px, 5 mm after rectification).
    "opencv": {"rig.yml": "%YAML:1.0\n---\nimageSize: [640, 480]\nK1: [[800, 0, 320], [0, 800, 240], [0, 0, 1]]\n"
                          "D1: [-0.1, 0.01, 0, 0, 0]\nK2: [[800, 0, 315], [0, 800, 240], [0, 0, 1]]\n"
                          "D2: [-0.1, 0.01, 0, 0, 0]\nR: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nT: [-5, 0, 0]\n"},
    "stereo_calib": {"intrinsics.yml": "%YAML:1.0\n---\nM1: [[800, 0, 320], [0, 800, 240], [0, 0, 1]]\n"
                                       "D1: [-0.1, 0.01, 0, 0, 0]\nM2: [[800, 0, 315], [0, 800, 240], [0, 0, 1]]\n"
                                       "D2: [-0.1, 0.01, 0, 0, 0]\n",
                     "extrinsics.yml": "%YAML:1.0\n---\nR: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nT: [-5, 0, 0]\n"},
    "kalibr": {"camchain.yaml": "cam0:\n  camera_model: pinhole\n  intrinsics: [800, 800, 320, 240]\n"
                                "  distortion_model: radtan\n  distortion_coeffs: [-0.1, 0.01, 0, 0]\n"
                                "  resolution: [640, 480]\ncam1:\n  camera_model: pinhole\n"
                                "  intrinsics: [800, 800, 315, 240]\n  distortion_model: radtan\n"
                                "  distortion_coeffs: [-0.1, 0.01, 0, 0]\n  resolution: [640, 480]\n"
                                "  T_cn_cnm1:\n  - [1, 0, 0, -0.005]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n"
                                "  - [0, 0, 0, 1]\n"},
}


@pytest.mark.parametrize("layout", sorted(LAYOUTS))
def test_every_calibration_layout_gives_the_same_rig(layout, out_dir):
    folder = out_dir / "layouts" / layout
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in LAYOUTS[layout].items():
        (folder / name).write_text(text)
    main_file = {"opencv": "rig.yml", "stereo_calib": "intrinsics.yml", "kalibr": "camchain.yaml"}[layout]
    rig = tm.Rig.from_file(folder / main_file,
                           extrinsics=folder / "extrinsics.yml" if layout == "stereo_calib" else None)
    assert rig.layout
    intrinsics = rig.intrinsics(image_size=(640, 480))  # stereo_calib files carry no image size
    reference = tm.Rig.from_file(reference_rig(out_dir)).intrinsics()
    for key in ("focal_px", "cx_px", "cy_px", "baseline_mm"):
        assert intrinsics[key] == pytest.approx(reference[key], rel=1e-9, abs=1e-9), key


def reference_rig(out_dir):
    path = out_dir / "layouts" / "reference.yml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(LAYOUTS["opencv"]["rig.yml"])
    return path


def test_ros_camera_info_pair(out_dir):
    folder = out_dir / "layouts" / "ros"
    folder.mkdir(parents=True, exist_ok=True)
    eye = ("image_width: 640\nimage_height: 480\ncamera_name: stereo/{name}\n"
           "camera_matrix: {{rows: 3, cols: 3, data: [800, 0, 320, 0, 800, 240, 0, 0, 1]}}\n"
           "distortion_model: plumb_bob\n"
           "distortion_coefficients: {{rows: 1, cols: 5, data: [-0.1, 0.01, 0, 0, 0]}}\n"
           "rectification_matrix: {{rows: 3, cols: 3, data: [1, 0, 0, 0, 1, 0, 0, 0, 1]}}\n"
           "projection_matrix: {{rows: 3, cols: 4, data: [780, 0, 318, {tx}, 0, 780, 241, 0, 0, 0, 1, 0]}}\n")
    (folder / "left.yaml").write_text(eye.format(name="left", tx=0))
    (folder / "right.yaml").write_text(eye.format(name="right", tx=-3.9))
    rig = tm.Rig.from_file(folder / "left.yaml", right=folder / "right.yaml")
    intrinsics = rig.intrinsics()
    assert rig.image_size == (640, 480)
    assert (intrinsics["focal_px"], intrinsics["cx_px"], intrinsics["cy_px"]) == (780, 318, 241)
    assert intrinsics["baseline_mm"] == pytest.approx(5.0)
    with pytest.raises(ValueError, match="not both"):
        tm.Rig.from_file(folder / "left.yaml", right=folder / "right.yaml", extrinsics=folder / "right.yaml")
