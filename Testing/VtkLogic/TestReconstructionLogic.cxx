// vtkTissueMosaicReconstructionLogic and its VTK outputs: frusta geometry, the growing model's in-place update, and
// a short synthetic scan run on the worker thread, checked against the scan's ground truth (frusta poses, model
// points on the true surface, exported files).
#include "vtkTissueMosaicFrusta.h"
#include "vtkTissueMosaicGrowingModel.h"
#include "vtkTissueMosaicPointCloud.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "SyntheticScanFrameSource.h"
#include "TissueSurface.h"

#include "Core/StereoRig.h"
#include "IO/PointCloudPly.h"
#include "IO/TrajectoryTum.h"
#include "Reconstruction/ReconstructionPipeline.h"

#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <mutex>
#include <thread>

using tissuemosaic::CameraPose;
using tissuemosaic::CameraPoses;
using tissuemosaic::ColoredPointCloud;
using tissuemosaic::RectifiedGeometry;
using tissuemosaic::testing::SyntheticScanFrameSource;

namespace {

Eigen::Vector3d pointOf(vtkPolyData* polyData, vtkIdType id) {
  double p[3];
  polyData->GetPoint(id, p);
  return Eigen::Vector3d(p[0], p[1], p[2]);
}

RectifiedGeometry smallGeometry() {
  RectifiedGeometry geometry;
  geometry.imageSize = cv::Size(320, 180);
  geometry.focalPx = 300;
  geometry.cxLeftPx = 150;
  geometry.cyPx = 95;
  geometry.baselineMm = 5;
  return geometry;
}

Eigen::Matrix4d pose(double angleRad, const Eigen::Vector3d& axis, const Eigen::Vector3d& translationMm) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(angleRad, axis.normalized()).toRotationMatrix();
  T.block<3, 1>(0, 3) = translationMm;
  return T;
}

/// Appends points (i, 0, depthMm) for i in [from, to), all of one colour and normal.
void appendRow(ColoredPointCloud& cloud, int from, int to, float depthMm, const cv::Vec3b& colour,
               const cv::Point3f& normal) {
  for (int i = from; i < to; ++i) {
    cloud.pointsMm.emplace_back(float(i), 0.f, depthMm);
    cloud.colorsRgb.push_back(colour);
    cloud.normals.push_back(normal);
  }
}

}  // namespace

TEST(ReconstructionFrusta, PointsAndLinesOfEachCameraAreAtItsPose) {
  const RectifiedGeometry geometry = smallGeometry();
  CameraPoses cameras(2);
  cameras[0].frameIndex = 0;
  cameras[1].frameIndex = 17;
  cameras[1].T_world_camera = pose(0.3, {0.2, 1, 0.1}, {12, -4, 3});
  const double depthMm = 10;
  vtkSmartPointer<vtkPolyData> frusta = tissuemosaic::cameraFrustaToPolyData(cameras, geometry, depthMm);
  ASSERT_EQ(frusta->GetNumberOfPoints(), 10);
  ASSERT_EQ(frusta->GetNumberOfLines(), 16);
  auto* frames = vtkIntArray::SafeDownCast(frusta->GetCellData()->GetArray(tissuemosaic::kFrustumFrameIndexArrayName));
  ASSERT_NE(frames, nullptr);
  for (vtkIdType line = 0; line < 16; ++line) EXPECT_EQ(frames->GetValue(line), line < 8 ? 0 : 17);

  for (int c = 0; c < 2; ++c) {
    const Eigen::Matrix4d T_camera_world = cameras[c].T_world_camera.inverse();
    EXPECT_LT((pointOf(frusta, 5 * c) - cameras[c].T_world_camera.block<3, 1>(0, 3)).norm(), 1e-9);
    // Each corner, taken back into the camera, is at the requested depth and projects onto an image corner.
    const double cornersPx[4][2] = {{-0.5, -0.5}, {319.5, -0.5}, {319.5, 179.5}, {-0.5, 179.5}};
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d cameraMm = (T_camera_world * pointOf(frusta, 5 * c + 1 + k).homogeneous()).head<3>();
      EXPECT_NEAR(cameraMm.z(), depthMm, 1e-9);
      EXPECT_NEAR(geometry.focalPx * cameraMm.x() / cameraMm.z() + geometry.cxLeftPx, cornersPx[k][0], 1e-9);
      EXPECT_NEAR(geometry.focalPx * cameraMm.y() / cameraMm.z() + geometry.cyPx, cornersPx[k][1], 1e-9);
    }
  }
  vtkNew<vtkPolyData> path;
  tissuemosaic::updateCameraPath(path, cameras);
  EXPECT_EQ(path->GetNumberOfPoints(), 2);
  EXPECT_EQ(path->GetNumberOfLines(), 1);
}

