#include "PointCloudPly.h"

#include "AtomicFile.h"
#include "ByteOrder.h"
#include "PlyFormat.h"
#include "Core/Error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace tissuemosaic {
namespace {

template <class T>
void appendLittleEndian(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (!hostIsLittleEndian()) std::reverse(raw, raw + sizeof(T));
  bytes.append(raw, sizeof(T));
}

std::uint8_t toColorChannel(double value, PlyScalar type) {
  if (type == PlyScalar::Float32 || type == PlyScalar::Float64) value *= 255.0;
  if (!(value > 0)) return 0;  // NaN too
  return static_cast<std::uint8_t>(std::min(255.0, std::round(value)));
}

}  // namespace

void writePly(const std::string& path, const ColoredPointCloud& cloud, const std::string& comment) {
  const std::string context = "cannot write PLY '" + path + "': ";
  const std::size_t n = cloud.pointsMm.size();
  const bool hasColors = !cloud.colorsRgb.empty();
  const bool hasNormals = !cloud.normals.empty();
  require(!hasColors || cloud.colorsRgb.size() == n, context + "the cloud has " + std::to_string(n) + " points but " +
                                                         std::to_string(cloud.colorsRgb.size()) + " colours");
  require(!hasNormals || cloud.normals.size() == n, context + "the cloud has " + std::to_string(n) + " points but " +
                                                        std::to_string(cloud.normals.size()) + " normals");
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment written by TissueMosaic\n";
  std::istringstream commentLines(comment);
  for (std::string line; std::getline(commentLines, line);) header << "comment " << line << "\n";
  header << "element vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (hasColors) header << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (hasNormals) header << "property float nx\nproperty float ny\nproperty float nz\n";
  header << "end_header\n";

  std::string body;
  body.reserve(n * (12 + (hasColors ? 3 : 0) + (hasNormals ? 12 : 0)));
  for (std::size_t i = 0; i < n; ++i) {
    const cv::Point3f& p = cloud.pointsMm[i];
    appendLittleEndian(body, p.x);
    appendLittleEndian(body, p.y);
    appendLittleEndian(body, p.z);
    if (hasColors) body.append(reinterpret_cast<const char*>(cloud.colorsRgb[i].val), 3);
    if (hasNormals) {
      appendLittleEndian(body, cloud.normals[i].x);
      appendLittleEndian(body, cloud.normals[i].y);
      appendLittleEndian(body, cloud.normals[i].z);
    }
  }
  const std::string headerText = header.str();
  writeStreamAtomically(path, "PLY", [&](std::ostream& file) {
    file.write(headerText.data(), static_cast<std::streamsize>(headerText.size()));
    file.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

namespace {

ColoredPointCloud readPlyFile(const std::string& path, bool wholeFile) {
  const std::string context = "cannot read PLY '" + path + "': ";
  std::ifstream file(path, std::ios::binary);
  require(file.good(), context + "file does not exist or is not readable");
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const PlyHeader header = parsePlyHeader(bytes, context);
  const PlyElement* vertexElement = header.find("vertex");
  require(vertexElement != nullptr, context + "there is no 'vertex' element");
  const PlyElement& vertex = *vertexElement;
  const int ix = vertex.findScalar({"x"}), iy = vertex.findScalar({"y"}), iz = vertex.findScalar({"z"});
  require(ix >= 0 && iy >= 0 && iz >= 0, context + "the vertices lack an x, y or z property");
  const int ir = vertex.findScalar({"red", "diffuse_red", "r"});
  const int ig = vertex.findScalar({"green", "diffuse_green", "g"});
  const int ib = vertex.findScalar({"blue", "diffuse_blue", "b"});
  const int inx = vertex.findScalar({"nx"}), iny = vertex.findScalar({"ny"}), inz = vertex.findScalar({"nz"});
  const bool hasColors = ir >= 0 && ig >= 0 && ib >= 0;
  const bool hasNormals = inx >= 0 && iny >= 0 && inz >= 0;

  // Body: elements in header order; everything after the vertices (faces ...) is left unread unless wholeFile, which
  // also checks the rows as VTK's line-based ASCII reader takes them (one line each).
  PlyBodyReader reader(bytes, header, context, wholeFile);
  ColoredPointCloud cloud;
  std::vector<double> values;
  for (const PlyElement& element : header.elements) {
    const bool isVertex = &element == &vertex;
    if (isVertex) {
      // A corrupt count must not allocate more than the file could hold (every vertex takes at least a byte).
      const std::size_t expected = std::min(element.count, bytes.size());
      cloud.pointsMm.reserve(expected);
      if (hasColors) cloud.colorsRgb.reserve(expected);
      if (hasNormals) cloud.normals.reserve(expected);
    }
    // Faces as VTK's PLY reader takes them: a list 'vertex_indices' of existing vertices (VTK 9.1 reads out of
    // bounds otherwise; found by fuzz_surface_ply).
    const bool isFace = wholeFile && element.name == "face" && element.count > 0;
    const int faceIndices = isFace ? element.findList({"vertex_indices", "vertex_index"}) : -1;
    if (isFace && faceIndices < 0) throw Error(context + "the faces have no list property 'vertex_indices'");
    for (std::size_t i = 0; i < element.count; ++i) {
      reader.readRow(element, i, values, [](std::size_t, std::size_t) {},
                     [&](std::size_t p, std::size_t, double value) {
                       if (isFace && static_cast<int>(p) == faceIndices &&
                           !(value >= 0 && value < static_cast<double>(vertex.count) && value == std::floor(value))) {
                         throw Error(context + "face " + std::to_string(i) + " refers to vertex " +
                                     cv::format("%.17g", value) + " of " + std::to_string(vertex.count));
                       }
                     });
      if (!isVertex) continue;
      cloud.pointsMm.emplace_back(static_cast<float>(values[ix]), static_cast<float>(values[iy]),
                                  static_cast<float>(values[iz]));
      if (hasColors)
        cloud.colorsRgb.emplace_back(toColorChannel(values[ir], vertex.properties[ir].valueType),
                                     toColorChannel(values[ig], vertex.properties[ig].valueType),
                                     toColorChannel(values[ib], vertex.properties[ib].valueType));
      if (hasNormals)
        cloud.normals.emplace_back(static_cast<float>(values[inx]), static_cast<float>(values[iny]),
                                   static_cast<float>(values[inz]));
    }
    if (isVertex && !wholeFile) break;
  }
  return cloud;
}

}  // namespace

ColoredPointCloud readPly(const std::string& path) { return readPlyFile(path, false); }

ColoredPointCloud readPlyWholeFile(const std::string& path) { return readPlyFile(path, true); }

}  // namespace tissuemosaic
