// Calibration files as the field ships them (IO/Calibration): each layout's minimal example is written here from
// one reference rig, in that tool's own conventions, and must read back as the reference (and rectify as it does).
#include "Core/Error.h"
#include "ErrorText.h"
#include "Core/StereoRig.h"
#include "IO/Calibration/CalibrationFile.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <filesystem>
#include <fstream>

namespace tissuemosaic {
namespace {

std::string outputPath(const std::string& name) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/CalibrationLayouts";
  std::filesystem::create_directories(folder);
  return folder + "/" + name;
}

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

/// A laparoscope-like rig: 5 mm baseline, slight toe-in, distortion with k3 = 0 (every layout can hold it).
StereoCalibration referenceRig() {
  StereoCalibration c;
  c.imageSize = {640, 480};
  c.K1 = (cv::Mat_<double>(3, 3) << 800, 0, 322.5, 0, 805, 241.0, 0, 0, 1);
  c.K2 = (cv::Mat_<double>(3, 3) << 810, 0, 315.0, 0, 812, 236.5, 0, 0, 1);
  c.D1 = (cv::Mat_<double>(1, 5) << -0.12, 0.05, 0.001, -0.0005, 0.0);
  c.D2 = (cv::Mat_<double>(1, 5) << -0.10, 0.04, -0.0008, 0.0004, 0.0);
  cv::Rodrigues(cv::Mat(cv::Vec3d(0.01, -0.03, 0.005)), c.R);
  c.T = (cv::Mat_<double>(3, 1) << -5.0, 0.05, 0.1);
  return c;
}

std::string numbers(const cv::Mat& m) {  // "a, b, c" row-major, full precision
  std::string text;
  for (int i = 0; i < static_cast<int>(m.total()); ++i)
    text += (i ? ", " : "") + cv::format("%.17g", m.at<double>(i / m.cols, i % m.cols));
  return text;
}
std::string rows(const cv::Mat& m) {  // "[[a, b], [c, d]]"
  std::string text = "[";
  for (int r = 0; r < m.rows; ++r) text += (r ? ", [" : "[") + numbers(m.row(r)) + "]";
  return text + "]";
}

void expectNear(const cv::Mat& a, const cv::Mat& b, double tolerance, const std::string& what) {
  ASSERT_EQ(a.total(), b.total()) << what;
  EXPECT_LE(cv::norm(a.reshape(1, 1), b.reshape(1, 1), cv::NORM_INF), tolerance) << what;
}

void expectReference(const StereoCalibration& read, double tolerance, bool withImageSize = true) {
  const StereoCalibration reference = referenceRig();
  expectNear(read.K1, reference.K1, tolerance, "K1");
  expectNear(read.K2, reference.K2, tolerance, "K2");
  expectNear(read.D1.colRange(0, 4), reference.D1.colRange(0, 4), tolerance, "D1");
  expectNear(read.D2.colRange(0, 4), reference.D2.colRange(0, 4), tolerance, "D2");
  expectNear(read.R, reference.R, tolerance, "R");
  expectNear(read.T, reference.T, tolerance * 1000, "T");  // mm: metres in the file lose 3 digits
  EXPECT_EQ(read.T.size(), cv::Size(1, 3));
  EXPECT_EQ(read.D1.rows, 1);
  if (withImageSize) EXPECT_EQ(read.imageSize, reference.imageSize);
}

TEST(CalibrationLayouts, OpenCvStereoCalibrateNames) {
  const std::string path = outputPath("opencv.yml");
  writeStereoCalibration(referenceRig(), path);
  const CalibrationFileContent content = readCalibrationFiles(CalibrationFiles{path, "", ""});
  EXPECT_EQ(content.layout, "OpenCV stereoCalibrate");
  expectReference(content.calibration, 0.0);
}

TEST(CalibrationLayouts, StereoCalibSampleAsOneFileWithoutImageSizeTakesTheFramesSize) {
  // SCARED / SurgT: floats, T as a row, no image size, extra keys (alpha1).
  const StereoCalibration reference = referenceRig();
  const std::string path = outputPath("scared.yaml");
  {
    cv::FileStorage storage(path, cv::FileStorage::WRITE);
    cv::Mat R, T, M1, D1, M2, D2;
    reference.R.convertTo(R, CV_32F);
    cv::Mat(reference.T.t()).convertTo(T, CV_32F);
    reference.K1.convertTo(M1, CV_32F);
    reference.D1.convertTo(D1, CV_32F);
    reference.K2.convertTo(M2, CV_32F);
    reference.D2.convertTo(D2, CV_32F);
    storage << "R" << R << "T" << T << "M1" << M1 << "D1" << D1 << "alpha1" << 0.0 << "M2" << M2 << "D2" << D2;
  }
  CalibrationFileContent content = readCalibrationFiles(CalibrationFiles{path, "", ""});
  EXPECT_EQ(content.layout, "OpenCV stereo_calib sample / SCARED / SurgT");
  expectReference(content.calibration, 1e-6, false);
  EXPECT_TRUE(content.calibration.imageSize.empty());
  EXPECT_NE(errorOf([&] { StereoRectifier{content.calibration}; }).find("gives no image size"), std::string::npos);
  content.calibration.adoptFrameSize({640, 480}, "video 'x'");
  EXPECT_EQ(content.calibration.imageSize, cv::Size(640, 480));
  EXPECT_NEAR(StereoRectifier(content.calibration).geometry().baselineMm, cv::norm(reference.T), 1e-5);
  // A file with a size keeps it, and frames of another size are refused with both sizes named.
  StereoCalibration sized = reference;
  EXPECT_NE(errorOf([&] { sized.adoptFrameSize({1280, 1024}, "video 'clip.mp4'"); })
                .find("the calibration is for 640x480 but the frames of video 'clip.mp4' are 1280x1024"),
            std::string::npos);
}

TEST(CalibrationLayouts, StereoCalibSampleIntrinsicsAndExtrinsicsPair) {
  const StereoCalibration reference = referenceRig();
  const std::string intrinsics = outputPath("intrinsics.yml"), extrinsics = outputPath("extrinsics.yml");
  {
    cv::FileStorage storage(intrinsics, cv::FileStorage::WRITE);
    storage << "M1" << reference.K1 << "D1" << reference.D1 << "M2" << reference.K2 << "D2" << reference.D2;
  }
  {
    cv::Mat R1, R2, P1, P2, Q;  // the sample writes its rectification too; it is not used
    cv::stereoRectify(reference.K1, reference.D1, reference.K2, reference.D2, reference.imageSize, reference.R,
                      reference.T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 1);
    cv::FileStorage storage(extrinsics, cv::FileStorage::WRITE);
    storage << "R" << reference.R << "T" << reference.T << "R1" << R1 << "R2" << R2 << "P1" << P1 << "P2" << P2
            << "Q" << Q;
  }
  expectReference(readCalibrationFiles(CalibrationFiles{intrinsics, extrinsics, ""}).calibration, 0.0, false);
  expectReference(readCalibrationFiles(std::vector<std::string>{extrinsics, intrinsics}).calibration, 0.0, false);
  const std::string alone = errorOf([&] { readCalibrationFiles(CalibrationFiles{intrinsics, "", ""}); });
  EXPECT_NE(alone.find("key 'R' is missing"), std::string::npos) << alone;
  EXPECT_NE(alone.find("give that file too"), std::string::npos) << alone;
  // The missing input is named as the engine's parameter, for the command line (--calib-extrinsics) and Python
  // (extrinsics=) to name their own; the message names neither.
  EXPECT_EQ(parameterOf([&] { readCalibrationFiles(CalibrationFiles{intrinsics, "", ""}); }), "extrinsicsCalibration");
  EXPECT_EQ(alone.find("--"), std::string::npos) << alone;
}

/// ROS's stereo calibrator rectifies with cv::stereoRectify and writes each eye's K D R P, P in metres.
void writeRosCameraInfo(const std::string& path, const std::string& name, const cv::Mat& K, const cv::Mat& D,
                        const cv::Mat& R, cv::Mat P) {
  P = P.clone();
  P.at<double>(0, 3) /= 1000.0;
  writeText(path, "image_width: 640\nimage_height: 480\ncamera_name: " + name +
                      "\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [" + numbers(K) +
                      "]\ndistortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [" +
                      numbers(D) + "]\nrectification_matrix:\n  rows: 3\n  cols: 3\n  data: [" + numbers(R) +
                      "]\nprojection_matrix:\n  rows: 3\n  cols: 4\n  data: [" + numbers(P) + "]\n");
}

TEST(CalibrationLayouts, RosCameraInfoPerEyeKeepsItsOwnRectification) {
  const StereoCalibration reference = referenceRig();
  cv::Mat R1, R2, P1, P2, Q;
  // alpha 0.5: a rectification other than TissueMosaic's own (alpha 0), so that using it is visible.
  cv::stereoRectify(reference.K1, reference.D1, reference.K2, reference.D2, reference.imageSize, reference.R,
                    reference.T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.5);
  const std::string left = outputPath("left.yaml"), right = outputPath("right.yaml");
  writeRosCameraInfo(left, "stereo/left", reference.K1, reference.D1, R1, P1);
  writeRosCameraInfo(right, "stereo/right", reference.K2, reference.D2, R2, P2);
  const CalibrationFileContent content = readCalibrationFiles(CalibrationFiles{left, "", right});
  EXPECT_EQ(content.layout, "ROS camera_info (one file per eye)");
  expectReference(content.calibration, 1e-9);
  const StereoRectifier rectifier(content.calibration);
  const RectifiedGeometry& g = rectifier.geometry();
  EXPECT_DOUBLE_EQ(g.focalPx, P1.at<double>(0, 0));
  EXPECT_DOUBLE_EQ(g.cxLeftPx, P1.at<double>(0, 2));
  EXPECT_DOUBLE_EQ(g.cyPx, P1.at<double>(1, 2));
  EXPECT_NEAR(g.baselineMm, cv::norm(reference.T), 1e-9);
  EXPECT_NEAR(cv::norm(g.Q, Q, cv::NORM_INF), 0.0, 1e-9);  // the Q cv::stereoRectify made with this rectification
  EXPECT_GT(std::abs(g.focalPx - StereoRectifier(reference).geometry().focalPx), 1.0);  // not recomputed
  // The eyes in either order through the app's list; one eye alone and swapped eyes are refused.
  expectReference(readCalibrationFiles(std::vector<std::string>{right, left}).calibration, 1e-9);
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{left, "", ""}); }).find("give the right eye's file too"),
            std::string::npos);
  EXPECT_EQ(parameterOf([&] { readCalibrationFiles(CalibrationFiles{left, "", ""}); }), "rightCalibration");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{right, "", left}); }).find("swapped"),
            std::string::npos);
}

