// Every registration file read back the way 3D Slicer reads it: .tfm (resampling convention, LPS), markups
// .mrk.json and .fcsv (LPS/RAS), models (.vtp .ply .stl .vtk .obj with Slicer's SPACE mark), the distance CSV
// and histogram PNG; and bad files answered by clear errors.
#include "TestRegistrationScene.h"
#include "Core/Error.h"
#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicItkTransformFile.h"
#include "vtkTissueMosaicLandmarksFile.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSTLReader.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataReader.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace tissuemosaic;
using namespace tissuemosaic::test;

namespace {

std::string outputPath(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "registration";
  std::filesystem::create_directories(folder);
  return (folder / name).string();
}

void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string readText(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

/// Runs `body`, expects an Error whose message contains `expected`.
template <class Body>
void expectError(Body body, const std::string& expected) {
  try {
    body();
    ADD_FAILURE() << "no error; expected one containing '" << expected << "'";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos) << error.what();
  }
}

Eigen::Matrix4d slicerFlip() {
  Eigen::Matrix4d flip = Eigen::Matrix4d::Identity();
  flip(0, 0) = flip(1, 1) = -1;
  return flip;
}

vtkSmartPointer<vtkPolyData> sphere() {
  vtkNew<vtkSphereSource> source;
  source->SetCenter(10, -20, 30);
  source->SetRadius(15);
  source->Update();
  vtkSmartPointer<vtkPolyData> output = source->GetOutput();
  return output;
}

}  // namespace

TEST(RegistrationFiles, TransformFileHoldsTheInverseInItkFormatAndReadsBack) {
  Eigen::Matrix4d targetFromModel = rigidTransform({0.2, 1, -0.4}, 27, {5, 5, 5}, {-12.5, 40, 88});
  targetFromModel.topLeftCorner<3, 3>() *= 1.03;  // a similarity from a --scale registration
  const std::string path = outputPath("transform.tfm");
  writeModelToTargetTransform(path, targetFromModel);

  std::istringstream lines(readText(path));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "#Insight Transform File V1.0");
  std::getline(lines, line);
  EXPECT_EQ(line, "#Transform 0");
  std::getline(lines, line);
  EXPECT_EQ(line, "Transform: AffineTransform_double_3_3");
  std::getline(lines, line);
  ASSERT_EQ(line.rfind("Parameters: ", 0), 0u);
  std::istringstream parameters(line.substr(12));
  std::vector<double> values;
  for (double v; parameters >> v;) values.push_back(v);
  ASSERT_EQ(values.size(), 12u);
  std::getline(lines, line);
  EXPECT_EQ(line, "FixedParameters: 0 0 0");

  // The file is T_model_target (ITK: fixed = CT -> moving = model).
  const Eigen::Matrix4d inFile = readItkTransformFile(path);
  EXPECT_LT((inFile - targetFromModel.inverse()).norm(), 1e-12);
  EXPECT_NEAR(values[9], inFile(0, 3), 1e-12);
  EXPECT_LT((readModelToTargetTransform(path) - targetFromModel).norm(), 1e-10);

  // Slicer: LPS file -> RAS by F T F; "transform to parent" = inverse of the resampling transform. A model point
  // (RAS in Slicer) put under that transform must land where T_target_model sends it.
  const Eigen::Matrix4d toParentRas = (slicerFlip() * inFile * slicerFlip()).inverse();
  const Eigen::Vector4d modelLps(3, -7, 42, 1);
  const Eigen::Vector4d landedRas = toParentRas * (slicerFlip() * modelLps);
  EXPECT_LT((slicerFlip() * landedRas - targetFromModel * modelLps).norm(), 1e-9);
}

