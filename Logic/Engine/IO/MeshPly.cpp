#include "IO/MeshPly.h"

#include "IO/AtomicFile.h"

#include "Core/Error.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

namespace tissuemosaic {

namespace {

int typeSize(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

/// A little-endian binary value of a PLY scalar type, as double.
double readBinary(std::istream& in, const std::string& type) {
  unsigned char bytes[8] = {};
  in.read(reinterpret_cast<char*>(bytes), typeSize(type));
  if (type == "float" || type == "float32") {
    float v;
    std::memcpy(&v, bytes, 4);
    return v;
  }
  if (type == "double" || type == "float64") {
    double v;
    std::memcpy(&v, bytes, 8);
    return v;
  }
  if (type == "uchar" || type == "uint8") return bytes[0];
  if (type == "char" || type == "int8") return static_cast<int8_t>(bytes[0]);
  if (type == "ushort" || type == "uint16") return static_cast<uint16_t>(bytes[0] | bytes[1] << 8);
  if (type == "short" || type == "int16") return static_cast<int16_t>(bytes[0] | bytes[1] << 8);
  uint32_t u = 0;
  std::memcpy(&u, bytes, 4);
  if (type == "uint" || type == "uint32") return u;
  return static_cast<int32_t>(u);
}

struct Property {
  std::string name, type, countType;  // countType non-empty: a list
};

}  // namespace

void writeMeshPly(const std::string& path, const TriangleMesh& mesh, const std::string& comment) {
  const auto vertexCount = static_cast<int64_t>(mesh.verticesMm.size());
  for (const cv::Vec3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= vertexCount) {
        throw Error("mesh PLY '" + path + "': a triangle refers to vertex " + std::to_string(t[k]) + " of " +
                    std::to_string(vertexCount));
      }
    }
  }
  writeStreamAtomically(path, "mesh", [&](std::ostream& file) {
    file << "ply\nformat binary_little_endian 1.0\n";
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);) file << "comment " << line << "\n";
    file << "element vertex " << vertexCount << "\nproperty float x\nproperty float y\nproperty float z\n"
         << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    static_assert(sizeof(cv::Point3f) == 12, "packed float triplets");
    file.write(reinterpret_cast<const char*>(mesh.verticesMm.data()), static_cast<std::streamsize>(12 * vertexCount));
    std::vector<char> faces(13 * mesh.triangles.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      faces[13 * i] = 3;
      std::memcpy(&faces[13 * i + 1], &mesh.triangles[i][0], 12);  // x86/ARM hosts are little-endian
    }
    file.write(faces.data(), static_cast<std::streamsize>(faces.size()));
  });
}

TriangleMesh readMeshPly(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  require(file.good(), "cannot read mesh '" + path + "': file does not exist or is not readable");
  const auto fail = [&](const std::string& why) { throw Error("mesh PLY '" + path + "': " + why); };
  std::string line;
  std::getline(file, line);
  if (line != "ply" && line != "ply\r") fail("not a PLY file");
  bool ascii = false;
  std::string element;
  int64_t vertexCount = 0, faceCount = 0;
  std::vector<Property> vertexProperties, faceProperties;
  while (std::getline(file, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      std::string format;
      words >> format;
      if (format == "ascii") ascii = true;
      else if (format != "binary_little_endian") fail("format '" + format + "' is not supported");
    } else if (keyword == "element") {
      int64_t count = 0;
      words >> element >> count;
      if (words.fail() || count < 0) fail("malformed line '" + line + "'");
      if (element == "vertex") vertexCount = count;
      if (element == "face") faceCount = count;
      if (element != "vertex" && element != "face" && count > 0) fail("element '" + element + "' is not supported");
    } else if (keyword == "property") {
      Property p;
      words >> p.type;
      if (p.type == "list") words >> p.countType >> p.type;
      words >> p.name;
      if (typeSize(p.type) == 0 || (!p.countType.empty() && typeSize(p.countType) == 0))
        fail("property '" + p.name + "' has an unknown type");
      (element == "vertex" ? vertexProperties : faceProperties).push_back(p);
    }
  }
  if (!file.good()) fail("the header has no end_header");
  int xyz[3] = {-1, -1, -1};
  for (int i = 0; i < static_cast<int>(vertexProperties.size()); ++i) {
    const Property& p = vertexProperties[i];
    if (!p.countType.empty()) fail("vertex list properties are not supported");
    for (int k = 0; k < 3; ++k) {
      if (p.name == std::string(1, "xyz"[k])) xyz[k] = i;
    }
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) fail("vertices lack x, y or z");
  // Every vertex and face takes at least one byte: a corrupt count must not allocate more than the file holds.
  const std::streampos dataStart = file.tellg();
  file.seekg(0, std::ios::end);
  const int64_t dataBytes = static_cast<int64_t>(file.tellg() - dataStart);
  file.seekg(dataStart);
  if (vertexCount > dataBytes || faceCount > dataBytes) {
    fail("the header declares " + std::to_string(vertexCount) + " vertices and " + std::to_string(faceCount) +
         " faces but only " + std::to_string(dataBytes) + " bytes follow it");
  }
  TriangleMesh mesh;
  mesh.verticesMm.resize(static_cast<std::size_t>(vertexCount));
  std::vector<double> values(vertexProperties.size());
  for (int64_t v = 0; v < vertexCount; ++v) {
    for (std::size_t i = 0; i < vertexProperties.size(); ++i) {
      if (ascii) file >> values[i];
      else values[i] = readBinary(file, vertexProperties[i].type);
    }
    if (!file) fail("truncated vertex data");
    mesh.verticesMm[v] = cv::Point3f(static_cast<float>(values[xyz[0]]), static_cast<float>(values[xyz[1]]),
                                     static_cast<float>(values[xyz[2]]));
  }
  mesh.triangles.reserve(static_cast<std::size_t>(faceCount));
  for (int64_t f = 0; f < faceCount; ++f) {
    for (const Property& p : faceProperties) {
      if (p.countType.empty()) {  // a scalar face property: skip
        double skip;
        if (ascii) file >> skip;
        else readBinary(file, p.type);
        continue;
      }
      double count = 0;
      if (ascii) file >> count;
      else count = readBinary(file, p.countType);
      if (!file) fail("truncated face data");
      if (count != 3) fail("face " + std::to_string(f) + " is not a triangle");
      cv::Vec3i t;
      for (int k = 0; k < 3; ++k) {
        double index = 0;
        if (ascii) file >> index;
        else index = readBinary(file, p.type);
        if (!(index >= 0 && index < static_cast<double>(vertexCount))) fail("a face refers to a missing vertex");
        t[k] = static_cast<int>(index);
      }
      mesh.triangles.push_back(t);
    }
    if (!file) fail("truncated face data");
  }
  return mesh;
}

}  // namespace tissuemosaic