TEST(ReconstructionGrowingModel, ArraysMadeOnAnotherThreadAreSwappedInWithoutACopy) {
  // Double buffering of the live view: the worker makes the arrays, the owner only swaps pointers.
  ColoredPointCloud cloud;
  for (int i = 0; i < 5000; ++i) {
    cloud.pointsMm.emplace_back(float(i), float(-i), 60.f);
    cloud.colorsRgb.emplace_back(uchar(i % 256), 1, 2);
    cloud.normals.emplace_back(0.f, 0.f, -1.f);
  }
  tissuemosaic::ModelArrays made;
  std::thread worker([&] { made = tissuemosaic::makeModelArrays(cloud); });
  worker.join();
  vtkNew<vtkPolyData> model;
  tissuemosaic::updateGrowingModel(model, cloud);  // what the view showed before
  vtkPoints* before = model->GetPoints();
  const void* madePoints = made.points->GetVoidPointer(0);
  const tissuemosaic::ModelArrays previous = tissuemosaic::swapModelArrays(model, made);
  EXPECT_EQ(previous.points.Get(), before) << "the replaced arrays come back, for release elsewhere";
  EXPECT_EQ(model->GetPoints()->GetVoidPointer(0), madePoints) << "swapped in, not copied";
  // The same polydata as updateGrowingModel makes: points, one vertex per point, colours, normals.
  ASSERT_EQ(model->GetNumberOfPoints(), 5000);
  EXPECT_EQ(model->GetNumberOfVerts(), 5000);
  double point[3];
  model->GetPoint(4321, point);
  EXPECT_EQ(point[0], 4321.0);
  EXPECT_EQ(point[1], -4321.0);
  vtkIdType count = 0;
  const vtkIdType* ids = nullptr;
  model->GetVerts()->GetCellAtId(4321, count, ids);
  ASSERT_EQ(count, 1);
  EXPECT_EQ(ids[0], 4321);
  auto* colours = vtkUnsignedCharArray::SafeDownCast(model->GetPointData()->GetScalars());
  ASSERT_NE(colours, nullptr);
  EXPECT_STREQ(colours->GetName(), tissuemosaic::kPointCloudColorArrayName);
  EXPECT_EQ(colours->GetValue(3 * 300), 300 % 256);
  ASSERT_NE(model->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(model->GetPointData()->GetNormals()->GetComponent(7, 2), -1.0);
}

TEST(ReconstructionGrowingModel, AppendsInPlaceAndRefreshesEarlierPoints) {
  ColoredPointCloud cloud;
  for (int i = 0; i < 1000; ++i) {
    cloud.pointsMm.emplace_back(float(i), float(2 * i), 50.f);
    cloud.colorsRgb.emplace_back(uchar(i % 256), 10, 20);
    cloud.normals.emplace_back(0.f, 0.f, -1.f);
  }
  vtkNew<vtkPolyData> model;
  tissuemosaic::GrowingModelUpdate update = tissuemosaic::updateGrowingModel(model, cloud);
  EXPECT_EQ(update.appendedPoints, 1000u);
  ASSERT_EQ(model->GetNumberOfPoints(), 1000);
  ASSERT_EQ(model->GetNumberOfVerts(), 1000);
  vtkDataArray* connectivity = model->GetVerts()->GetConnectivityArray();
  vtkDataArray* pointArray = model->GetPoints()->GetData();

  // Fusion moved point 3 and added 500 more: the same arrays grow, earlier values are refreshed.
  cloud.pointsMm[3].z = 51.f;
  cloud.colorsRgb[3] = cv::Vec3b(1, 2, 3);
  appendRow(cloud, 1000, 1500, 60.f, cv::Vec3b(200, 100, 50), cv::Point3f(0.f, 1.f, 0.f));
  update = tissuemosaic::updateGrowingModel(model, cloud);
  EXPECT_EQ(update.keptPoints, 1000u);
  EXPECT_EQ(update.appendedPoints, 500u);
  EXPECT_EQ(model->GetVerts()->GetConnectivityArray(), connectivity) << "vertex cells were rebuilt";
  EXPECT_EQ(model->GetPoints()->GetData(), pointArray) << "point array was replaced";
  ASSERT_EQ(model->GetNumberOfPoints(), 1500);
  ASSERT_EQ(model->GetNumberOfVerts(), 1500);
  EXPECT_EQ(pointOf(model, 3).z(), 51.0);
  EXPECT_EQ(pointOf(model, 1499).x(), 1499.0);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(model->GetPointData()->GetScalars());
  ASSERT_NE(colors, nullptr);
  EXPECT_STREQ(colors->GetName(), tissuemosaic::kPointCloudColorArrayName);
  EXPECT_EQ(colors->GetValue(3 * 3 + 2), 3);
  EXPECT_EQ(colors->GetValue(3 * 1200), 200);
  ASSERT_NE(model->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(model->GetPointData()->GetNormals()->GetComponent(1200, 1), 1.0);
  // Every vertex cell i holds point i.
  vtkIdType size;
  const vtkIdType* ids;
  model->GetVerts()->GetCellAtId(1234, size, ids);
  ASSERT_EQ(size, 1);
  EXPECT_EQ(ids[0], 1234);

  // The buffers grow geometrically: the next key frame's points fit without a new allocation (a whole-model
  // allocation at every key frame faults in every page of the model again on the GUI thread).
  const void* pointBuffer = pointArray->GetVoidPointer(0);
  const void* colorBuffer = colors->GetVoidPointer(0);
  const void* normalBuffer = model->GetPointData()->GetNormals()->GetVoidPointer(0);
  EXPECT_GE(pointArray->GetSize(), 2 * 3 * 1000);
  appendRow(cloud, 1500, 1600, 70.f, cv::Vec3b(10, 20, 30), cv::Point3f(1.f, 0.f, 0.f));
  update = tissuemosaic::updateGrowingModel(model, cloud);
  EXPECT_EQ(update.appendedPoints, 100u);
  EXPECT_EQ(pointArray->GetVoidPointer(0), pointBuffer) << "points reallocated for 100 more";
  EXPECT_EQ(colors->GetVoidPointer(0), colorBuffer) << "colours reallocated for 100 more";
  EXPECT_EQ(model->GetPointData()->GetNormals()->GetVoidPointer(0), normalBuffer) << "normals reallocated";
  EXPECT_EQ(pointOf(model, 1599).x(), 1599.0);
  EXPECT_EQ(pointOf(model, 1499).x(), 1499.0);
  EXPECT_EQ(colors->GetValue(3 * 1550 + 2), 30);

  cloud.pointsMm.resize(10);
  cloud.colorsRgb.resize(10);
  cloud.normals.resize(10);
  update = tissuemosaic::updateGrowingModel(model, cloud);
  EXPECT_EQ(update.removedPoints, 1590u);
  EXPECT_EQ(model->GetNumberOfPoints(), 10);
  EXPECT_EQ(model->GetNumberOfVerts(), 10);
}

TEST(ReconstructionLogic, RefusesToStartWithoutInputAndInvalidParameters) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  EXPECT_FALSE(logic->Start());
  EXPECT_NE(logic->GetLastErrorText().find("no input"), std::string::npos) << logic->GetLastErrorText();
  EXPECT_EQ(logic->GetScanState(), vtkTissueMosaicReconstructionLogic::StateIdle);

  tissuemosaic::ReconstructionParameters parameters;
  parameters.stereo.znccWindowPx = 10;  // even: invalid
  EXPECT_FALSE(logic->SetParameters(parameters));
  EXPECT_NE(logic->GetLastErrorText().find("znccWindowPx"), std::string::npos) << logic->GetLastErrorText();
  EXPECT_EQ(logic->GetParameters().stereo.znccWindowPx, 11);

  parameters = {};
  parameters.tracking.inlierThresholdPx = 3.5;
  parameters.stereo.maxDisparityPx = 60;
  ASSERT_TRUE(logic->SetParameters(parameters)) << logic->GetLastErrorText();
  const std::string path = std::string(TM_TEST_OUTPUT_DIR) + "/reconstruction-parameters.yml";
  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  ASSERT_TRUE(logic->WriteParametersFile(path)) << logic->GetLastErrorText();
  vtkNew<vtkTissueMosaicReconstructionLogic> other;
  ASSERT_TRUE(other->ReadParametersFile(path)) << other->GetLastErrorText();
  EXPECT_EQ(other->GetParameters().tracking.inlierThresholdPx, 3.5);
  EXPECT_EQ(other->GetParameters().stereo.maxDisparityPx, 60);
  EXPECT_FALSE(other->ReadParametersFile(path + ".missing"));

  EXPECT_FALSE(logic->OpenFrameFolders("/nonexistent/left", "/nonexistent/right"));
  EXPECT_FALSE(logic->HasInput());
}

class ReconstructionLogicScan : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    scan_ = std::make_shared<tissuemosaic::synthetic::SyntheticScan>(tissuemosaic::testing::shortScanOptions(20));
  }
  static void TearDownTestSuite() { scan_.reset(); }

  /// A logic set up for the scan: in-memory frames, exact geometry, a narrow disparity range (speed), frequent key
  /// frames (a short scan).
  static tissuemosaic::ReconstructionParameters parameters() {
    tissuemosaic::ReconstructionParameters parameters;
    parameters.stereo.setFixedDisparityRange(0, 40);
    parameters.tracking.keyFrameMinGapFrames = 4;
    parameters.tracking.keyFramePoseThreshold = 2.0;
    return parameters;
  }

  void setUp(vtkTissueMosaicReconstructionLogic* logic) {
    ASSERT_TRUE(logic->SetParameters(parameters())) << logic->GetLastErrorText();
    logic->SetDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
    auto scan = scan_;
    ASSERT_TRUE(logic->SetFrameSourceFactory([scan] { return std::make_unique<SyntheticScanFrameSource>(scan); }));
    logic->SetRectifiedGeometry(scan_->geometry());
  }

  /// Ground truth in the logic's world (the first left rectified camera).
  Eigen::Matrix4d truePose(int frame) const { return scan_->T_world_camera(0).inverse() * scan_->T_world_camera(frame); }

  static std::shared_ptr<tissuemosaic::synthetic::SyntheticScan> scan_;
};
std::shared_ptr<tissuemosaic::synthetic::SyntheticScan> ReconstructionLogicScan::scan_;