TEST(RegistrationFiles, TransformFileWithCentreAndOtherTypes) {
  const std::string path = outputPath("centred.tfm");
  writeText(path,
            "#Insight Transform File V1.0\n#Transform 0\nTransform: MatrixOffsetTransformBase_double_3_3\n"
            "Parameters: 0 -1 0 1 0 0 0 0 1 1 2 3\nFixedParameters: 10 0 0\n");
  const Eigen::Matrix4d matrix = readItkTransformFile(path);
  // y = A (x - c) + t + c at x = c gives t + c.
  const Eigen::Vector4d atCentre = matrix * Eigen::Vector4d(10, 0, 0, 1);
  EXPECT_LT((atCentre - Eigen::Vector4d(11, 2, 3, 1)).norm(), 1e-12);
  writeText(path, "#Insight Transform File V1.0\nTransform: TranslationTransform_double_3_3\nParameters: 1 2 3\n"
                  "FixedParameters:\n");
  EXPECT_LT((readItkTransformFile(path).topRightCorner<3, 1>() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);

  writeText(path, "#Insight Transform File V1.0\nTransform: BSplineTransform_double_3_3\nParameters: 1 2 3 4\n");
  expectError([&] { readItkTransformFile(path); }, "only 3D linear transforms");
  writeText(path, "not a transform\n");
  expectError([&] { readItkTransformFile(path); }, "not an ITK text transform file");
  writeText(path, "#Insight Transform File V1.0\nTransform: AffineTransform_double_3_3\nParameters: 1 0 0 x\n");
  expectError([&] { readItkTransformFile(path); }, "not a number");
  expectError([&] { readItkTransformFile(outputPath("missing.tfm")); }, "does not exist");
}

TEST(RegistrationFiles, MarkupsJsonRoundTripInBothFrames) {
  LandmarkList model{"model landmarks", {{"tip", {1.5, -2, 30}}, {"notch", {-4, 8.25, 31}}, {"ridge", {0, 0, 29}}}};
  LandmarkList target{"target landmarks", {{"tip", {11, 2, -3}}, {"notch", {6, 12, -4}}, {"ridge", {9, 5, -2}}}};
  for (const AnatomicalFrame frame : {AnatomicalFrame::LPS, AnatomicalFrame::RAS}) {
    const std::string path = outputPath(std::string("pairs_") + frameName(frame) + ".mrk.json");
    writeLandmarkFile(path, {model, target}, frame);

    // The raw JSON as Slicer reads it.
    const auto document = nlohmann::json::parse(readText(path));
    ASSERT_EQ(document["markups"].size(), 2u);
    const auto& first = document["markups"][0];
    EXPECT_EQ(first["type"], "Fiducial");
    EXPECT_EQ(first["coordinateSystem"], frameName(frame));
    EXPECT_EQ(first["controlPoints"][0]["label"], "tip");
    const double sign = frame == AnatomicalFrame::RAS ? -1 : 1;
    EXPECT_DOUBLE_EQ(first["controlPoints"][0]["position"][0].get<double>(), sign * 1.5);
    EXPECT_DOUBLE_EQ(first["controlPoints"][0]["position"][1].get<double>(), sign * -2);
    EXPECT_DOUBLE_EQ(first["controlPoints"][0]["position"][2].get<double>(), 30);

    const LandmarkPairs pairs = readLandmarkPairs(path);
    ASSERT_EQ(pairs.labels.size(), 3u);
    EXPECT_TRUE(pairs.pairedByLabel);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_LT((pairs.modelLps[i] - model.points[i].positionLps).norm(), 1e-12);
      EXPECT_LT((pairs.targetLps[i] - target.points[i].positionLps).norm(), 1e-12);
    }
  }
}

