// Writing a synthetic scan to files: kept apart from the renderer so that programs which only render do not link
// OpenCV's image codecs.
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "IO/DisparityPfm.h"
#include "IO/MeshPly.h"
#include "IO/TrajectoryTum.h"

#include <opencv2/imgcodecs.hpp>

#include <filesystem>

namespace tissuemosaic::synthetic {

int writeSyntheticScan(const SyntheticScan& scan, const std::string& directory, void (*progress)(int, int)) {
  const std::filesystem::path root(directory);
  for (const char* sub : {"left", "right", "groundtruth"}) {
    std::error_code error;
    std::filesystem::create_directories(root / sub, error);
    require(std::filesystem::is_directory(root / sub), "cannot create output folder '" + (root / sub).string() + "'");
  }
  int written = 0;
  const auto image = [&](const std::filesystem::path& path, const cv::Mat& pixels) {
    bool ok = false;
    try {
      ok = cv::imwrite(path.string(), pixels);
    } catch (const cv::Exception&) {
    }
    require(ok, "cannot write image '" + path.string() + "'");
    ++written;
  };
  scan.calibration().write((root / "rig.yml").string());
  ++written;

  Trajectory trajectory;
  for (int index = 0; index < scan.frameCount(); ++index) {
    const SyntheticScanFrame frame = scan.renderFrame(index);
    const std::string name = cv::format("%06d", index);
    image(root / "left" / (name + ".png"), frame.leftRectified);
    image(root / "right" / (name + ".png"), frame.rightRectified);
    writePfm((root / "groundtruth" / ("depth_" + name + ".pfm")).string(), frame.depthMm);
    ++written;
    image(root / "groundtruth" / ("highlight_mask_left_" + name + ".png"), frame.highlightMaskLeft);
    TimedPose pose;
    pose.timeS = frame.timeS;
    pose.T_world_camera = frame.T_world_camera;
    trajectory.push_back(pose);
    if (progress) progress(index + 1, scan.frameCount());
  }
  writeTumTrajectory((root / "groundtruth" / "trajectory.txt").string(), trajectory,
                     "TissueMosaic synthetic scan ground truth: T_world_camera of the LEFT RECTIFIED camera\n"
                     "world: tissue Z = h(X, Y), +Z into the tissue; millimetres, seconds\n"
                     "t tx ty tz qx qy qz qw");
  ++written;
  writeMeshPly((root / "groundtruth" / "surface.ply").string(), scan.seenSurfaceMesh(0.5),
               "TissueMosaic synthetic scan: true tissue surface seen by both eyes in at least one frame\n"
               "frame: world (tissue Z = h(X, Y), +Z into the tissue), millimetres");
  ++written;
  return written;
}

}  // namespace tissuemosaic::synthetic