TEST(CalibrationLayouts, KalibrCamchain) {
  const StereoCalibration reference = referenceRig();
  cv::Mat T_cam1_cam0 = cv::Mat::eye(4, 4, CV_64F);
  reference.R.copyTo(T_cam1_cam0(cv::Rect(0, 0, 3, 3)));
  cv::Mat(reference.T / 1000.0).copyTo(T_cam1_cam0(cv::Rect(3, 0, 1, 3)));
  auto camera = [](const cv::Mat& K, const cv::Mat& D) {
    return "  camera_model: pinhole\n  distortion_coeffs: [" + numbers(D.colRange(0, 4)) +
           "]\n  distortion_model: radtan\n  intrinsics: [" +
           cv::format("%.17g, %.17g, %.17g, %.17g", K.at<double>(0, 0), K.at<double>(1, 1), K.at<double>(0, 2),
                      K.at<double>(1, 2)) +
           "]\n  resolution: [640, 480]\n  rostopic: /cam/image_raw\n";
  };
  std::string text = "cam0:\n  cam_overlaps: [1]\n" + camera(reference.K1, reference.D1) + "cam1:\n  T_cn_cnm1:\n";
  for (int r = 0; r < 4; ++r) text += "  - [" + numbers(T_cam1_cam0.row(r)) + "]\n";  // PyYAML's indentation
  text += "  cam_overlaps: [0]\n" + camera(reference.K2, reference.D2);
  const std::string path = outputPath("camchain.yaml");
  writeText(path, text);
  const CalibrationFileContent content = readCalibrationFiles(CalibrationFiles{path, "", ""});
  EXPECT_EQ(content.layout, "Kalibr camchain.yaml");
  expectReference(content.calibration, 1e-12);
}