TEST(RegistrationFiles, SlicerMarkupsJsonAndFcsvAreRead) {
  // As Slicer 5 writes a point list (trimmed): RAS, one point missing.
  const std::string json = outputPath("slicer.mrk.json");
  writeText(json, R"({"@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#",
    "markups": [{"type": "Fiducial", "coordinateSystem": "RAS", "coordinateUnits": "mm", "controlPoints": [
      {"id": "1", "label": "F-1", "position": [10.0, 20.0, 30.0], "positionStatus": "defined"},
      {"id": "2", "label": "F-2", "position": [0.0, 0.0, 0.0], "positionStatus": "missing"},
      {"id": "3", "label": "F-3", "position": [-1.5, 2.5, -3.5]}]}]})");
  const LandmarkList list = readLandmarks(json);
  ASSERT_EQ(list.points.size(), 2u);
  EXPECT_EQ(list.fileFrame, AnatomicalFrame::RAS);
  EXPECT_EQ(list.points[1].label, "F-3");
  EXPECT_LT((list.points[0].positionLps - Eigen::Vector3d(-10, -20, 30)).norm(), 1e-12);
  EXPECT_LT((list.points[1].positionLps - Eigen::Vector3d(1.5, -2.5, -3.5)).norm(), 1e-12);

  // Slicer 4.11 .fcsv (LPS) with a quoted label, and an old one with the numeric code 0 = RAS.
  const std::string fcsv = outputPath("slicer.fcsv");
  writeText(fcsv, "# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n"
                  "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n"
                  "vtkMRMLMarkupsFiducialNode_0,1,2,3,0,0,0,1,1,1,0,\"a, b\",,\n"
                  "vtkMRMLMarkupsFiducialNode_1,-4.5,5,6e1,0,0,0,1,1,1,0,F-2,,\n");
  const LandmarkList fromFcsv = readLandmarks(fcsv);
  ASSERT_EQ(fromFcsv.points.size(), 2u);
  EXPECT_EQ(fromFcsv.points[0].label, "a, b");
  EXPECT_LT((fromFcsv.points[1].positionLps - Eigen::Vector3d(-4.5, 5, 60)).norm(), 1e-12);
  writeText(fcsv, "# Markups fiducial file version = 4.4\n# CoordinateSystem = 0\n"
                  "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n"
                  "1,1,2,3,0,0,0,1,1,1,0,P,,\n");
  EXPECT_LT((readLandmarks(fcsv).points[0].positionLps - Eigen::Vector3d(-1, -2, 3)).norm(), 1e-12);

  // Round trip of our own .fcsv in RAS.
  const std::string written = outputPath("written.fcsv");
  writeLandmarkFile(written, {fromFcsv}, AnatomicalFrame::RAS);
  EXPECT_NE(readText(written).find("# CoordinateSystem = RAS"), std::string::npos);
  const LandmarkList back = readLandmarks(written);
  ASSERT_EQ(back.points.size(), 2u);
  EXPECT_EQ(back.points[0].label, "a, b");
  EXPECT_LT((back.points[1].positionLps - fromFcsv.points[1].positionLps).norm(), 1e-12);

  // No declared frame: an error unless the caller states one.
  writeText(fcsv, "1,1,2,3,0,0,0,1,1,1,0,P,,\n");
  expectError([&] { readLandmarks(fcsv); }, "does not say whether it is in LPS or RAS");
  writeText(fcsv, "");  // issue 32: an empty file said "does not say LPS or RAS"
  expectError([&] { readLandmarks(fcsv, AnatomicalFrame::RAS); }, "holds no landmarks");
  writeText(fcsv, "1,1,2,3,0,0,0,1,1,1,0,P,,\n");
  EXPECT_LT((readLandmarks(fcsv, AnatomicalFrame::RAS).points[0].positionLps - Eigen::Vector3d(-1, -2, 3)).norm(),
            1e-12);
}

