#include "vtkTissueMosaicSurfaceModelFile.h"

#include "IO/AtomicFile.h"
#include "IO/PointCloudPly.h"

#include "Core/Error.h"
#include "vtkTissueMosaicVtkMessages.h"

#include <Eigen/Dense>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>
#include <vtkStringArray.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <optional>

namespace tissuemosaic {

namespace {

/// Slicer's name of the VTP field-data array that holds the frame.
constexpr const char* kSpaceArrayName = "SPACE";

std::string lowercaseExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string extension = path.substr(dot);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension;
}

/// The frame a header text declares ("SPACE=LPS" / "SPACE=RAS"), if any.
std::optional<AnatomicalFrame> declaredFrame(const std::string& header) {
  if (header.find("SPACE=RAS") != std::string::npos) return AnatomicalFrame::RAS;
  if (header.find("SPACE=LPS") != std::string::npos) return AnatomicalFrame::LPS;
  return std::nullopt;
}

std::string text(const char* maybeNull) { return maybeNull ? maybeNull : ""; }

/// Runs a reader with its messages caught; throws Error with VTK's words when it reports an error.
template <class Reader>
vtkSmartPointer<vtkPolyData> runReader(Reader* reader, const std::string& path) {
  VtkMessageCatcher catcher(reader);
  reader->SetFileName(path.c_str());
  reader->Update();
  if (catcher.hasErrors()) throw Error("cannot read surface model '" + path + "': " + catcher.messages());
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->ShallowCopy(reader->GetOutput());
  return output;
}

/// Applies the LPS<->RAS flip to points and normals in place (a 180 degree turn about z: faces keep their order).
void flipInPlace(vtkPolyData* polyData) {
  Eigen::Matrix4d flip = Eigen::Matrix4d::Identity();
  flip(0, 0) = flip(1, 1) = -1;
  polyData->DeepCopy(transformedPolyData(polyData, flip));
}

void rotateVectors(vtkDataArray* vectors, const Eigen::Matrix3d& rotation) {
  if (!vectors || vectors->GetNumberOfComponents() != 3) return;
  for (vtkIdType i = 0; i < vectors->GetNumberOfTuples(); ++i) {
    double v[3];
    vectors->GetTuple(i, v);
    Eigen::Vector3d rotated = rotation * Eigen::Vector3d(v[0], v[1], v[2]);
    const double norm = rotated.norm();
    if (norm > 0) rotated /= norm;
    vectors->SetTuple(i, rotated.data());
  }
}

}  // namespace

SurfaceModelFile readSurfaceModel(const std::string& path, ModelFrameChoice frame) {
  {
    std::ifstream probe(path, std::ios::binary);
    require(probe.good(), "cannot read surface model '" + path + "': the file does not exist or is not readable");
    probe.seekg(0, std::ios::end);
    require(probe.tellg() > 0, "cannot read surface model '" + path + "': the file is empty");
  }
  const std::string extension = lowercaseExtension(path);
  SurfaceModelFile model;
  std::optional<AnatomicalFrame> declared;
  if (extension == ".stl") {
    vtkNew<vtkSTLReader> reader;
    model.polyDataLps = runReader(reader.Get(), path);
    std::string header = text(reader->GetHeader());
    if (header.empty() && reader->GetBinaryHeader()) {
      vtkUnsignedCharArray* bytes = reader->GetBinaryHeader();
      for (vtkIdType i = 0; i < bytes->GetNumberOfValues(); ++i) header += static_cast<char>(bytes->GetValue(i));
    }
    declared = declaredFrame(header);
  } else if (extension == ".vtk") {
    vtkNew<vtkPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    require(reader->IsFilePolyData(), "cannot read surface model '" + path +
                                          "': not a legacy VTK poly data file (a mesh saved as vtkPolyData)");
    model.polyDataLps = runReader(reader.Get(), path);
    declared = declaredFrame(text(reader->GetHeader()));
  } else if (extension == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> reader;
    model.polyDataLps = runReader(reader.Get(), path);
    if (auto* space = vtkStringArray::SafeDownCast(
            model.polyDataLps->GetFieldData()->GetAbstractArray(kSpaceArrayName));
        space && space->GetNumberOfValues() > 0) {
      declared = declaredFrame("SPACE=" + space->GetValue(0));
      model.polyDataLps->GetFieldData()->RemoveArray(kSpaceArrayName);
    }
  } else if (extension == ".ply") {
    // VTK's reader fills a truncated file's missing vertices with zeros (or crashes): check the whole file first.
    std::size_t vertices = 0;
    try {
      vertices = readPlyWholeFile(path).size();
    } catch (const Error& error) {
      throw Error("cannot read surface model '" + path + "': " + error.what());
    }
    vtkNew<vtkPLYReader> reader;
    require(reader->CanReadFile(path.c_str()), "cannot read surface model '" + path + "': not a PLY file");
    model.polyDataLps = runReader(reader.Get(), path);
    require(static_cast<std::size_t>(model.polyDataLps->GetNumberOfPoints()) == vertices,
            "cannot read surface model '" + path + "': VTK read " +
                std::to_string(model.polyDataLps->GetNumberOfPoints()) + " of its " + std::to_string(vertices) +
                " vertices");
    vtkStringArray* comments = reader->GetComments();
    for (vtkIdType i = 0; comments && i < comments->GetNumberOfValues() && !declared; ++i) {
      declared = declaredFrame(comments->GetValue(i));
    }
  } else if (extension == ".obj") {
    vtkNew<vtkOBJReader> reader;
    model.polyDataLps = runReader(reader.Get(), path);
    declared = declaredFrame(text(reader->GetComment()));
  } else {
    throw Error("cannot read surface model '" + path + "': unknown extension '" + extension +
                "' (use .stl, .vtk, .vtp, .ply or .obj)");
  }
  require(model.polyDataLps->GetNumberOfPoints() > 0,
          "the surface model '" + path + "' has no points (empty or not a mesh of this format)");

  model.frameDeclaredInFile = declared.has_value();
  switch (frame) {
    case ModelFrameChoice::FromFile: model.fileFrame = declared.value_or(AnatomicalFrame::LPS); break;
    case ModelFrameChoice::LPS: model.fileFrame = AnatomicalFrame::LPS; break;
    case ModelFrameChoice::RAS: model.fileFrame = AnatomicalFrame::RAS; break;
  }
  if (model.fileFrame == AnatomicalFrame::RAS) flipInPlace(model.polyDataLps);
  return model;
}

