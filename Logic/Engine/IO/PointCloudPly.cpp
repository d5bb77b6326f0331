#include "PointCloudPly.h"

#include "AtomicFile.h"
#include "ByteOrder.h"
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

// ---- reading -------------------------------------------------------------------------------------------------

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parseScalar(const std::string& name, Scalar& type) {
  static const std::pair<const char*, Scalar> names[] = {
      {"char", Scalar::Int8},     {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},   {"uint8", Scalar::UInt8},
      {"short", Scalar::Int16},   {"int16", Scalar::Int16},     {"ushort", Scalar::UInt16}, {"uint16", Scalar::UInt16},
      {"int", Scalar::Int32},     {"int32", Scalar::Int32},     {"uint", Scalar::UInt32},   {"uint32", Scalar::UInt32},
      {"float", Scalar::Float32}, {"float32", Scalar::Float32}, {"double", Scalar::Float64}, {"float64", Scalar::Float64}};
  for (const auto& entry : names) {
    if (name == entry.first) {
      type = entry.second;
      return true;
    }
  }
  return false;
}

std::size_t scalarBytes(Scalar type) {
  switch (type) {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  bool isList = false;
  Scalar countType = Scalar::UInt8;
  Scalar valueType = Scalar::Float32;
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

/// Reads scalars one after the other from the body of the file, ascii or binary.
class BodyReader {
public:
  BodyReader(const std::string& bytes, std::size_t start, Format format, const std::string& context)
      : bytes_(bytes), position_(start), format_(format), context_(context) {}

  double read(Scalar type) {
    if (format_ == Format::Ascii) return readAscii();
    const std::size_t size = scalarBytes(type);
    if (position_ + size > bytes_.size()) throw Error(context_ + "the file is truncated");  // no string per value
    char raw[8];
    std::memcpy(raw, bytes_.data() + position_, size);
    position_ += size;
    if ((format_ == Format::BinaryLittle) != hostIsLittleEndian()) std::reverse(raw, raw + size);
    switch (type) {
      case Scalar::Int8: return decode<std::int8_t>(raw);
      case Scalar::UInt8: return decode<std::uint8_t>(raw);
      case Scalar::Int16: return decode<std::int16_t>(raw);
      case Scalar::UInt16: return decode<std::uint16_t>(raw);
      case Scalar::Int32: return decode<std::int32_t>(raw);
      case Scalar::UInt32: return decode<std::uint32_t>(raw);
      case Scalar::Float32: return decode<float>(raw);
      case Scalar::Float64: return decode<double>(raw);
    }
    return 0;
  }

private:
  template <class T>
  static double decode(const char* raw) {
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return static_cast<double>(value);
  }

  double readAscii() {
    while (position_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[position_]))) ++position_;
    if (position_ >= bytes_.size()) throw Error(context_ + "the file is truncated");
    std::size_t end = position_;
    while (end < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[end]))) ++end;
    // strtod stops at the whitespace (or the string's terminating zero) that ends the token.
    char* parsedEnd = nullptr;
    const double value = std::strtod(bytes_.c_str() + position_, &parsedEnd);
    if (parsedEnd != bytes_.c_str() + end)
      throw Error(context_ + "'" + bytes_.substr(position_, end - position_) + "' is not a number");
    position_ = end;
    return value;
  }

  const std::string& bytes_;
  std::size_t position_;
  Format format_;
  const std::string& context_;
};