/// MATLAB's documented projection of a camera-1 point into camera 2's image, 1-based pixels:
/// [x y z] * RotationOfCamera2 + TranslationOfCamera2, then [u v w] = p * IntrinsicMatrix (no distortion).
cv::Point2d matlabProjectIntoCamera2(const cv::Vec3d& point, const cv::Mat& rotation, const cv::Mat& translation,
                                     const cv::Mat& intrinsicMatrix) {
  const cv::Mat p = cv::Mat(point).t() * rotation + translation;
  const cv::Mat uvw = p * intrinsicMatrix;
  return {uvw.at<double>(0) / uvw.at<double>(2), uvw.at<double>(1) / uvw.at<double>(2)};
}

TEST(CalibrationLayouts, MatlabStereoParametersJsonInItsOwnConventions) {
  const StereoCalibration reference = referenceRig();
  auto intrinsicMatrix = [](const cv::Mat& K) {  // MATLAB: transposed, 1-based principal point
    cv::Mat m = K.clone();
    m.at<double>(0, 2) += 1;
    m.at<double>(1, 2) += 1;
    return cv::Mat(m.t());
  };
  const cv::Mat rotation = reference.R.t(), translation = reference.T.t();
  // The file is in MATLAB's conventions: its projection of a point is OpenCV's plus one pixel.
  const cv::Vec3d point(3, -2, 60);
  std::vector<cv::Point2d> opencv;
  cv::projectPoints(std::vector<cv::Point3d>{cv::Point3d(point)}, reference.R, reference.T, reference.K2, cv::noArray(),
                    opencv);
  const cv::Point2d matlab = matlabProjectIntoCamera2(point, rotation, translation, intrinsicMatrix(reference.K2));
  ASSERT_NEAR(matlab.x, opencv[0].x + 1, 1e-9);
  ASSERT_NEAR(matlab.y, opencv[0].y + 1, 1e-9);

  auto camera = [&](const cv::Mat& K, const cv::Mat& D) {
    return "{\"IntrinsicMatrix\": " + rows(intrinsicMatrix(K)) + ", \"RadialDistortion\": [" +
           cv::format("%.17g, %.17g, %.17g", D.at<double>(0), D.at<double>(1), D.at<double>(4)) +
           "], \"TangentialDistortion\": [" + cv::format("%.17g, %.17g", D.at<double>(2), D.at<double>(3)) +
           "], \"ImageSize\": [480, 640], \"WorldUnits\": \"mm\", \"EstimateSkew\": false}";
  };
  const std::string path = outputPath("stereoParams.json");
  writeText(path, "{\"CameraParameters1\": " + camera(reference.K1, reference.D1) + ", \"CameraParameters2\": " +
                      camera(reference.K2, reference.D2) + ", \"RotationOfCamera2\": " + rows(rotation) +
                      ", \"TranslationOfCamera2\": [" + numbers(translation) + "]}");
  const CalibrationFileContent content = readCalibrationFiles(CalibrationFiles{path, "", ""});
  EXPECT_EQ(content.layout, "MATLAB stereoParameters (Stereo Camera Calibrator)");
  expectReference(content.calibration, 1e-12);

  // R2022b's names: K not transposed, PoseCamera2 (camera 2 in camera 1), here in metres.
  cv::Mat K1 = reference.K1.clone(), K2 = reference.K2.clone();
  for (cv::Mat* K : {&K1, &K2}) {
    K->at<double>(0, 2) += 1;
    K->at<double>(1, 2) += 1;
  }
  const cv::Mat poseR = reference.R.t(), poseT = -reference.R.t() * reference.T / 1000.0;
  const std::string pose = outputPath("stereoParamsPose.json");
  writeText(pose, "{\"CameraParameters1\": {\"K\": " + rows(K1) + ", \"RadialDistortion\": [" +
                      numbers(reference.D1.colRange(0, 2)) + "], \"TangentialDistortion\": [" +
                      numbers(reference.D1.colRange(2, 4)) + "], \"ImageSize\": [480, 640]}, \"CameraParameters2\": {"
                      "\"K\": " + rows(K2) + ", \"RadialDistortion\": [" + numbers(reference.D2.colRange(0, 2)) +
                      "], \"TangentialDistortion\": [" + numbers(reference.D2.colRange(2, 4)) +
                      "], \"ImageSize\": [480, 640]}, \"PoseCamera2\": {\"R\": " + rows(poseR) +
                      ", \"Translation\": [" + numbers(poseT.t()) + "]}, \"WorldUnits\": \"m\"}");
  expectReference(readCalibrationFiles(CalibrationFiles{pose, "", ""}).calibration, 1e-12);
}