TEST(RegistrationFiles, LandmarkPairingAndBadLandmarkFiles) {
  LandmarkList model{"", {{"A", {0, 0, 0}}, {"B", {1, 0, 0}}, {"C", {0, 1, 0}}}};
  LandmarkList shuffled{"", {{"C", {0, 3, 0}}, {"A", {0, 0, 3}}, {"B", {3, 0, 0}}}};
  const LandmarkPairs byLabel = pairLandmarks(model, shuffled);
  EXPECT_TRUE(byLabel.pairedByLabel);
  EXPECT_LT((byLabel.targetLps[0] - Eigen::Vector3d(0, 0, 3)).norm(), 1e-12);
  LandmarkList unlabeled{"", {{"", {5, 0, 0}}, {"", {6, 0, 0}}, {"", {7, 0, 0}}}};
  const LandmarkPairs byOrder = pairLandmarks(model, unlabeled);
  EXPECT_FALSE(byOrder.pairedByLabel);
  EXPECT_LT((byOrder.targetLps[2] - Eigen::Vector3d(7, 0, 0)).norm(), 1e-12);
  unlabeled.points.pop_back();
  expectError([&] { pairLandmarks(model, unlabeled); }, "cannot pair the landmarks: 3 on the model but 2");
  // Issue 32: labels that match in part (one misnamed point, listed in another order) were paired by order, a wrong
  // fit without a word. They are an error naming the labels on one side only.
  LandmarkList misnamed{"", {{"C", {0, 3, 0}}, {"A", {0, 0, 3}}, {"X", {3, 0, 0}}}};
  expectError([&] { pairLandmarks(model, misnamed); },
              "the landmark labels do not match: only on the model: 'B'; only on the target: 'X'");
  misnamed.points.pop_back();
  expectError([&] { pairLandmarks(model, misnamed); }, "only on the model: 'B'; only on the target: none");
  // No label in common (each list numbered by its own name): the labels say nothing, order pairs them.
  LandmarkList ownNames{"", {{"T-1", {5, 0, 0}}, {"T-2", {6, 0, 0}}, {"T-3", {7, 0, 0}}}};
  EXPECT_FALSE(pairLandmarks(model, ownNames).pairedByLabel);

  const std::string path = outputPath("bad.mrk.json");
  writeText(path, "{\"markups\": [ {\"coordinateSystem\": \"LPS\", \"controlPoints\": [ {\"position\": [1, 2]} ]} ]}");
  expectError([&] { readLandmarks(path); }, "not three numbers");
  writeText(path, "{ not json");
  expectError([&] { readLandmarks(path); }, "not valid JSON");
  writeText(path, "{\"markups\": [ {\"coordinateSystem\": \"IJK\"} ]}");
  expectError([&] { readLandmarks(path); }, "only LPS and RAS");
  writeText(path, "{\"markups\": [ {\"coordinateSystem\": \"LPS\"} ]}");
  expectError([&] { readLandmarkPairs(path); }, "expected two");
  expectError([&] { readLandmarks(outputPath("nothing.mrk.json")); }, "does not exist");
  expectError([&] { readLandmarks(outputPath("points.txt")); }, ".mrk.json or .fcsv");
}

