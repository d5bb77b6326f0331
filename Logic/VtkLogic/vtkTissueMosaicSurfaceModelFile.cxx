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
#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <vector>

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

/// VTK's STL reader takes a file for binary as vtksys::SystemTools::DetectFileType does, and then allocates the
/// triangle count that bytes 80-83 declare before reading any: a corrupt 300-byte file asked for 19.6 GB. A
/// binary STL is 84 bytes plus 50 per triangle.
void requireBinaryStlCountFits(const std::string& path) {
  if (vtksys::SystemTools::DetectFileType(path.c_str()) != vtksys::SystemTools::FileTypeBinary) return;
  std::ifstream file(path, std::ios::binary);
  file.seekg(0, std::ios::end);
  const long long bytes = static_cast<long long>(file.tellg());
  require(bytes >= 84, "cannot read surface model '" + path + "': a binary STL file holds at least 84 bytes, this one " +
                           std::to_string(bytes));
  unsigned char count[4] = {};
  file.seekg(80);
  file.read(reinterpret_cast<char*>(count), 4);
  const long long triangles = count[0] | count[1] << 8 | count[2] << 16 | static_cast<long long>(count[3]) << 24;
  require(84 + 50 * triangles <= bytes, "cannot read surface model '" + path + "': the binary STL declares " +
                                            std::to_string(triangles) + " triangles but holds " +
                                            std::to_string(bytes) + " bytes (84 + 50 per triangle)");
}

/// True when `text` is a whole number (strtod / strtoll took every character).
bool isNumber(const std::string& text, bool integer) {
  if (text.empty()) return false;
  char* end = nullptr;
  if (integer) std::strtoll(text.c_str(), &end, 10);
  else std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

/// VTK 9.1's OBJ reader dereferences null when a face uses a vertex, texture coordinate or normal that the file
/// does not define (`f 2 100/1` with no `v` line; a `vn` line whose numbers are garbage): check every reference
/// first. OBJ indices are 1-based, negative ones count back from the last definition.
void requireObjReferencesDefined(const std::string& path) {
  std::ifstream file(path);
  std::string line;
  long long defined[3] = {0, 0, 0};  // v, vt, vn
  const char* names[3] = {"vertex", "texture coordinate", "normal"};
  for (long long number = 1; std::getline(file, line); ++number) {
    std::istringstream words(line);
    std::string keyword, word;
    words >> keyword;
    const auto fail = [&](const std::string& why) {
      throw Error("cannot read surface model '" + path + "': line " + std::to_string(number) + ": " + why);
    };
    const int definition = keyword == "v" ? 0 : keyword == "vt" ? 1 : keyword == "vn" ? 2 : -1;
    if (definition >= 0) {
      const int needed = definition == 1 ? 1 : 3;
      for (int i = 0; i < needed; ++i) {
        if (!(words >> word) || !isNumber(word, false)) fail("'" + keyword + "' needs " + std::to_string(needed) + " numbers");
      }
      ++defined[definition];
    } else if (keyword == "f" || keyword == "l" || keyword == "p") {
      while (words >> word) {
        std::istringstream parts(word);
        std::string part;
        for (int kind = 0; kind < 3 && std::getline(parts, part, '/'); ++kind) {
          if (part.empty() && kind > 0) continue;  // "1//3": no texture coordinate
          if (!isNumber(part, true)) fail("'" + word + "' is not a reference such as 1, 1/2 or 1//3");
          const long long index = std::strtoll(part.c_str(), nullptr, 10);
          if (index == 0 || index > defined[kind] || -index > defined[kind]) {
            fail("'" + keyword + "' refers to " + names[kind] + " " + part + " but " + std::to_string(defined[kind]) +
                 " are defined before it");
          }
        }
      }
    }
  }
}

/// VTK 9.1's XML reader dereferences null for an array whose type it does not know (`<Array type="StOing"`):
/// check the type of every array in the XML part of the file (before any appended raw data) first.
void requireVtkXmlArrayTypesKnown(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  text = text.substr(0, text.find("<AppendedData"));
  static const char* known[] = {"Int8",   "Int16",  "Int32",   "Int64",   "UInt8",  "UInt16", "UInt32",
                                "UInt64", "Float32", "Float64", "String", "Bit"};
  for (const char* tag : {"<DataArray", "<Array"}) {
    for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1)) {
      const std::string element = text.substr(at, text.find('>', at) - at);
      const std::size_t typeAt = element.find(" type=\"");
      const std::string type =
          typeAt == std::string::npos ? "" : element.substr(typeAt + 7, element.find('"', typeAt + 7) - typeAt - 7);
      require(std::find_if(std::begin(known), std::end(known), [&](const char* k) { return type == k; }) !=
                  std::end(known),
              "cannot read surface model '" + path + "': an array has " +
                  (typeAt == std::string::npos ? std::string("no type") : "the unknown type '" + type + "'") +
                  " (Int8..UInt64, Float32, Float64, String or Bit)");
    }
  }
}

