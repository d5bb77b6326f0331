"""Every error path raises a Python exception carrying the engine's (the command line's) message."""
import numpy as np
import pytest

import tissuemosaic as tm


@pytest.fixture(scope="module")
def pair():
    return tm.synth.pair(width=320, height=180, seed=2)


def test_engine_errors_are_value_errors():
    assert issubclass(tm.Error, ValueError)


def test_missing_calibration_file(out_dir):
    with pytest.raises(tm.Error, match=r"cannot read stereo calibration '.*no-such-rig\.yml'.*file does not exist"):
        tm.Rig.from_file(out_dir / "no-such-rig.yml")


def test_bad_calibration_names_the_key(out_dir):
    path = out_dir / "bad-rig.yml"
    path.write_text("%YAML:1.0\nK1: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: [1,0,0,0,1,0,0,0,1]\n")
    with pytest.raises(tm.Error, match=r"cannot read stereo calibration"):
        tm.Rig.from_file(path)


def test_malformed_calibration(out_dir):
    path = out_dir / "malformed.yml"
    path.write_text("K1: [1, 2\n  - : :\n")
    with pytest.raises(tm.Error, match=r"cannot read stereo calibration"):
        tm.Rig.from_file(path)


def test_calibration_for_other_frames(pair, out_dir):
    tm.synth.pair(width=320, height=180, seed=2, out=out_dir / "pair")  # rig.yml for 320x180
    rig = tm.Rig.from_file(out_dir / "pair" / "rig.yml")
    small = np.zeros((90, 160, 3), np.uint8)
    with pytest.raises(tm.Error, match=r"the calibration is for 320x180 but the frames of .* are 160x90"):
        tm.Reconstruction(rig, device="cpu").process(small, small, 0.0)


def test_mismatched_sizes(pair):
    reconstruction = tm.Reconstruction(pair["rectified_rig"], device="cpu")
    with pytest.raises(tm.Error, match=r"the left frame is 320x180 but the right one 160x90"):
        reconstruction.process(pair["left"], pair["right"][:90, :160].copy(), 0.0)
    with pytest.raises(tm.Error, match=r"the left image is 320x180 but the right one 160x90"):
        tm.stereo(pair["left"], pair["right"][:90, :160].copy())


def test_wrong_dtype_and_shape(pair):
    reconstruction = tm.Reconstruction(pair["rectified_rig"], device="cpu")
    with pytest.raises(TypeError, match=r"left: expected a uint8 image array, got dtype float32"):
        reconstruction.process(pair["left"].astype(np.float32), pair["right"], 0.0)
    with pytest.raises(ValueError, match=r"right: expected an HxWx3 \(RGB\) or HxW \(grey\) image, got shape \(180, 320, 4\)"):
        reconstruction.process(pair["left"], np.zeros((180, 320, 4), np.uint8), 0.0)
    with pytest.raises(ValueError, match=r"left: the image's pixels are not packed"):
        reconstruction.process(pair["left"][:, :, ::-1], pair["right"], 0.0)
    with pytest.raises(ValueError, match=r"left: the image is empty"):
        tm.stereo(np.zeros((0, 10, 3), np.uint8), np.zeros((0, 10, 3), np.uint8))
    with pytest.raises(TypeError):
        reconstruction.process("left.png", pair["right"], 0.0)


def test_unknown_parameter_names_the_nearest(pair):
    with pytest.raises(tm.Error, match=r"unknown key 'znccWindw' in node 'stereo' \(did you mean 'znccWindowPx'\?\)"):
        tm.Reconstruction(pair["rectified_rig"], params={"stereo": {"znccWindw": 11}})
    with pytest.raises(tm.Error, match=r"cannot open parameters file '.*missing\.yml': file does not exist"):
        tm.Reconstruction(pair["rectified_rig"], params="missing.yml")


def test_out_of_range_parameter(pair):
    with pytest.raises(tm.Error, match=r"znccWindowPx"):
        tm.Reconstruction(pair["rectified_rig"], params={"stereo": {"znccWindowPx": -3}})


def test_devices(pair):
    with pytest.raises(tm.Error, match=r"^device: unknown device 'gpu': expected cpu, cuda or auto$"):
        tm.stereo(pair["left"], pair["right"], device="gpu")
    if not tm.cuda_available():
        with pytest.raises(tm.Error, match=r"^device: cuda was asked for, but .*CUDA"):
            tm.Reconstruction(pair["rectified_rig"], device="cuda")