TEST_F(ReconstructionLogicScan, OutputsAreThePipelinesAndMatchTheGroundTruth) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  setUp(logic);
  const int frameCount = scan_->frameCount();
  EXPECT_EQ(logic->GetInputFrameCount(), frameCount);
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  EXPECT_FALSE(logic->SetParameters(logic->GetParameters())) << "parameters must be fixed during a scan";

  // The same frames through the engine directly, on this thread, while the worker runs: the reference.
  tissuemosaic::ReconstructionPipeline pipeline(scan_->geometry(), parameters(), tissuemosaic::Device::Cpu);
  for (int k = 0; k < frameCount; ++k) {
    const auto frame = scan_->renderFrame(k);
    pipeline.process(frame.leftRectified, frame.rightRectified, frame.timeS);
  }
  const tissuemosaic::ModelPoints reference = pipeline.modelSnapshot();
  const auto& keyFrames = pipeline.keyFrames();

  ASSERT_TRUE(logic->WaitForScanEnd(120.0));
  logic->UpdateOutputs();
  const auto& status = logic->GetStatus();
  ASSERT_EQ(status.state, vtkTissueMosaicReconstructionLogic::StateFinished) << status.errorText;
  EXPECT_EQ(status.framesProcessed, frameCount);
  EXPECT_EQ(status.lostFrames, 0);
  EXPECT_EQ(status.device, "cpu");
  EXPECT_EQ(status.disparityRange, (tissuemosaic::DisparityRange{0, 40}));
  EXPECT_EQ(logic->GetDisparityRangeText(), "fixed: 0..40 px");

  // Frusta: one per key frame, at the pipeline's (refined) key-frame poses, and near the true poses.
  vtkPolyData* frusta = logic->GetKeyFrameFrusta();
  ASSERT_GE(status.keyFrames, 3);
  ASSERT_EQ(status.keyFrames, static_cast<int>(keyFrames.size()));
  ASSERT_EQ(frusta->GetNumberOfPoints(), 5 * status.keyFrames);
  ASSERT_EQ(frusta->GetNumberOfLines(), 8 * status.keyFrames);
  auto* frames = vtkIntArray::SafeDownCast(frusta->GetCellData()->GetArray(tissuemosaic::kFrustumFrameIndexArrayName));
  ASSERT_NE(frames, nullptr);
  EXPECT_EQ(frames->GetValue(0), 0) << "the first frame is the first key frame";
  double worstMm = 0;
  for (int k = 0; k < status.keyFrames; ++k) {
    const int frame = frames->GetValue(8 * k);
    EXPECT_EQ(frame, keyFrames[k].frameIndex);
    EXPECT_LT((pointOf(frusta, 5 * k) - keyFrames[k].T_world_camera.block<3, 1>(0, 3)).norm(), 1e-6);
    const Eigen::Vector3d corner = tissuemosaic::pixelToWorldMm(scan_->geometry(), keyFrames[k].T_world_camera, -0.5,
                                                                -0.5, logic->GetFrustumDepthMm());
    EXPECT_LT((pointOf(frusta, 5 * k + 1) - corner).norm(), 1e-6) << "key frame " << frame;
    worstMm = std::max(worstMm, (pointOf(frusta, 5 * k) - truePose(frame).block<3, 1>(0, 3)).norm());
  }
  std::cout << "[ measured ] " << status.keyFrames << " key frames, worst centre error to the truth " << worstMm
            << " mm\n";
  EXPECT_LT(worstMm, 2.5) << "key frame centres far from the truth: wrong frame or pose";

  // Trajectory: every tracked frame; the current frustum at the last frame.
  EXPECT_EQ(logic->GetTrajectory()->GetNumberOfPoints(), frameCount);
  ASSERT_EQ(logic->GetCurrentFrustum()->GetNumberOfPoints(), 5);
  EXPECT_LT((pointOf(logic->GetCurrentFrustum(), 0) - truePose(frameCount - 1).block<3, 1>(0, 3)).norm(), 2.5);

  // Model: exactly the pipeline's (points, colours, normals), one vertex cell each, on the true surface.
  vtkPolyData* model = logic->GetModel();
  ASSERT_GT(model->GetNumberOfPoints(), 10000);
  ASSERT_EQ(model->GetNumberOfPoints(), static_cast<vtkIdType>(reference.size()));
  EXPECT_EQ(model->GetNumberOfPoints(), status.modelPoints);
  EXPECT_EQ(model->GetNumberOfVerts(), model->GetNumberOfPoints());
  auto* colors = vtkUnsignedCharArray::SafeDownCast(model->GetPointData()->GetArray(tissuemosaic::kPointCloudColorArrayName));
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->GetNumberOfComponents(), 3);
  vtkDataArray* normals = model->GetPointData()->GetNormals();
  ASSERT_NE(normals, nullptr);
  const Eigen::Matrix4d T_truth_logic = scan_->T_world_camera(0);
  std::vector<double> errorsMm;
  int different = 0;
  for (vtkIdType i = 0; i < model->GetNumberOfPoints(); i += 7) {
    const cv::Point3f& p = reference.cloud.pointsMm[i];
    const cv::Vec3b& c = reference.cloud.colorsRgb[i];
    different += pointOf(model, i) != Eigen::Vector3d(p.x, p.y, p.z) || colors->GetValue(3 * i) != c[0] ||
                 colors->GetValue(3 * i + 2) != c[2] || normals->GetComponent(i, 2) != reference.cloud.normals[i].z;
    const Eigen::Vector3d truthMm = (T_truth_logic * pointOf(model, i).homogeneous()).head<3>();
    errorsMm.push_back(std::abs(truthMm.z() - scan_->surface().heightMm(truthMm.x(), truthMm.y())));
  }
  EXPECT_EQ(different, 0) << "model points differ from the pipeline's";
  std::sort(errorsMm.begin(), errorsMm.end());
  const double medianErrorMm = errorsMm[errorsMm.size() / 2];
  std::cout << "[ measured ] model " << model->GetNumberOfPoints() << " points, height error to the true surface: "
            << "median " << medianErrorMm << " mm, p90 " << errorsMm[errorsMm.size() * 9 / 10] << " mm\n";
  EXPECT_LT(medianErrorMm, 1.5) << "model far from the true surface: wrong frame";

  // Timing table: the paper's stages and the model agreement; stereo ran on every frame.
  const auto table = logic->GetTimingTable();
  ASSERT_EQ(table.size(), 8u);
  EXPECT_EQ(table[1].stage, "stereo");
  EXPECT_EQ(table[4].stage, "model_agreement");
  EXPECT_EQ(table[7].stage, "total");
  EXPECT_GT(table[1].keyFrameMedianMs, 0);
  EXPECT_GT(table[1].otherFrameMedianMs, 0);
  EXPECT_GT(table[7].keyFrameMeanMs, table[1].keyFrameMeanMs);
}