void writeSurfaceModel(const std::string& path, vtkPolyData* polyDataLps, AnatomicalFrame fileFrame) {
  require(polyDataLps != nullptr && polyDataLps->GetNumberOfPoints() > 0,
          "cannot write surface model '" + path + "': the model is empty");
  auto model = vtkSmartPointer<vtkPolyData>::New();
  model->DeepCopy(polyDataLps);
  if (fileFrame == AnatomicalFrame::RAS) flipInPlace(model);
  const std::string mark = std::string("SPACE=") + frameName(fileFrame);
  const std::string extension = lowercaseExtension(path);

  // VTK's writers report a missing folder with their own internals: say it plainly first.
  requireWritableOutput(path, "surface model");
  auto write = [&](auto* writer) {
    writeFileAtomically(path, "surface model", [&](const std::string& temporaryPath) {
      VtkMessageCatcher catcher(writer);
      writer->SetFileName(temporaryPath.c_str());
      const int ok = writer->Write();
      if (!ok || catcher.hasErrors()) {
        throw Error("cannot write surface model '" + path + "': " +
                    (catcher.messages().empty() ? std::string("the writer failed") : catcher.messages()));
      }
      return true;
    });
  };
  if (extension == ".vtp") {
    vtkNew<vtkStringArray> space;
    space->SetName(kSpaceArrayName);
    space->InsertNextValue(frameName(fileFrame));
    model->GetFieldData()->AddArray(space);
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(model);
    writer->SetDataModeToBinary();
    write(writer.Get());
  } else if (extension == ".ply") {
    vtkNew<vtkPLYWriter> writer;
    writer->SetInputData(model);
    writer->SetFileTypeToBinary();
    writer->AddComment(mark);
    if (auto* colors = vtkUnsignedCharArray::SafeDownCast(model->GetPointData()->GetScalars());
        colors && colors->GetName() && (colors->GetNumberOfComponents() == 3 || colors->GetNumberOfComponents() == 4)) {
      writer->SetArrayName(colors->GetName());
      writer->SetEnableAlpha(colors->GetNumberOfComponents() == 4);
    }
    write(writer.Get());
  } else if (extension == ".stl") {
    require(model->GetNumberOfPolys() > 0 || model->GetNumberOfStrips() > 0,
            "cannot write '" + path + "': STL holds triangles only and this model has none (use .vtp or .ply)");
    vtkNew<vtkTriangleFilter> triangles;
    triangles->SetInputData(model);
    triangles->Update();
    vtkNew<vtkSTLWriter> writer;
    writer->SetInputData(triangles->GetOutput());
    writer->SetFileTypeToBinary();
    writer->SetHeader(("TissueMosaic output. " + mark).c_str());
    write(writer.Get());
  } else if (extension == ".vtk") {
    vtkNew<vtkPolyDataWriter> writer;
    writer->SetInputData(model);
    writer->SetFileTypeToBinary();
    writer->SetHeader(("TissueMosaic output. " + mark).c_str());
    write(writer.Get());
  } else {
    throw Error("cannot write surface model '" + path + "': unknown extension '" + extension +
                "' (use .vtp, .ply, .stl or .vtk)");
  }
}

vtkSmartPointer<vtkPolyData> transformedPolyData(vtkPolyData* polyData, const Eigen::Matrix4d& transform) {
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->DeepCopy(polyData);
  const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
  const Eigen::Vector3d translation = transform.topRightCorner<3, 1>();
  vtkPoints* points = output->GetPoints();
  if (points) {
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
      double p[3];
      points->GetPoint(i, p);
      const Eigen::Vector3d mapped = linear * Eigen::Vector3d(p[0], p[1], p[2]) + translation;
      points->SetPoint(i, mapped.data());
    }
    points->Modified();
  }
  // Normals turn with the rotation part; a uniform scale only changes their length, renormalised below.
  const Eigen::Matrix3d normalMap = linear.inverse().transpose();
  rotateVectors(output->GetPointData()->GetNormals(), normalMap);
  rotateVectors(output->GetCellData()->GetNormals(), normalMap);
  return output;
}

std::vector<Eigen::Vector3d> finitePoints(const std::vector<Eigen::Vector3d>& points, std::size_t* leftOut) {
  std::vector<Eigen::Vector3d> finite;
  finite.reserve(points.size());
  for (const Eigen::Vector3d& p : points) {
    if (p.allFinite()) finite.push_back(p);
  }
  if (leftOut) *leftOut = points.size() - finite.size();
  return finite;
}

std::vector<Eigen::Vector3d> polyDataPoints(vtkPolyData* polyData) {
  std::vector<Eigen::Vector3d> points;
  if (!polyData || !polyData->GetPoints()) return points;
  points.resize(static_cast<std::size_t>(polyData->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < polyData->GetNumberOfPoints(); ++i) polyData->GetPoint(i, points[i].data());
  return points;
}

}  // namespace tissuemosaic