/// The reference rig in StereoMIS's StereoCalibration.ini: per eye fc_x fc_y cc_x cc_y kc_0..kc_4 res_x res_y, the
/// extrinsics R_0..R_8 T_0..T_2 in one section (here the left one, as the data set's loaders read them).
std::string stereoMisIni(const StereoCalibration& c, bool withT) {
  std::string text = "; StereoMIS-style calibration\n";
  const cv::Mat* K[2] = {&c.K1, &c.K2};
  const cv::Mat* D[2] = {&c.D1, &c.D2};
  for (int eye = 0; eye < 2; ++eye) {
    text += eye == 0 ? "[StereoLeft]\n" : "[StereoRight]\n";
    text += cv::format("res_x = %d\nres_y=%d\n", c.imageSize.width, c.imageSize.height);
    text += cv::format("fc_x = %.17g\nfc_y = %.17g\ncc_x = %.17g\ncc_y = %.17g\n", K[eye]->at<double>(0, 0),
                       K[eye]->at<double>(1, 1), K[eye]->at<double>(0, 2), K[eye]->at<double>(1, 2));
    for (int k = 0; k < 5; ++k) text += cv::format("kc_%d = %.17g\n", k, D[eye]->at<double>(k));
    if (eye == 0) {
      for (int i = 0; i < 9; ++i) text += cv::format("R_%d = %.17g\n", i, c.R.at<double>(i));
      for (int i = 0; withT && i < 3; ++i) text += cv::format("T_%d = %.17g\n", i, c.T.at<double>(i));
    }
  }
  return text;
}

