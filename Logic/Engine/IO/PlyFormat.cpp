#include "PlyFormat.h"

#include "ByteOrder.h"
#include "Core/Error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace tissuemosaic {
namespace {

bool parseScalar(const std::string& name, PlyScalar& type) {
  static const std::pair<const char*, PlyScalar> names[] = {
      {"char", PlyScalar::Int8},     {"int8", PlyScalar::Int8},       {"uchar", PlyScalar::UInt8},
      {"uint8", PlyScalar::UInt8},   {"short", PlyScalar::Int16},     {"int16", PlyScalar::Int16},
      {"ushort", PlyScalar::UInt16}, {"uint16", PlyScalar::UInt16},   {"int", PlyScalar::Int32},
      {"int32", PlyScalar::Int32},   {"uint", PlyScalar::UInt32},     {"uint32", PlyScalar::UInt32},
      {"float", PlyScalar::Float32}, {"float32", PlyScalar::Float32}, {"double", PlyScalar::Float64},
      {"float64", PlyScalar::Float64}};
  for (const auto& entry : names) {
    if (name == entry.first) {
      type = entry.second;
      return true;
    }
  }
  return false;
}

std::size_t scalarBytes(PlyScalar type) {
  switch (type) {
    case PlyScalar::Int8: case PlyScalar::UInt8: return 1;
    case PlyScalar::Int16: case PlyScalar::UInt16: return 2;
    case PlyScalar::Int32: case PlyScalar::UInt32: case PlyScalar::Float32: return 4;
    case PlyScalar::Float64: return 8;
  }
  return 0;
}

template <class T>
double decode(const char* raw) {
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return static_cast<double>(value);
}

int findProperty(const PlyElement& element, std::initializer_list<const char*> names, bool list) {
  for (const char* name : names) {
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
      if (element.properties[i].isList == list && element.properties[i].name == name) return static_cast<int>(i);
    }
  }
  return -1;
}

}  // namespace

int PlyElement::findScalar(std::initializer_list<const char*> names) const { return findProperty(*this, names, false); }
int PlyElement::findList(std::initializer_list<const char*> names) const { return findProperty(*this, names, true); }

const PlyElement* PlyHeader::find(const std::string& name) const {
  const auto it = std::find_if(elements.begin(), elements.end(), [&](const PlyElement& e) { return e.name == name; });
  return it == elements.end() ? nullptr : &*it;
}

PlyHeader parsePlyHeader(const std::string& bytes, const std::string& context) {
  std::size_t position = 0;
  const auto nextLine = [&]() {
    require(position < bytes.size(), context + "the header has no 'end_header' line");
    std::size_t end = bytes.find('\n', position);
    if (end == std::string::npos) end = bytes.size();
    std::string line = bytes.substr(position, end - position);
    position = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  };
  require(nextLine() == "ply", context + "not a PLY file (it must start with 'ply')");
  PlyHeader header;
  bool sawFormat = false;
  int lineNumber = 1;
  for (std::string line = nextLine(); line != "end_header"; line = nextLine()) {
    ++lineNumber;
    // Header lines are text, and each keyword's line holds exactly its words: VTK 9.1's PLY reader freed memory twice
    // or read out of bounds on element lines such as "element ver4ex 4ply" or names with control bytes
    // (fuzz_surface_ply), which a looser reading let through.
    const auto control = std::find_if(line.begin(), line.end(), [](char c) {
      const auto byte = static_cast<unsigned char>(c);
      return (byte < 0x20 && c != '\t') || byte == 0x7f;
    });
    require(control == line.end(), context + "header line " + std::to_string(lineNumber) + " holds a control byte");
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    std::vector<std::string> rest;
    if (keyword != "comment" && keyword != "obj_info") {
      for (std::string word; words >> word;) rest.push_back(word);
      words.clear();
      words.str(line);
      words >> keyword;
    }
    const auto requireWords = [&](std::size_t count) {
      require(rest.size() == count, context + "malformed line '" + line + "'");
    };
    if (keyword == "format") {
      requireWords(2);
      std::string name;
      words >> name;
      if (name == "ascii") header.format = PlyFormat::Ascii;
      else if (name == "binary_little_endian") header.format = PlyFormat::BinaryLittle;
      else if (name == "binary_big_endian") header.format = PlyFormat::BinaryBig;
      else throw Error(context + "unknown format '" + name + "'");
      sawFormat = true;
    } else if (keyword == "element") {
      requireWords(2);
      PlyElement element;
      long long count = -1;
      words >> element.name >> count;
      require(!words.fail() && count >= 0 && rest[1].find_first_not_of("0123456789") == std::string::npos,
              context + "malformed line '" + line + "'");
      require(header.find(element.name) == nullptr, context + "element '" + element.name + "' is declared twice");
      element.count = static_cast<std::size_t>(count);
      header.elements.push_back(element);
    } else if (keyword == "property") {
      require(!header.elements.empty(), context + "a property comes before any element");
      PlyProperty property;
      std::string type;
      words >> type;
      requireWords(type == "list" ? 4 : 2);
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
      header.elements.back().properties.push_back(property);
    } else {
      require(keyword == "comment" || keyword == "obj_info" || keyword.empty(),
              context + "unexpected header line '" + line + "'");
    }
  }
  require(sawFormat, context + "the header has no 'format' line");
  header.bodyStart = std::min(position, bytes.size());
  return header;
}