TEST_F(ReconstructionLogicScan, ExportsModelAndTrajectory) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  setUp(logic);
  logic->SetMaximumFrames(12);
  const std::string out = std::string(TM_TEST_OUTPUT_DIR) + "/reconstruction-export";
  std::filesystem::create_directories(out);
  EXPECT_FALSE(logic->ExportModel(out + "/none.ply"));
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  ASSERT_TRUE(logic->WaitForScanEnd(60.0));
  ASSERT_TRUE(logic->ExportModel(out + "/model.ply")) << logic->GetLastErrorText();
  ASSERT_TRUE(logic->ExportModel(out + "/model.vtp")) << logic->GetLastErrorText();
  EXPECT_FALSE(logic->ExportModel(out + "/model.xyz"));
  ASSERT_TRUE(logic->ExportTrajectory(out + "/trajectory.txt")) << logic->GetLastErrorText();
  EXPECT_EQ(logic->GetStatus().framesProcessed, 12);

  const ColoredPointCloud ply = tissuemosaic::readPly(out + "/model.ply");
  EXPECT_EQ(static_cast<vtkIdType>(ply.size()), logic->GetModel()->GetNumberOfPoints());
  EXPECT_EQ(ply.colorsRgb.size(), ply.size());
  EXPECT_EQ(ply.normals.size(), ply.size());
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((out + "/model.vtp").c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), logic->GetModel()->GetNumberOfPoints());
  EXPECT_EQ(reader->GetOutput()->GetNumberOfVerts(), logic->GetModel()->GetNumberOfPoints());

  const tissuemosaic::Trajectory trajectory = tissuemosaic::readTumTrajectory(out + "/trajectory.txt");
  ASSERT_EQ(trajectory.size(), 12u);
  for (int k = 0; k < 12; ++k) {
    EXPECT_NEAR(trajectory[k].timeS, scan_->timeS(k), 1e-6);  // TUM files keep 6 decimals
    EXPECT_LT((trajectory[k].T_world_camera.block<3, 1>(0, 3) - truePose(k).block<3, 1>(0, 3)).norm(), 2.5);
  }
}