def test_disparity_range_arguments(pair):
    with pytest.raises(ValueError, match=r"min_px < max_px"):
        tm.stereo(pair["left"], pair["right"], disparity_range=(5, 2))
    with pytest.raises(ValueError, match=r"disparity_range: expected \"auto\""):
        tm.stereo(pair["left"], pair["right"], disparity_range="wide")
    with pytest.raises(tm.Error, match=r"the disparity range 400\.\.500 px lies beyond the 320-pixel-wide frames"):
        tm.stereo(pair["left"], pair["right"], disparity_range=(400, 500))
    with pytest.raises(tm.Error, match=r"the disparity range 400\.\.500 px lies beyond the 320-pixel-wide frames"):
        tm.Reconstruction(pair["rectified_rig"], params={"stereo": {"disparityRange": "fixed", "minDisparityPx": 400,
                                                                    "maxDisparityPx": 500}})
    # A featureless pair: the automatic range has too few matches, and says so.
    grey = np.full((180, 320, 3), 128, np.uint8)
    with pytest.raises(tm.Error, match=r"match"):
        tm.stereo(grey, grey)


def test_pinhole_values(pair):
    # The engine names the value, the module its argument (the command line names its option instead).
    with pytest.raises(tm.Error, match=r"^focal_px: the focal length must be a positive number of pixels, not -1$"):
        tm.Rig.rectified(focal_px=-1, baseline_mm=5, image_size=(320, 180))
    with pytest.raises(tm.Error, match=r"^cx_px: the principal point's x 5000 px lies far outside"):
        tm.Rig.rectified(focal_px=300, baseline_mm=5, cx_px=5000, image_size=(320, 180))
    with pytest.raises(tm.Error, match=r"does not know its image size"):
        tm.Rig.rectified(focal_px=300, baseline_mm=5).intrinsics()


def test_inputs(out_dir):
    with pytest.raises(tm.Error, match=r"give exactly one input"):
        tm.frames()
    with pytest.raises(tm.Error, match=r"left and right frame folders go together"):
        tm.frames(left_frames=out_dir)
    with pytest.raises(tm.Error, match=r"frame folder '.*nowhere' does not exist"):
        tm.frames(left_frames=out_dir / "nowhere", right_frames=out_dir / "nowhere")
    with pytest.raises(tm.Error, match=r"cannot open video '.*none\.avi': file does not exist"):
        tm.frames(video=out_dir / "none.avi")
    with pytest.raises(ValueError, match=r"fps"):
        tm.frames(video=out_dir / "none.avi", fps=0)


def test_outputs_and_queries(pair, out_dir):
    reconstruction = tm.Reconstruction(pair["rectified_rig"], device="cpu")
    with pytest.raises(tm.Error, match=r"no model points"):
        reconstruction.save(out_dir / "empty.ply")
    reconstruction.process(pair["left"], pair["right"], 0.0)
    with pytest.raises(tm.Error, match=r"^path: '.*model\.obj': the model is written as \.ply or \.vtp"):
        reconstruction.save(out_dir / "model.obj")
    with pytest.raises(ValueError, match=r"key_frames"):
        reconstruction.trajectory("bogus")
    with pytest.raises(tm.Error, match=r"no-such\.pfm"):
        tm.read_pfm(out_dir / "no-such.pfm")


def test_evaluate_errors(out_dir, with_gui):
    points = np.zeros((10, 3), np.float32)
    if not with_gui:
        with pytest.raises(ValueError, match=r"needs the VTK logic"):
            tm.evaluate(points, out_dir / "none.ply")
        return
    with pytest.raises(tm.Error, match=r"none\.ply"):
        tm.evaluate(points, out_dir / "none.ply")
    with pytest.raises(tm.Error, match=r"no finite point"):
        tm.evaluate(np.full((4, 3), np.nan), out_dir / "none.ply")
    with pytest.raises(ValueError, match=r"go together"):
        tm.evaluate(points, out_dir / "none.ply", trajectory=np.zeros((2, 8)))


def test_to_open3d_needs_open3d(pair):
    reconstruction = tm.Reconstruction(pair["rectified_rig"], device="cpu")
    reconstruction.process(pair["left"], pair["right"], 0.0)
    model = reconstruction.model()
    try:
        import open3d  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match=r"python3-open3d"):
            model.to_open3d()
        return
    cloud = model.to_open3d()
    assert len(cloud.points) == len(model)
