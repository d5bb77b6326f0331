#pragma once
/// @file PlyFormat.h
/// @brief The one PLY reading layer under PointCloudPly.h and MeshPly.h: the header (format, elements, their
/// properties) and a reader of the body's values, ascii or binary of either byte order. Every count and type is
/// checked here, so that the readers above only map properties to their fields.
#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace tissuemosaic {

enum class PlyScalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyScalar countType = PlyScalar::UInt8;  ///< lists only
  PlyScalar valueType = PlyScalar::Float32;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  /// Index of the first scalar (not list) property with one of these names, in the order given; -1: none.
  int findScalar(std::initializer_list<const char*> names) const;
  /// Index of the first list property with one of these names; -1: none.
  int findList(std::initializer_list<const char*> names) const;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t bodyStart = 0;  ///< byte offset of the first value after "end_header\n"
  const PlyElement* find(const std::string& name) const;  ///< null: no such element
};

/// Parses the header of a whole PLY file held in bytes. Throws Error, its text starting with context, for a file
/// that does not start with "ply", an unknown format or type, a malformed element or property line, a property
/// before any element, an unknown keyword, or no "end_header" or "format" line.
PlyHeader parsePlyHeader(const std::string& bytes, const std::string& context);

/// Reads the body's values one after the other, in the header's element and property order.
class PlyBodyReader {
public:
  /// rowsOnePerLine (ascii only): each element row must be one line holding exactly its values, as line-based
  /// readers need (VTK 9.1's PLY reader called strtol(NULL) on a row split over lines); the rows are then read
  /// between beginRow and endRow.
  PlyBodyReader(const std::string& bytes, const PlyHeader& header, const std::string& context,
                bool rowsOnePerLine = false);

  double read(PlyScalar type);
  /// A list property's length: a whole number, not negative (else Error "a list has an invalid length").
  std::size_t readListLength(PlyScalar countType);
  void beginRow(const std::string& element, std::size_t row);
  void endRow();
  /// Reads row `row` of `element` (between beginRow and endRow): each scalar property's value into
  /// scalars[property index]; each list property's length handed to listLength(property index, length), then its
  /// values to listValue(property index, position in the list, value). The one row loop of every PLY reader.
  template <class ListLength, class ListValue>
  void readRow(const PlyElement& element, std::size_t row, std::vector<double>& scalars, const ListLength& listLength,
               const ListValue& listValue) {
    beginRow(element.name, row);
    scalars.resize(element.properties.size());
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      if (!property.isList) {
        scalars[p] = read(property.valueType);
        continue;
      }
      const std::size_t length = readListLength(property.countType);
      listLength(p, length);
      for (std::size_t k = 0; k < length; ++k) listValue(p, k, read(property.valueType));
    }
    endRow();
  }
  std::size_t bytesLeft() const { return bytes_.size() - position_; }

private:
  double readAscii();
  [[noreturn]] void failRow() const;

  const std::string& bytes_;
  std::size_t position_;
  PlyFormat format_;
  const std::string& context_;
  bool rowsOnePerLine_;
  bool inRow_ = false;
  std::string rowElement_;
  std::size_t row_ = 0;
};

}  // namespace tissuemosaic