TEST(RegistrationFiles, ModelsWrittenWithSlicersSpaceMarkAndReadBack) {
  const auto model = sphere();
  double expected[3];
  model->GetPoint(7, expected);
  for (const std::string extension : {".vtp", ".ply", ".stl", ".vtk"}) {
    for (const AnatomicalFrame frame : {AnatomicalFrame::LPS, AnatomicalFrame::RAS}) {
      SCOPED_TRACE(extension + " " + frameName(frame));
      const std::string path = outputPath(std::string("sphere_") + frameName(frame) + extension);
      writeSurfaceModel(path, model, frame);

      // What a plain VTK reader (Slicer's) sees: the coordinates in `frame` and the SPACE mark.
      vtkSmartPointer<vtkPolyData> raw;
      std::string mark;
      if (extension == ".vtp") {
        vtkNew<vtkXMLPolyDataReader> reader;
        reader->SetFileName(path.c_str());
        reader->Update();
        raw = reader->GetOutput();
        auto* space = vtkStringArray::SafeDownCast(raw->GetFieldData()->GetAbstractArray("SPACE"));
        ASSERT_NE(space, nullptr);
        mark = "SPACE=" + space->GetValue(0);
      } else if (extension == ".ply") {
        vtkNew<vtkPLYReader> reader;
        reader->SetFileName(path.c_str());
        reader->Update();
        raw = reader->GetOutput();
        for (vtkIdType i = 0; i < reader->GetComments()->GetNumberOfValues(); ++i) mark += reader->GetComments()->GetValue(i);
      } else if (extension == ".stl") {
        vtkNew<vtkSTLReader> reader;
        reader->SetFileName(path.c_str());
        reader->Update();
        raw = reader->GetOutput();
        if (reader->GetHeader()) mark = reader->GetHeader();
        if (auto* bytes = reader->GetBinaryHeader()) {
          for (vtkIdType i = 0; i < bytes->GetNumberOfValues(); ++i) mark += static_cast<char>(bytes->GetValue(i));
        }
      } else {
        vtkNew<vtkPolyDataReader> reader;
        reader->SetFileName(path.c_str());
        reader->Update();
        raw = reader->GetOutput();
        mark = reader->GetHeader();
      }
      EXPECT_NE(mark.find(std::string("SPACE=") + frameName(frame)), std::string::npos) << mark;
      ASSERT_GT(raw->GetNumberOfPoints(), 0);
      EXPECT_EQ(raw->GetNumberOfPolys(), model->GetNumberOfPolys());
      const double sign = frame == AnatomicalFrame::RAS ? -1 : 1;
      if (extension != ".stl") {  // STL stores triangles, not the point list: compare bounds instead
        double p[3];
        raw->GetPoint(7, p);
        EXPECT_NEAR(p[0], sign * expected[0], 1e-4);
        EXPECT_NEAR(p[1], sign * expected[1], 1e-4);
        EXPECT_NEAR(p[2], expected[2], 1e-4);
      }
      // Our reader honours the mark and returns LPS; forcing the other frame flips it.
      const SurfaceModelFile back = readSurfaceModel(path);
      EXPECT_TRUE(back.frameDeclaredInFile);
      EXPECT_EQ(back.fileFrame, frame);
      double bounds[6], original[6];
      back.polyDataLps->GetBounds(bounds);
      model->GetBounds(original);
      for (int i = 0; i < 6; ++i) EXPECT_NEAR(bounds[i], original[i], 1e-4);
      const SurfaceModelFile forced =
          readSurfaceModel(path, frame == AnatomicalFrame::LPS ? ModelFrameChoice::RAS : ModelFrameChoice::LPS);
      forced.polyDataLps->GetBounds(bounds);
      EXPECT_NEAR(bounds[0], -original[1], 1e-4);
      EXPECT_NEAR(bounds[4], original[4], 1e-4);
    }
  }
}

TEST(RegistrationFiles, ObjAndUnmarkedFilesAreLps) {
  const std::string path = outputPath("triangle.obj");
  writeText(path, "# SPACE=RAS\nv 1 2 3\nv 4 5 6\nv 7 8 10\nf 1 2 3\n");
  const SurfaceModelFile marked = readSurfaceModel(path);
  EXPECT_EQ(marked.fileFrame, AnatomicalFrame::RAS);
  double p[3];
  marked.polyDataLps->GetPoint(0, p);
  EXPECT_DOUBLE_EQ(p[0], -1);
  EXPECT_DOUBLE_EQ(p[1], -2);
  EXPECT_DOUBLE_EQ(p[2], 3);
  writeText(path, "v 1 2 3\nv 4 5 6\nv 7 8 10\nf 1 2 3\n");
  const SurfaceModelFile unmarked = readSurfaceModel(path);
  EXPECT_FALSE(unmarked.frameDeclaredInFile);
  EXPECT_EQ(unmarked.fileFrame, AnatomicalFrame::LPS);
  unmarked.polyDataLps->GetPoint(0, p);
  EXPECT_DOUBLE_EQ(p[0], 1);
}

TEST(RegistrationFiles, BadModelFilesAreClearErrors) {
  expectError([&] { readSurfaceModel(outputPath("none.stl")); }, "does not exist");
  const std::string empty = outputPath("empty.ply");
  writeText(empty, "");
  expectError([&] { readSurfaceModel(empty); }, "the file is empty");
  const std::string corruptPly = outputPath("corrupt.ply");
  writeText(corruptPly, "this is not a ply file at all\n");
  expectError([&] { readSurfaceModel(corruptPly); }, "not a PLY file");
  const std::string corruptVtp = outputPath("corrupt.vtp");
  writeText(corruptVtp, "<VTKFile type=\"PolyData\"><broken");
  expectError([&] { readSurfaceModel(corruptVtp); }, "cannot read surface model");
  const std::string noPoints = outputPath("nopoints.obj");
  writeText(noPoints, "# nothing here\n");
  expectError([&] { readSurfaceModel(noPoints); }, "has no points");
  const std::string unknown = outputPath("model.xyz");
  writeText(unknown, "1 2 3\n");
  expectError([&] { readSurfaceModel(unknown); }, "unknown extension");
  vtkNew<vtkPolyData> nothing;
  expectError([&] { writeSurfaceModel(outputPath("nothing.vtp"), nothing); }, "the model is empty");
  expectError([&] { writeSurfaceModel("/nonexistent-folder/model.vtp", sphere()); }, "cannot write surface model");
}

