// synth.pair() and synth.scan(): the synthetic scenes of `tissuemosaic synth` with exact ground truth.
#include "Arrays.h"
#include "Bindings.h"
#include "Parameters.h"
#include "Rig.h"

#include "Core/Error.h"
#include "IO/ImageFile.h"
#include "SyntheticScan.h"
#include "SyntheticStereoScene.h"

#include <opencv2/videoio.hpp>
#include <pybind11/stl.h>

#include <filesystem>

namespace tissuemosaic::python {

namespace {

std::shared_ptr<Rig> calibrationRig(const StereoCalibration& calibration, bool rectified, const std::string& what) {
  StereoGeometrySpec spec;
  spec.calibration = CalibrationFileContent{calibration, "synthetic"};
  spec.framesRectified = rectified;
  return std::make_shared<Rig>(std::move(spec), what);
}

py::dict pair(int width, int height, int seed, const std::string& preset, const std::string& lighting,
              const py::object& out, bool bgr) {
  require(preset == "default" || preset == "wide", "preset must be 'default' or 'wide', got '" + preset + "'");
  require(seed >= 0, "seed must be a non-negative integer");
  synthetic::SyntheticStereoOptions options = preset == "wide"
                                                  ? synthetic::SyntheticStereoOptions::wideDisparity(width, height)
                                                  : synthetic::SyntheticStereoOptions{};
  options.width = width;
  options.height = height;
  options.seed = static_cast<uint32_t>(seed);
  options.lighting = synthetic::parseSyntheticLighting(lighting);
  const std::string directory = out.is_none() ? std::string() : pathText(out, "out");
  synthetic::SyntheticStereoPair rendered;
  {
    py::gil_scoped_release release;
    rendered = synthetic::renderSyntheticStereoPair(options);
    if (!directory.empty()) synthetic::writeSyntheticStereoPair(rendered, directory);
  }
  py::dict result;
  result["left"] = toUserImage(rendered.leftRectified, bgr);
  result["right"] = toUserImage(rendered.rightRectified, bgr);
  result["left_raw"] = toUserImage(rendered.leftRaw, bgr);
  result["right_raw"] = toUserImage(rendered.rightRaw, bgr);
  result["disparity"] = toArray(rendered.disparityPx);
  result["depth_mm"] = toArray(rendered.depthMm);
  result["highlight_mask"] = toArray(rendered.highlightMaskLeft);
  result["rig"] = calibrationRig(rendered.calibration, false, "synthetic pair's raw rig");
  result["rectified_rig"] = calibrationRig(rendered.calibration, true, "synthetic pair's rig, frames rectified");
  return result;
}

/// The scan's rectified frames side by side in one MJPG AVI (OpenCV's own writer, no codec library): a 3D video
/// for frames(video=..., layout="sbs") and `reconstruct --video`.
void writeSideBySideVideo(const std::filesystem::path& root, int frames, double fps, const std::string& path) {
  cv::VideoWriter writer;
  for (int index = 0; index < frames; ++index) {
    const std::string name = cv::format("%06d.png", index);
    const ImagePair pair = loadImagePair((root / "left" / name).string(), (root / "right" / name).string());
    cv::Mat sideBySide;
    cv::hconcat(pair.left, pair.right, sideBySide);
    if (!writer.isOpened()) {
      writer.open(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, sideBySide.size());
      require(writer.isOpened(), "cannot write the video '" + path + "' (MJPG AVI)");
    }
    writer.write(sideBySide);
  }
}

py::dict scan(const py::object& out, int frames, int width, int height, int seed, double fps,
              const std::string& lighting, const py::object& video) {
  require(seed >= 0, "seed must be a non-negative integer");
  synthetic::SyntheticScanOptions options;
  options.frames = frames;
  options.width = width;
  options.height = height;
  options.seed = static_cast<uint32_t>(seed);
  options.fps = fps;
  options.lighting = synthetic::parseSyntheticLighting(lighting);
  const std::string directory = pathText(out, "out");
  const std::string videoPath = video.is_none() ? std::string() : pathText(video, "video");
  int written = 0;
  RectifiedGeometry geometry;
  {
    py::gil_scoped_release release;
    const synthetic::SyntheticScan scene(options);
    written = synthetic::writeSyntheticScan(scene, directory);
    geometry = scene.geometry();
    if (!videoPath.empty()) writeSideBySideVideo(directory, frames, fps, videoPath);
  }
  const std::filesystem::path root(directory);
  py::dict result;
  result["left_frames"] = (root / "left").string();
  result["right_frames"] = (root / "right").string();
  result["rig"] = (root / "rig.yml").string();
  result["trajectory"] = (root / "groundtruth" / "trajectory.txt").string();
  result["surface"] = (root / "groundtruth" / "surface.ply").string();
  result["files_written"] = written;
  result["video"] = videoPath.empty() ? py::object(py::none()) : py::object(py::str(videoPath));
  result["focal_px"] = geometry.focalPx;
  result["baseline_mm"] = geometry.baselineMm;
  return result;
}

}  // namespace

void bindSynth(py::module_& module) {
  py::module_ synth = module.def_submodule("synth", "synthetic stereo pairs and scans with exact ground truth");
  synth.def("pair", &pair, py::kw_only(), py::arg("width") = 960, py::arg("height") = 540, py::arg("seed") = 1,
            py::arg("preset") = "default", py::arg("lighting") = "standard", py::arg("out") = py::none(),
            py::arg("bgr") = false,
            R"(A synthetic stereo-endoscope pair of liver-like tissue (as ``tissuemosaic synth pair``): a dict with
left, right (rectified, RGB unless bgr), left_raw, right_raw, disparity (float32 px, NaN = unseen), depth_mm,
highlight_mask, rig (the raw rig, a Rig) and rectified_rig (the same rig for the rectified views). out: also write
the files the command writes there. preset: "default" or "wide"; lighting: "standard" or "realistic".)");
  synth.def("scan", &scan, py::arg("out"), py::kw_only(), py::arg("frames") = 120, py::arg("width") = 960,
            py::arg("height") = 540, py::arg("seed") = 1, py::arg("fps") = 30.0, py::arg("lighting") = "standard", py::arg("video") = py::none(),
            R"(Writes a synthetic scanning video into the folder out, as ``tissuemosaic synth scan`` does (rectified
frames in left/ and right/, rig.yml, groundtruth/trajectory.txt, surface.ply, depth). Returns a dict of the paths
(left_frames, right_frames, rig, trajectory, surface), files_written, focal_px and baseline_mm. The frames are
rectified: Rig.from_file(result["rig"], rectified=True). video: also write them side by side into this MJPG AVI
(frames(video=..., layout="sbs")).)");
}

}  // namespace tissuemosaic::python