TEST(CalibrationLayouts, StereoMisIni) {
  const std::string path = outputPath("StereoCalibration.ini");
  writeText(path, stereoMisIni(referenceRig(), true));
  const CalibrationFileContent content = readCalibrationFiles(CalibrationFiles{path, "", ""});
  EXPECT_EQ(content.layout, "StereoMIS StereoCalibration.ini");
  expectReference(content.calibration, 1e-12);
  // Missing and malformed parts are named.
  writeText(path, stereoMisIni(referenceRig(), false));
  const std::string missing = errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); });
  EXPECT_NE(missing.find("key 'T_0' is in neither [StereoRight] nor [StereoLeft]"), std::string::npos) << missing;
  writeText(path, "[StereoLeft]\nfc_x = 800\nthis line is no key\n[StereoRight]\n");
  const std::string malformed = errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); });
  EXPECT_NE(malformed.find("INI line 3 is neither [section] nor key = value"), std::string::npos) << malformed;
}

TEST(CalibrationLayouts, UnknownLayoutListsTheLayoutsUnderstood) {
  const std::string path = outputPath("unknown.yaml");
  writeText(path, "focal: 800\nbaseline: 5\n");
  const std::string message = errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("(focal baseline)"), std::string::npos) << message;
  for (const char* layout : {"OpenCV stereoCalibrate", "stereo_calib sample", "ROS camera_info", "Kalibr", "MATLAB",
                             "StereoMIS"})
    EXPECT_NE(message.find(layout), std::string::npos) << layout << ": " << message;
  const std::string notYaml = outputPath("broken.yaml");
  writeText(notYaml, "a: [1, 2\nb: {\n");
  EXPECT_NE(errorOf([&] { readStereoCalibration(notYaml); }).find("not a valid YAML or JSON"), std::string::npos);
  const std::string list = outputPath("list.yaml");
  writeText(list, "- 1\n- 2\n");
  EXPECT_NE(errorOf([&] { readStereoCalibration(list); }).find("holds no keys"), std::string::npos);
}