// Found by fuzz_surface_{stl,obj,vtp} (the inputs are in Testing/Fuzz/corpus): VTK 9.1's readers crashed (OBJ, VTP:
// segmentation fault in `tissuemosaic eval`) or asked for 19.6 GB (STL) on these; the project's checks refuse them.
TEST(RegistrationFiles, FilesThatCrashVtksReadersAreClearErrors) {
  const std::string obj = outputPath("undefined-reference.obj");
  writeText(obj, "f 2 100/1\nf 2//1 /1\n");
  expectError([&] { readSurfaceModel(obj); }, "line 1: 'f' refers to vertex 2 but 0 are defined before it");
  writeText(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\x80\x81\nf 1//1 2//1 3//1\n");
  expectError([&] { readSurfaceModel(obj); }, "line 4: 'vn' needs 3 numbers");
  writeText(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 -1/1\n");
  expectError([&] { readSurfaceModel(obj); }, "refers to texture coordinate 2 but 1 are defined");
  writeText(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 -1/1/-1\n");
  EXPECT_EQ(readSurfaceModel(obj).polyDataLps->GetNumberOfPoints(), 3);  // negative (relative) indices are fine

  const std::string vtp = outputPath("unknown-type.vtp");
  writeText(vtp, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\"><PolyData><FieldData>"
                 "<Array type=\"StOing\" Name=\"SPACE\" NumberOfTuples=\"1\" format=\"ascii\">76 80 83 0</Array>"
                 "</FieldData></PolyData></VTKFile>\n");
  expectError([&] { readSurfaceModel(vtp); }, "an array has the unknown type 'StOing'");

  const std::string vtk = outputPath("malformed.vtk");
  writeText(vtk, "# vtk DataFile Version\n\nASCII\nDATASET POLYDATA\nPOINTS 4f POLYGONS 2 8");
  expectError([&] { readSurfaceModel(vtk); }, "section POINTS does not give its counts");
  writeText(vtk, "# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                 "POLYGONS 1 4\n3 0 1\n");
  expectError([&] { readSurfaceModel(vtk); }, "POLYGONS declares 4 numbers but 3 follow");
  writeText(vtk, "# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                 "POLYGONS 1 4\n3 0 1 2\n");
  EXPECT_EQ(readSurfaceModel(vtk).polyDataLps->GetNumberOfCells(), 1);
  // VTK reads the format word in any case: "AScII" with a byte that is no number among a cell's ids crashed it
  // (fuzz_surface_vtk, corpus/fuzz_surface_vtk/crash-f3b9f5a2*) while the check above took the file for binary.
  writeText(vtk, "# vtk DataFile Version 4.2\nx\nAScII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                 "POLYGONS 1 4\n3 0 \x9d 2\n");
  expectError([&] { readSurfaceModel(vtk); }, "POLYGONS");

  const std::string stl = outputPath("huge-count.stl");
  std::string binary(80, '\x01');
  binary += std::string("\xff\xff\xff\x7f", 4) + std::string(50, '\x02');
  writeText(stl, binary);
  expectError([&] { readSurfaceModel(stl); }, "the binary STL declares 2147483647 triangles but holds 134 bytes");
}

TEST(RegistrationFiles, DistanceCsvHistogramPngAndDistanceMap) {
  const std::vector<Eigen::Vector3d> points = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  const std::vector<double> distances = {0.05, 0.15, 1.25}, signedDistances = {-0.05, 0.15, 1.25};
  const std::string csv = outputPath("distances.csv");
  writeDistanceCsv(csv, points, distances, signedDistances);
  std::istringstream lines(readText(csv));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "index,x_mm,y_mm,z_mm,distance_mm,signed_distance_mm");
  std::getline(lines, line);
  EXPECT_EQ(line, "0,1,2,3,0.05,-0.05");

  const DistanceStatistics statistics = distanceStatistics(distances);
  const DistanceHistogram histogram = distanceHistogram(distances, 0.1);
  ASSERT_EQ(histogram.counts.size(), 13u);
  EXPECT_EQ(histogram.counts[0] + histogram.counts[1] + histogram.counts[12], 3u);
  const std::string png = outputPath("histogram.png");
  writeHistogramPng(png, histogram, statistics);
  const cv::Mat image = cv::imread(png);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 900);
  EXPECT_EQ(image.rows, 560);
  // The bars are drawn in the bar colour (BGR 180, 110, 40): some pixels must have it.
  cv::Mat barMask;
  cv::inRange(image, cv::Scalar(180, 110, 40), cv::Scalar(180, 110, 40), barMask);
  EXPECT_GT(cv::countNonZero(barMask), 1000);
  expectError([&] { writeHistogramPng("/nonexistent-folder/h.png", histogram, statistics); }, "cannot write");

  auto model = sphere();
  std::vector<double> perPoint(static_cast<std::size_t>(model->GetNumberOfPoints()), 0.5);
  addDistanceArrays(model, perPoint, perPoint);
  const std::string vtp = outputPath("distance_map.vtp");
  writeSurfaceModel(vtp, model);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(vtp.c_str());
  reader->Update();
  ASSERT_NE(reader->GetOutput()->GetPointData()->GetArray("DistanceMm"), nullptr);
  EXPECT_FLOAT_EQ(reader->GetOutput()->GetPointData()->GetArray("DistanceMm")->GetComponent(3, 0), 0.5f);
}

// VTK 9.1's PLY reader calls strtol(NULL) when an ASCII row is split over two lines (found by fuzz_surface_ply:
// a segfault in eval and register): each row must be one line of its declared values.
TEST(RegistrationFiles, AsciiPlyRowsSplitOverLinesAreErrors) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string good = outputPath("ascii_triangle.ply");
  writeText(good, header + "0 0 50\n1 0 50\n0 1 51\n3 0 1 2\n");
  EXPECT_EQ(readSurfaceModel(good).polyDataLps->GetNumberOfPoints(), 3);
  const std::string split = outputPath("ascii_split_row.ply");
  writeText(split, header + "0 0 50\n1 0\n50 0 1 51\n3 0 1 2\n");
  expectError([&] { readSurfaceModel(split); }, "row 1 of element 'vertex' is not one line of its declared values");
  const std::string longList = outputPath("ascii_long_list.ply");
  writeText(longList, header + "0 0 50\n1 0 50\n0 1 51\n3 0 1 2 0\n");
  expectError([&] { readSurfaceModel(longList); }, "row 0 of element 'face'");
}

// VTK 9.1's PLY reader fills a truncated file's missing vertices with zeros (a silently wrong model) or crashes:
// readSurfaceModel checks the whole file first, in the vertex data and in the faces.
TEST(RegistrationFiles, TruncatedPlyModelsAreErrors) {
  const std::string path = outputPath("sphere_full.ply");
  writeSurfaceModel(path, sphere());
  const std::string bytes = readText(path);
  ASSERT_EQ(readSurfaceModel(path).polyDataLps->GetNumberOfPoints(), sphere()->GetNumberOfPoints());
  const std::size_t header = bytes.find("end_header\n") + 11;
  ASSERT_GT(bytes.size(), header + 100);
  // A third of the body: within the vertices; all but the last 5 bytes: within the faces (the last element).
  for (const std::size_t keep : {header + (bytes.size() - header) / 3, bytes.size() - 5}) {
    const std::string truncated = outputPath("sphere_truncated.ply");
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, keep);
    expectError([&] { readSurfaceModel(truncated); }, "truncated");
  }
}