TEST_F(ReconstructionLogicScan, PauseResumeStopAndReset) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  setUp(logic);
  ASSERT_TRUE(logic->Start());
  logic->Pause();
  EXPECT_EQ(logic->GetScanState(), vtkTissueMosaicReconstructionLogic::StatePaused);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  logic->UpdateOutputs();
  const int pausedAt = logic->GetStatus().framesProcessed;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  logic->UpdateOutputs();
  EXPECT_LE(logic->GetStatus().framesProcessed, pausedAt + 1) << "the worker went on while paused";
  ASSERT_TRUE(logic->Start()) << "resume";
  EXPECT_EQ(logic->GetScanState(), vtkTissueMosaicReconstructionLogic::StateRunning);
  logic->Stop();
  ASSERT_TRUE(logic->WaitForScanEnd(30.0));
  EXPECT_EQ(logic->GetScanState(), vtkTissueMosaicReconstructionLogic::StateStopped);
  logic->UpdateOutputs();
  EXPECT_LT(logic->GetStatus().framesProcessed, scan_->frameCount());
  EXPECT_FALSE(logic->Start()) << "an ended scan needs a reset";

  logic->Reset();
  EXPECT_EQ(logic->GetScanState(), vtkTissueMosaicReconstructionLogic::StateIdle);
  EXPECT_EQ(logic->GetModel()->GetNumberOfPoints(), 0);
  EXPECT_EQ(logic->GetKeyFrameFrusta()->GetNumberOfPoints(), 0);
  EXPECT_TRUE(logic->GetLeftFrame().empty());
  EXPECT_TRUE(logic->CanChangeParameters());
}

