#include "IO/MeshPly.h"

#include "IO/AtomicFile.h"
#include "IO/PlyFormat.h"

#include "Core/Error.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace tissuemosaic {

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
  const std::string context = "mesh PLY '" + path + "': ";
  const auto fail = [&](const std::string& why) { throw Error(context + why); };
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const PlyHeader header = parsePlyHeader(bytes, context);
  const PlyElement* vertex = header.find("vertex");
  const PlyElement* face = header.find("face");
  const std::size_t vertexCount = vertex ? vertex->count : 0, faceCount = face ? face->count : 0;
  int xyz[3] = {-1, -1, -1};
  if (vertex) {
    for (const PlyProperty& p : vertex->properties) {
      if (p.isList) fail("vertex list properties are not supported");
    }
    xyz[0] = vertex->findScalar({"x"});
    xyz[1] = vertex->findScalar({"y"});
    xyz[2] = vertex->findScalar({"z"});
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) fail("vertices lack x, y or z");
  // Every vertex and face takes at least one byte: a corrupt count must not allocate more than the file holds.
  const std::size_t dataBytes = bytes.size() - header.bodyStart;
  if (vertexCount > dataBytes || faceCount > dataBytes) {
    fail("the header declares " + std::to_string(vertexCount) + " vertices and " + std::to_string(faceCount) +
         " faces but only " + std::to_string(dataBytes) + " bytes follow it");
  }
  TriangleMesh mesh;
  mesh.verticesMm.reserve(vertexCount);
  mesh.triangles.reserve(faceCount);
  PlyBodyReader reader(bytes, header, context);
  std::vector<double> values;
  // Elements in the header's order; those other than vertices and faces (and the faces' other properties) are read
  // past.
  for (const PlyElement& element : header.elements) {
    const bool isVertex = &element == vertex, isFace = &element == face;
    // Per property: a face's vertex index list (named once per element, not per value).
    std::vector<bool> indexList(element.properties.size(), false);
    for (std::size_t p = 0; isFace && p < element.properties.size(); ++p) {
      const std::string& name = element.properties[p].name;
      indexList[p] = name == "vertex_indices" || name == "vertex_index";
    }
    const auto isIndices = [&indexList](std::size_t p) { return indexList[p]; };
    for (std::size_t row = 0; row < element.count; ++row) {
      cv::Vec3i triangle;
      reader.readRow(
          element, row, values,
          [&](std::size_t p, std::size_t length) {
            if (isIndices(p) && length != 3) fail("face " + std::to_string(row) + " is not a triangle");
          },
          [&](std::size_t p, std::size_t k, double value) {
            if (!isIndices(p)) return;
            if (!(value >= 0 && value < static_cast<double>(vertexCount))) fail("a face refers to a missing vertex");
            triangle[static_cast<int>(k)] = static_cast<int>(value);
            if (k == 2) mesh.triangles.push_back(triangle);
          });
      if (isVertex) {
        mesh.verticesMm.emplace_back(static_cast<float>(values[xyz[0]]), static_cast<float>(values[xyz[1]]),
                                     static_cast<float>(values[xyz[2]]));
      }
    }
  }
  return mesh;
}

}  // namespace tissuemosaic
