// tm-make-dataset-layouts SCAN OUT: the public data sets' layouts made from a synthetic scan (`tissuemosaic synth
// scan`), for the tests of --scared, --hamlyn and --stereomis (Datasets.cmake): no data set is committed.
//   OUT/scared/      endoscope_calibration.yaml (M1 D1 M2 D2 R T, T a row, as SCARED ships it), data/rgb.mp4 (left
//                    on top of right), data/frame_data/frame_dataNNNNNN.json ({"camera-pose": 4x4, mm});
//                    OUT/scared_first_pose.txt: the first pose as TUM, for the run with plain options
//   OUT/stereomis/   sequence.mp4 (side by side) and StereoCalibration.ini
//   OUT/hamlyn/rectified01/rectified01/  image01/, image02/ and intrinsics.txt (3x3, no baseline);
//                    OUT/hamlyn_options.txt: the same geometry as plain options
// Videos are MPEG-4 (lossy): each test compares two runs over the same file, never with the frames.
#include "Core/StereoRig.h"
#include "IO/Calibration/CalibrationFile.h"
#include "IO/TrajectoryTum.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace fs = std::filesystem;
using namespace tissuemosaic;

namespace {

std::vector<fs::path> sortedFiles(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

void writeVideo(const std::string& path, const std::vector<fs::path>& left, const std::vector<fs::path>& right,
                bool sideBySide) {
  cv::VideoWriter writer;
  for (std::size_t i = 0; i < left.size(); ++i) {
    cv::Mat packed;
    const std::vector<cv::Mat> eyes = {cv::imread(left[i].string()), cv::imread(right[i].string())};
    sideBySide ? cv::hconcat(eyes, packed) : cv::vconcat(eyes, packed);
    if (!writer.isOpened() &&
        !writer.open(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), 25, packed.size())) {
      throw std::runtime_error("OpenCV cannot write MPEG-4 video " + path);
    }
    writer.write(packed);
  }
}

std::string number(double value) { return cv::format("%.17g", value); }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: tm-make-dataset-layouts SCAN OUT\n";
    return 2;
  }
  try {
    const fs::path scan(argv[1]), out(argv[2]);
    const StereoCalibration rig = readStereoCalibration((scan / "rig.yml").string());
    const Trajectory truth = readTumTrajectory((scan / "groundtruth" / "trajectory.txt").string());
    const std::vector<fs::path> left = sortedFiles(scan / "left"), right = sortedFiles(scan / "right");

    const fs::path scared = out / "scared";
    fs::create_directories(scared / "data" / "frame_data");
    {
      cv::FileStorage file((scared / "endoscope_calibration.yaml").string(), cv::FileStorage::WRITE);
      file << "M1" << rig.K1 << "D1" << rig.D1 << "M2" << rig.K2 << "D2" << rig.D2 << "R" << rig.R << "T"
           << rig.T.reshape(1, 1);
    }
    writeVideo((scared / "data" / "rgb.mp4").string(), left, right, false);
    // The first pose as TUM, and as JSON the matrix read back from it: TUM's quaternion rounds, and the run with
    // --start-tum must start from exactly the pose the SCARED run takes from frame_data000000.json.
    Trajectory first(truth.begin(), truth.begin() + 1);
    first.front().timeS = 0;
    writeTumTrajectory((out / "scared_first_pose.txt").string(), first);
    Trajectory poses = truth;
    poses.front().T_world_camera = readTumTrajectory((out / "scared_first_pose.txt").string()).front().T_world_camera;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      std::ofstream json(scared / "data" / "frame_data" / cv::format("frame_data%06zu.json", i));
      const Eigen::Matrix4d& T = poses[i].T_world_camera;
      json << "{\"camera-pose\": [";
      for (int r = 0; r < 4; ++r) {
        json << (r ? ", [" : "[") << number(T(r, 0)) << ", " << number(T(r, 1)) << ", " << number(T(r, 2)) << ", "
             << number(T(r, 3)) << "]";
      }
      json << "], \"timestamp\": " << i << "}\n";
    }

    const fs::path stereomis = out / "stereomis";
    fs::create_directories(stereomis);
    writeVideo((stereomis / "sequence.mp4").string(), left, right, true);
    {
      std::ofstream ini(stereomis / "StereoCalibration.ini");
      const cv::Mat* K[2] = {&rig.K1, &rig.K2};
      const cv::Mat* D[2] = {&rig.D1, &rig.D2};
      const char* names[2] = {"StereoLeft", "StereoRight"};
      for (int eye = 0; eye < 2; ++eye) {
        ini << "[" << names[eye] << "]\nres_x = " << rig.imageSize.width << "\nres_y = " << rig.imageSize.height
            << "\nfc_x = " << number(K[eye]->at<double>(0, 0)) << "\nfc_y = " << number(K[eye]->at<double>(1, 1))
            << "\ncc_x = " << number(K[eye]->at<double>(0, 2)) << "\ncc_y = " << number(K[eye]->at<double>(1, 2))
            << "\n";
        for (int k = 0; k < 5; ++k) {
          ini << "kc_" << k << " = " << number(k < static_cast<int>(D[eye]->total()) ? D[eye]->at<double>(k) : 0.0)
              << "\n";
        }
      }
      for (int i = 0; i < 9; ++i) ini << "R_" << i << " = " << number(rig.R.at<double>(i)) << "\n";
      for (int i = 0; i < 3; ++i) ini << "T_" << i << " = " << number(rig.T.at<double>(i)) << "\n";
    }

    const fs::path hamlyn = out / "hamlyn" / "rectified01" / "rectified01";
    fs::create_directories(hamlyn / "image01");
    fs::create_directories(hamlyn / "image02");
    for (std::size_t i = 0; i < left.size(); ++i) {
      fs::copy_file(left[i], hamlyn / "image01" / left[i].filename(), fs::copy_options::overwrite_existing);
      fs::copy_file(right[i], hamlyn / "image02" / right[i].filename(), fs::copy_options::overwrite_existing);
    }
    const RectifiedGeometry geometry = StereoRectifier(rig).geometry();
    std::ofstream(hamlyn / "intrinsics.txt") << number(geometry.focalPx) << " 0 " << number(geometry.cxLeftPx)
                                             << "\n0 " << number(geometry.focalPx) << " " << number(geometry.cyPx)
                                             << "\n0 0 1\n";
    std::ofstream(out / "hamlyn_options.txt") << "--focal-px " << number(geometry.focalPx) << " --cx-px "
                                              << number(geometry.cxLeftPx) << " --cy-px " << number(geometry.cyPx)
                                              << " --baseline-mm " << number(geometry.baselineMm) << "\n";
    std::cout << "wrote SCARED, StereoMIS and Hamlyn layouts of " << left.size() << " frames under " << out.string()
              << " (doffs " << geometry.doffsPx << " px)\n";
  } catch (const std::exception& error) {
    std::cerr << "tm-make-dataset-layouts: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