namespace {

/// A gate the test opens: frame reads wait at it (after the first `freePasses`), so the worker is certainly inside
/// a frame until the test lets it go. A watchdog opens it after `limitS` whatever happens, so that a call which waits
/// for the worker ends the test with a failure instead of a hang.
class Gate {
public:
  explicit Gate(int freePasses = 0) : freePasses_(freePasses) {}
  void open() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      open_ = true;
    }
    changed_.notify_all();
  }
  bool isOpen() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return open_;
  }
  void waitUntilOpen() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (freePasses_ > 0) {
      --freePasses_;
      return;
    }
    entered_ = true;
    changed_.notify_all();
    changed_.wait(lock, [this] { return open_; });
  }
  /// True once a reader waits at the gate (within limitS).
  bool waitForReader(double limitS) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::duration<double>(limitS), [this] { return entered_; });
  }
  /// Runs `call` with a watchdog that opens the gate after limitS; true when the call returned while the gate was
  /// still shut, i.e. without waiting for whoever waits at it.
  bool returnsWhileShut(const std::function<void()>& call, double limitS) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      callDone_ = false;
    }
    std::thread watchdog([this, limitS] {
      std::unique_lock<std::mutex> lock(mutex_);
      if (!changed_.wait_for(lock, std::chrono::duration<double>(limitS), [this] { return open_ || callDone_; })) {
        open_ = true;
        changed_.notify_all();
      }
    });
    call();
    const bool shut = !isOpen();
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      callDone_ = true;
    }
    changed_.notify_all();
    watchdog.join();
    return shut;
  }

private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int freePasses_;
  bool open_ = false, entered_ = false, callDone_ = false;
};

/// The scan's frames, each read held at the gate until it opens.
class GatedSource : public tissuemosaic::StereoFrameSource {
public:
  GatedSource(std::shared_ptr<const tissuemosaic::synthetic::SyntheticScan> scan, std::shared_ptr<Gate> gate)
      : inner_(std::move(scan)), gate_(std::move(gate)) {}
  bool next(tissuemosaic::StereoFrame& frame) override {
    gate_->waitUntilOpen();
    return inner_.next(frame);
  }
  int frameCount() const override { return inner_.frameCount(); }
  cv::Size frameSize() const override { return inner_.frameSize(); }
  std::string description() const override { return "gated"; }

private:
  SyntheticScanFrameSource inner_;
  std::shared_ptr<Gate> gate_;
};

}  // namespace