/// VTK 9.1's legacy reader dereferences null when a section of an ASCII file is malformed and the file ends inside
/// it (`POINTS 4f POLYGONS 2 8`, found by fuzz_surface_vtk). For ASCII files, check that POINTS names its count
/// and a known type and that the numbers follow, and that each cell section's integers follow, before VTK reads.
void requireLegacyVtkSectionsComplete(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::string line;
  for (int i = 0; i < 3 && std::getline(file, line); ++i) {
  }
  // VTK takes the format word in any case ("AScII" too: fuzz_surface_vtk); binary legacy files: counted blocks.
  std::string format = line.substr(0, 5);
  std::transform(format.begin(), format.end(), format.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (format != "ascii") return;
  std::vector<std::string> tokens;
  for (std::string token; file >> token;) tokens.push_back(token);
  const auto fail = [&](const std::string& why) {
    throw Error("cannot read surface model '" + path + "': " + why);
  };
  const auto count = [&](std::size_t at, const std::string& section) {
    if (at >= tokens.size() || !isNumber(tokens[at], true) || std::strtoll(tokens[at].c_str(), nullptr, 10) < 0) {
      fail("section " + section + " does not give its counts");
    }
    return static_cast<std::size_t>(std::strtoll(tokens[at].c_str(), nullptr, 10));
  };
  static const char* types[] = {"bit", "unsigned_char", "char", "unsigned_short", "short", "unsigned_int", "int",
                                "unsigned_long", "long", "float", "double", "vtkIdType", "vtktypeint64",
                                "vtktypeuint64"};
  for (std::size_t at = 0; at < tokens.size(); ++at) {
    const std::string& word = tokens[at];
    std::size_t numbers = 0;
    if (word == "POINTS") {
      numbers = 3 * count(at + 1, word);
      if (at + 2 >= tokens.size() || std::find(std::begin(types), std::end(types), tokens[at + 2]) == std::end(types))
        fail("POINTS has no known data type");
      at += 2;
    } else if (word == "VERTICES" || word == "LINES" || word == "POLYGONS" || word == "TRIANGLE_STRIPS") {
      count(at + 1, word);
      numbers = count(at + 2, word);
      at += 2;
      // VTK 5.1 files: OFFSETS / CONNECTIVITY blocks follow, each with a type and its own integers.
      if (at + 1 < tokens.size() && tokens[at + 1] == "OFFSETS") numbers = 0;
    } else {
      continue;
    }
    for (std::size_t k = 1; k <= numbers; ++k) {
      if (at + k >= tokens.size() || !isNumber(tokens[at + k], false)) {
        fail(word + " declares " + std::to_string(numbers) + " numbers but " + std::to_string(k - 1) + " follow");
      }
    }
    at += numbers;
  }
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
    requireBinaryStlCountFits(path);
    vtkNew<vtkSTLReader> reader;
    model.polyDataLps = runReader(reader.Get(), path);
    std::string header = text(reader->GetHeader());
    if (header.empty() && reader->GetBinaryHeader()) {
      vtkUnsignedCharArray* bytes = reader->GetBinaryHeader();
      for (vtkIdType i = 0; i < bytes->GetNumberOfValues(); ++i) header += static_cast<char>(bytes->GetValue(i));
    }
    declared = declaredFrame(header);
  } else if (extension == ".vtk") {
    requireLegacyVtkSectionsComplete(path);
    vtkNew<vtkPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    require(reader->IsFilePolyData(), "cannot read surface model '" + path +
                                          "': not a legacy VTK poly data file (a mesh saved as vtkPolyData)");
    model.polyDataLps = runReader(reader.Get(), path);
    declared = declaredFrame(text(reader->GetHeader()));
  } else if (extension == ".vtp") {
    requireVtkXmlArrayTypesKnown(path);
    vtkNew<vtkXMLPolyDataReader> reader;
    model.polyDataLps = runReader(reader.Get(), path);
    if (auto* space = vtkStringArray::SafeDownCast(
            model.polyDataLps->GetFieldData()->GetAbstractArray(kSpaceArrayName));
        space && space->GetNumberOfValues() > 0) {
      declared = declaredFrame("SPACE=" + space->GetValue(0));
      model.polyDataLps->GetFieldData()->RemoveArray(kSpaceArrayName);
    }
  } else if (extension == ".ply") {
    // VTK's reader fills a truncated file's missing vertices with zeros, and crashes on faces beyond the vertices or
    // an ASCII row split over lines: check the whole file first (readPlyWholeFile checks all three).
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
    requireObjReferencesDefined(path);
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
