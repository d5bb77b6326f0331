// frames(): the command line's inputs (two frame folders, two videos, a 3D video in a layout) as an iterator of
// (left, right, time_s), rectified when a rig of a calibration is given.
#include "Arrays.h"
#include "Bindings.h"
#include "Parameters.h"
#include "Rig.h"

#include "Core/Error.h"
#include "IO/StereoInput.h"

#include <pybind11/stl.h>

namespace tissuemosaic::python {

namespace {

class FrameIterator {
public:
  FrameIterator(std::unique_ptr<StereoFrameSource> source, std::shared_ptr<Rig> rig, bool bgr, int maxFrames)
      : source_(std::move(source)), bgr_(bgr), maxFrames_(maxFrames) {
    if (rig) geometry_ = rig->resolve(source_->frameSize(), source_->description());
  }

  py::tuple next() {
    if (maxFrames_ >= 0 && returned_ >= maxFrames_) throw py::stop_iteration();
    StereoFrame frame;
    cv::Mat left, right;
    {
      py::gil_scoped_release release;
      if (!source_->next(frame)) {
        left.release();
      } else if (geometry_ && geometry_->rectifier) {
        geometry_->rectifier->rectify(frame.left, frame.right, left, right);
      } else {
        left = frame.left;
        right = frame.right;
      }
    }
    if (left.empty()) throw py::stop_iteration();
    ++returned_;
    return py::make_tuple(toUserImage(left, bgr_), toUserImage(right, bgr_), frame.timeS);
  }

  int frameCount() const { return source_->frameCount(); }
  py::tuple frameSize() const { return py::make_tuple(source_->frameSize().width, source_->frameSize().height); }
  std::string description() const { return source_->description(); }

private:
  std::unique_ptr<StereoFrameSource> source_;
  std::shared_ptr<const StereoGeometry> geometry_;
  bool bgr_;
  int maxFrames_;
  int returned_ = 0;
};

std::string optionalPath(const py::object& path, const char* what) {
  return path.is_none() ? std::string() : pathText(path, what);
}

std::unique_ptr<FrameIterator> frames(const py::object& leftFrames, const py::object& rightFrames,
                                      const py::object& leftVideo, const py::object& rightVideo,
                                      const py::object& video, const std::string& layout, double fps,
                                      std::shared_ptr<Rig> rig, bool bgr, std::optional<int> maxFrames) {
  StereoInputPaths paths;
  paths.leftFrames = optionalPath(leftFrames, "left_frames");
  paths.rightFrames = optionalPath(rightFrames, "right_frames");
  paths.leftVideo = optionalPath(leftVideo, "left_video");
  paths.rightVideo = optionalPath(rightVideo, "right_video");
  paths.video = optionalPath(video, "video");
  paths.layout = layout;
  paths.fps = fps;
  if (!(fps >= 0.01 && fps <= 10000)) throw py::value_error("fps: must be within [0.01, 10000] frames per second");
  if (maxFrames && *maxFrames <= 0) throw py::value_error("max_frames: must be positive");
  std::unique_ptr<StereoFrameSource> source;
  {
    py::gil_scoped_release release;
    source = openStereoInput(paths);
  }
  return std::make_unique<FrameIterator>(std::move(source), std::move(rig), bgr, maxFrames.value_or(-1));
}

}  // namespace

void bindFrames(py::module_& module) {
  py::class_<FrameIterator>(module, "Frames", "An iterator of (left, right, time_s) from frames().")
      .def("__iter__", [](FrameIterator& self) -> FrameIterator& { return self; }, py::return_value_policy::reference_internal)
      .def("__next__", &FrameIterator::next)
      .def_property_readonly("frame_count", &FrameIterator::frameCount, "frames in the input (-1: unknown)")
      .def_property_readonly("frame_size", &FrameIterator::frameSize, "(width, height) of one eye")
      .def_property_readonly("description", &FrameIterator::description);
  module.def("frames", &frames, py::kw_only(), py::arg("left_frames") = py::none(),
             py::arg("right_frames") = py::none(), py::arg("left_video") = py::none(),
             py::arg("right_video") = py::none(), py::arg("video") = py::none(), py::arg("layout") = "sbs",
             py::arg("fps") = 30.0, py::arg("rig") = nullptr, py::arg("bgr") = false,
             py::arg("max_frames") = py::none(),
             R"(The stereo frames of one input, as the command line reads them (docs/INPUT.md): two frame folders
(left_frames, right_frames; paired in file-name order, time = index / fps), two videos (left_video, right_video), or
one 3D video (video, layout "sbs", "sbs-half", "tb", "tb-half" or "rows"). Videos may be V4L2 devices or GStreamer
pipelines. Yields (left, right, time_s): HxWx3 uint8 RGB (bgr=True: BGR). With a rig of a calibration whose frames
are raw, the pairs are rectified; give those to stereo() or Reconstruction with a rig of rectified frames
(Rig.from_file(..., rectified=True)), or give Reconstruction the raw frames (frames() without rig).)");
}

}  // namespace tissuemosaic::python