namespace {

/// The first `frames` frames of a scan only (a scan that ends while the camera is out).
class FirstFrames : public tissuemosaic::StereoFrameSource {
public:
  FirstFrames(std::shared_ptr<const tissuemosaic::synthetic::SyntheticScan> scan, int frames)
      : inner_(std::move(scan)), frames_(frames) {}
  bool next(tissuemosaic::StereoFrame& frame) override { return given_++ < frames_ && inner_.next(frame); }
  int frameCount() const override { return frames_; }
  cv::Size frameSize() const override { return inner_.frameSize(); }
  std::string description() const override { return "first frames"; }

private:
  SyntheticScanFrameSource inner_;
  int frames_, given_ = 0;
};

}  // namespace

// The scope taken out for frames 8-13 and put back: while it is out the user reads "Lost: move the camera back over
// the scanned tissue" and no agreement; once it is back, "Relocalised" and the model agreement with its numbers.
TEST_F(ReconstructionLogicScan, SaysLostAndRelocalisedAndShowsTheAgreement) {
  tissuemosaic::synthetic::SyntheticScanOptions options = tissuemosaic::testing::shortScanOptions(20);
  options.hardMode.cameraOutStart = 8;
  options.hardMode.cameraOutEnd = 14;
  const auto scan = std::make_shared<const tissuemosaic::synthetic::SyntheticScan>(options);
  const auto run = [&](int frames, vtkTissueMosaicReconstructionLogic* logic) {
    ASSERT_TRUE(logic->SetParameters(parameters())) << logic->GetLastErrorText();
    logic->SetDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
    ASSERT_TRUE(logic->SetFrameSourceFactory([scan, frames] { return std::make_unique<FirstFrames>(scan, frames); }));
    logic->SetRectifiedGeometry(scan->geometry());
    ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
    ASSERT_TRUE(logic->WaitForScanEnd(120.0));
    logic->UpdateOutputs();
  };

  vtkNew<vtkTissueMosaicReconstructionLogic> out;
  run(12, out);  // ends with the camera out
  const auto& lost = out->GetStatus();
  std::cout << "[ measured ] camera out at the end: \"" << out->GetTrackingStateText() << "\", \""
            << out->GetAgreementText() << "\"\n";
  EXPECT_FALSE(lost.tracked);
  EXPECT_EQ(lost.lostFrames, 4);
  EXPECT_EQ(lost.frameStatus, static_cast<int>(tissuemosaic::FrameStatus::Lost));
  EXPECT_EQ(out->GetTrackingStateText().rfind("Lost: move the camera back over the scanned tissue", 0), 0u);
  EXPECT_EQ(out->GetAgreementText(), "model agreement: not measured");
  EXPECT_EQ(out->GetSceneMotionText(), "") << "a lost frame says nothing of what moved";

  vtkNew<vtkTissueMosaicReconstructionLogic> back;
  run(20, back);
  const auto& status = back->GetStatus();
  std::cout << "[ measured ] back from frame 14: relocalised at " << status.lastRelocalisedFrame << ", \""
            << back->GetTrackingStateText() << "\", \"" << back->GetAgreementText() << "\"\n";
  EXPECT_TRUE(status.tracked);
  EXPECT_EQ(status.lostFrames, 6);
  EXPECT_EQ(status.relocalisations, 1);
  EXPECT_GE(status.lastRelocalisedFrame, 14);
  EXPECT_LE(status.lastRelocalisedFrame, 18);
  EXPECT_EQ(back->GetTrackingStateText(), "Relocalised, finished");
  EXPECT_TRUE(status.agreement.measured);
  EXPECT_NE(status.agreementLevel, static_cast<int>(tissuemosaic::AgreementLevel::None));
  EXPECT_NE(back->GetAgreementText().find("% within 1 mm, median "), std::string::npos) << back->GetAgreementText();
  // The scan's scope sweeps at 6-20 mm/s (0.2-0.7 mm a frame): the last frame says the camera moves.
  EXPECT_EQ(back->GetSceneMotionText().rfind("Moving: the camera", 0), 0u) << back->GetSceneMotionText();
}

// A reset while running returns at once; the old worker finishes its frame in the background. Checked by events, not
// by the clock: the worker is held inside a frame read, and Reset must return while it still is.
TEST_F(ReconstructionLogicScan, ResetWhileRunningDoesNotWaitForTheWorker) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  setUp(logic);
  auto scan = scan_;
  auto gate = std::make_shared<Gate>();
  ASSERT_TRUE(logic->SetFrameSourceFactory([scan, gate] { return std::make_unique<GatedSource>(scan, gate); }));
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  ASSERT_TRUE(gate->waitForReader(60.0)) << "the worker never started reading frames";
  EXPECT_TRUE(gate->returnsWhileShut([&] { logic->Reset(); }, 20.0)) << "Reset waited for the worker's frame";
  gate->open();  // the old worker finishes its frame and ends in the background
  EXPECT_EQ(logic->GetScanState(), vtkTissueMosaicReconstructionLogic::StateIdle);
  EXPECT_TRUE(logic->CanChangeParameters());

  // Negative control: a call that does wait for the worker (here: for the gate itself) fails the same check.
  Gate shut;
  EXPECT_FALSE(shut.returnsWhileShut([&shut] { shut.waitUntilOpen(); }, 0.2));
}