int findProperty(const Element& element, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (std::size_t i = 0; i < element.properties.size(); ++i)
      if (!element.properties[i].isList && element.properties[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::uint8_t toColorChannel(double value, Scalar type) {
  if (type == Scalar::Float32 || type == Scalar::Float64) value *= 255.0;
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

  // Header: lines up to "end_header".
  std::size_t position = 0;
  auto nextLine = [&]() {
    require(position < bytes.size(), context + "the header has no 'end_header' line");
    std::size_t end = bytes.find('\n', position);
    if (end == std::string::npos) end = bytes.size();
    std::string line = bytes.substr(position, end - position);
    position = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  };
  require(nextLine() == "ply", context + "not a PLY file (it must start with 'ply')");
  Format format = Format::Ascii;
  bool sawFormat = false;
  std::vector<Element> elements;
  for (std::string line = nextLine(); line != "end_header"; line = nextLine()) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string name;
      words >> name;
      if (name == "ascii") format = Format::Ascii;
      else if (name == "binary_little_endian") format = Format::BinaryLittle;
      else if (name == "binary_big_endian") format = Format::BinaryBig;
      else throw Error(context + "unknown format '" + name + "'");
      sawFormat = true;
    } else if (keyword == "element") {
      Element element;
      long long count = -1;
      words >> element.name >> count;
      require(!words.fail() && count >= 0, context + "malformed line '" + line + "'");
      element.count = static_cast<std::size_t>(count);
      elements.push_back(element);
    } else if (keyword == "property") {
      require(!elements.empty(), context + "a property comes before any element");
      Property property;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string countType, valueType;
        words >> countType >> valueType >> property.name;
        property.isList = true;
        require(parseScalar(countType, property.countType) && parseScalar(valueType, property.valueType),
                context + "unknown type in '" + line + "'");
      } else {
        words >> property.name;
        require(parseScalar(type, property.valueType), context + "unknown type in '" + line + "'");
      }
      require(!words.fail(), context + "malformed line '" + line + "'");
      elements.back().properties.push_back(property);
    } else {
      require(keyword == "comment" || keyword == "obj_info" || keyword.empty(),
              context + "unexpected header line '" + line + "'");
    }
  }
  require(sawFormat, context + "the header has no 'format' line");
  const auto vertexElement = std::find_if(elements.begin(), elements.end(),
                                          [](const Element& e) { return e.name == "vertex"; });
  require(vertexElement != elements.end(), context + "there is no 'vertex' element");
  const Element& vertex = *vertexElement;
  const int ix = findProperty(vertex, {"x"}), iy = findProperty(vertex, {"y"}), iz = findProperty(vertex, {"z"});
  require(ix >= 0 && iy >= 0 && iz >= 0, context + "the vertices lack an x, y or z property");
  const int ir = findProperty(vertex, {"red", "diffuse_red", "r"});
  const int ig = findProperty(vertex, {"green", "diffuse_green", "g"});
  const int ib = findProperty(vertex, {"blue", "diffuse_blue", "b"});
  const int inx = findProperty(vertex, {"nx"}), iny = findProperty(vertex, {"ny"}), inz = findProperty(vertex, {"nz"});
  const bool hasColors = ir >= 0 && ig >= 0 && ib >= 0;
  const bool hasNormals = inx >= 0 && iny >= 0 && inz >= 0;

  // Body: elements in header order; everything after the vertices (faces ...) is left unread unless wholeFile.
  BodyReader reader(bytes, position, format, context);
  ColoredPointCloud cloud;
  std::vector<double> values;
  for (const Element& element : elements) {
    const bool isVertex = &element == &vertex;
    if (isVertex) {
      // A corrupt count must not allocate more than the file could hold (every vertex takes at least a byte).
      const std::size_t expected = std::min(element.count, bytes.size());
      cloud.pointsMm.reserve(expected);
      if (hasColors) cloud.colorsRgb.reserve(expected);
      if (hasNormals) cloud.normals.reserve(expected);
    }
    values.assign(element.properties.size(), 0.0);
    // Faces as VTK's PLY reader takes them: a list 'vertex_indices' of existing vertices (VTK 9.1 reads out of
    // bounds otherwise; found by fuzz_surface_ply).
    const bool isFace = wholeFile && element.name == "face" && element.count > 0;
    int faceIndices = -1;
    for (std::size_t p = 0; isFace && p < element.properties.size(); ++p) {
      if (element.properties[p].isList && (element.properties[p].name == "vertex_indices" ||
                                           element.properties[p].name == "vertex_index")) {
        faceIndices = static_cast<int>(p);
      }
    }
    if (isFace && faceIndices < 0) throw Error(context + "the faces have no list property 'vertex_indices'");
    for (std::size_t i = 0; i < element.count; ++i) {
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const Property& property = element.properties[p];
        if (!property.isList) {
          values[p] = reader.read(property.valueType);
          continue;
        }
        const double count = reader.read(property.countType);
        if (!(count >= 0 && count == std::floor(count))) throw Error(context + "a list has an invalid length");
        for (long long k = 0; k < static_cast<long long>(count); ++k) {
          const double value = reader.read(property.valueType);
          if (isFace && static_cast<int>(p) == faceIndices &&
              !(value >= 0 && value < static_cast<double>(vertex.count) && value == std::floor(value))) {
            throw Error(context + "face " + std::to_string(i) + " refers to vertex " + cv::format("%.17g", value) + " of " +
                        std::to_string(vertex.count));
          }
        }
      }
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