PlyBodyReader::PlyBodyReader(const std::string& bytes, const PlyHeader& header, const std::string& context,
                             bool rowsOnePerLine)
    : bytes_(bytes), position_(header.bodyStart), format_(header.format), context_(context),
      rowsOnePerLine_(rowsOnePerLine && header.format == PlyFormat::Ascii) {}

void PlyBodyReader::beginRow(const std::string& element, std::size_t row) {
  rowElement_ = element;
  row_ = row;
  inRow_ = true;
}

void PlyBodyReader::endRow() {
  inRow_ = false;
  if (!rowsOnePerLine_) return;
  // The rest of the line holds no value, and the line ends here (or the file does).
  while (position_ < bytes_.size() && (bytes_[position_] == ' ' || bytes_[position_] == '\t' || bytes_[position_] == '\r'))
    ++position_;
  if (position_ == bytes_.size()) return;
  if (bytes_[position_] != '\n') failRow();
  ++position_;
}

void PlyBodyReader::failRow() const {
  throw Error(context_ + "row " + std::to_string(row_) + " of element '" + rowElement_ +
              "' is not one line of its declared values (an ASCII PLY holds one row per line)");
}

double PlyBodyReader::read(PlyScalar type) {
  if (format_ == PlyFormat::Ascii) return readAscii();
  const std::size_t size = scalarBytes(type);
  if (position_ + size > bytes_.size()) throw Error(context_ + "the file is truncated");  // no string per value
  char raw[8];
  std::memcpy(raw, bytes_.data() + position_, size);
  position_ += size;
  if ((format_ == PlyFormat::BinaryLittle) != hostIsLittleEndian()) std::reverse(raw, raw + size);
  switch (type) {
    case PlyScalar::Int8: return decode<std::int8_t>(raw);
    case PlyScalar::UInt8: return decode<std::uint8_t>(raw);
    case PlyScalar::Int16: return decode<std::int16_t>(raw);
    case PlyScalar::UInt16: return decode<std::uint16_t>(raw);
    case PlyScalar::Int32: return decode<std::int32_t>(raw);
    case PlyScalar::UInt32: return decode<std::uint32_t>(raw);
    case PlyScalar::Float32: return decode<float>(raw);
    case PlyScalar::Float64: return decode<double>(raw);
  }
  return 0;
}

std::size_t PlyBodyReader::readListLength(PlyScalar countType) {
  const double count = read(countType);
  // Every value takes at least a byte: a longer list cannot be in the file (and would not fit a size_t).
  if (!(count >= 0 && count == std::floor(count) && count <= static_cast<double>(bytes_.size())))
    throw Error(context_ + "a list has an invalid length");
  return static_cast<std::size_t>(count);
}

double PlyBodyReader::readAscii() {
  bool crossedLine = false;
  while (position_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[position_]))) {
    crossedLine |= bytes_[position_] == '\n';
    ++position_;
  }
  if (position_ >= bytes_.size()) throw Error(context_ + "the file is truncated");
  if (rowsOnePerLine_ && inRow_ && crossedLine) failRow();  // endRow took the row's own line end
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

}  // namespace tissuemosaic