// Every call the GUI makes returns while the worker is busy: checked by events, not by the clock. The first frame
// goes through (the worker makes progress while the owner polls), then the worker is held at the next frame read,
// and each call must return while it still is.
TEST_F(ReconstructionLogicScan, OwnerNeverWaitsForTheWorker) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  setUp(logic);
  auto scan = scan_;
  auto gate = std::make_shared<Gate>(1);
  ASSERT_TRUE(logic->SetFrameSourceFactory([scan, gate] { return std::make_unique<GatedSource>(scan, gate); }));
  logic->SetRectifiedGeometry(scan_->geometry());
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  ASSERT_TRUE(gate->waitForReader(120.0)) << "the worker never came to its second frame";
  bool processed = false;
  for (int poll = 0; poll < 6000 && !processed; ++poll) {  // the first frame's results reach the owner
    EXPECT_TRUE(gate->returnsWhileShut([&] { logic->UpdateOutputs(); }, 20.0)) << "UpdateOutputs waited";
    processed = logic->GetStatus().framesProcessed >= 1;
    if (!processed) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(processed) << "the first frame never reached the owner";
  EXPECT_TRUE(gate->returnsWhileShut([&] { logic->Pause(); }, 20.0)) << "Pause waited for the worker";
  EXPECT_TRUE(gate->returnsWhileShut([&] { EXPECT_TRUE(logic->Start()); }, 20.0)) << "resuming waited";
  EXPECT_TRUE(gate->returnsWhileShut([&] { logic->Stop(); }, 20.0)) << "Stop waited for the worker";
  EXPECT_TRUE(gate->returnsWhileShut([&] { logic->Reset(); }, 20.0)) << "Reset waited for the worker";
  gate->open();
}

TEST_F(ReconstructionLogicScan, SaysWhichDisparityRangeItUses) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  setUp(logic);
  // Before a scan: what the parameters ask for, in disparities where the rig is known.
  tissuemosaic::ReconstructionParameters distance = parameters();
  distance.stereo.disparityRangeMode = tissuemosaic::DisparityRangeMode::WorkingDistance;
  distance.stereo.workingDistanceNearMm = 50;
  distance.stereo.workingDistanceFarMm = 150;
  ASSERT_TRUE(logic->SetParameters(distance)) << logic->GetLastErrorText();
  tissuemosaic::RectifiedGeometry geometry;
  ASSERT_TRUE(logic->GetRectifiedGeometry(geometry));
  const tissuemosaic::DisparityRange expected = tissuemosaic::disparityRangeForDepthMm(geometry, 50, 150);
  EXPECT_EQ(logic->GetDisparityRangeText(), "working distance 50..150 mm: " + expected.text());

  // The automatic range (the default): chosen from the first frame, then reported as the scan goes.
  tissuemosaic::ReconstructionParameters automatic = parameters();
  automatic.stereo.disparityRangeMode = tissuemosaic::DisparityRangeMode::Automatic;
  ASSERT_TRUE(logic->SetParameters(automatic)) << logic->GetLastErrorText();
  EXPECT_EQ(logic->GetDisparityRangeText(), "auto: from the first frame's feature matches");
  logic->SetMaximumFrames(3);
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  ASSERT_TRUE(logic->WaitForScanEnd(120.0));
  logic->UpdateOutputs();
  const auto& status = logic->GetStatus();
  ASSERT_EQ(status.state, vtkTissueMosaicReconstructionLogic::StateFinished) << status.errorText;
  const auto frame = scan_->renderFrame(2);
  double low = 1e9, high = -1e9;
  for (int i = 0; i < static_cast<int>(frame.disparityPx.total()); ++i) {
    const float d = frame.disparityPx.at<float>(i);
    if (!std::isfinite(d)) continue;
    low = std::min<double>(low, d);
    high = std::max<double>(high, d);
  }
  EXPECT_LE(status.disparityRange.minPx, low);
  EXPECT_GE(status.disparityRange.maxPx, high);
  EXPECT_EQ(logic->GetDisparityRangeText().rfind("auto: " + status.disparityRange.text(), 0), 0u)
      << logic->GetDisparityRangeText();
}