// Found by fuzz_calibration (Testing/Fuzz/corpus/fuzz_calibration/oom-*): OpenCV allocates an OpenCV matrix's
// rows x cols before it counts the data, so a 1 KB file saying 65536 x 65536 asked for 32 GB (an out-of-memory
// under ASan, std::bad_alloc or a swap storm without).
TEST(CalibrationLayouts, MatrixSizeBeyondItsDataIsRefusedBeforeAllocating) {
  const std::string path = outputPath("huge-matrix.yml");
  writeText(path, "%YAML:1.0\n---\nK1: !!opencv-matrix\n   rows: 65536\n   cols: 65536\n   dt: d\n   data: [ 1., 2. ]\n");
  const std::string message = errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); });
  EXPECT_NE(message.find("key 'K1' says 65536x65536 but holds 2 values"), std::string::npos) << message;
  writeText(path, "%YAML:1.0\n---\nK1: !!opencv-matrix\n   rows: -3\n   cols: 3\n   dt: d\n   data: [ 1., 2. ]\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); }).find("key 'K1' says -3x3"),
            std::string::npos);
  // A complex YAML key (a list as key) made the list of keys in the no-layout error throw YAML::TypedBadConversion
  // (found by fuzz_calibration: corpus/fuzz_calibration/crash-f6b9a089*).
  writeText(path, "focal: 800\n? [a, b]\n: 5\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); }).find("its keys (focal [a, b])"),
            std::string::npos);
  writeText(path, "K1: {rows: 3}\nD1: [1, 2, 3, 4]\nK2: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nD2: [1, 2, 3, 4]\nR: x\nT: [1, 2, 3]\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); }).find("cannot read stereo calibration"),
            std::string::npos);
  // A ROS-style {rows, cols, data} whose rows is beyond int's range: undefined behaviour in the cast before the
  // check (found by fuzz_calibration_pair: corpus/fuzz_calibration_pair/crash-0ece9dea*).
  writeText(path, "K1: {rows: 7.8e109, cols: 3, data: [1, 2, 3]}\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); })
                .find("key 'K1.rows' must be a whole number from 1 to 1000000, not 7.8e+109"),
            std::string::npos);
  // An image size beyond int's range: undefined behaviour in the cast (found by fuzz_calibration in a Kalibr
  // camchain's resolution: corpus/fuzz_calibration/crash-0ebfd525*); the same check serves every layout.
  writeText(path, "cam0:\n  intrinsics: [801, 805, 322.5, 241]\n  distortion_model: none\n"
                  "  resolution: [3.3e66, 480]\ncam1:\n  intrinsics: [801, 805, 322.5, 241]\n"
                  "  distortion_model: none\n  resolution: [640, 480]\n"
                  "  T_cn_cnm1: [[1, 0, 0, -5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); })
                .find("key 'resolution' must hold positive whole pixels (at most 100000)"),
            std::string::npos);
  writeText(path, "K1: [[800, 0, 320], [0, 800, 240], [0, 0, 1]]\nD1: [0, 0, 0, 0]\nK2: [[800, 0, 320], [0, 800, 240], "
                  "[0, 0, 1]]\nD2: [0, 0, 0, 0]\nR: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nT: [-5, 0, 0]\n"
                  "imageSize: [640, 1e300]\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); })
                .find("key 'imageSize' must hold positive whole pixels (at most 100000)"),
            std::string::npos);
  // OpenCV's parser lets an empty key out as std::length_error, not cv::Exception (found by fuzz_params).
  writeText(path, "%YAML:1.0\n---\nK1:\n   :\n");
  EXPECT_NE(errorOf([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); })
                .find("not a valid OpenCV YAML/XML file"),
            std::string::npos);
}

}  // namespace
}  // namespace tissuemosaic
