#include "IO/Calibration/CalibrationDocument.h"

#include "Core/Error.h"
#include "Core/ParameterFileKeys.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <iterator>

namespace tissuemosaic {
namespace {

YAML::Node numberNode(double value) {
  // YAML's spellings, which yaml-cpp reads back; validation then names the non-finite value.
  if (std::isnan(value)) return YAML::Node(std::string(".nan"));
  if (std::isinf(value)) return YAML::Node(std::string(value > 0 ? ".inf" : "-.inf"));
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);  // round-trips every double
  return YAML::Node(std::string(text));
}

bool isOpenCvMatrix(const cv::FileNode& node) {
  return node.isMap() && !node["rows"].empty() && !node["cols"].empty() && !node["dt"].empty() &&
         !node["data"].empty();
}

/// FileStorage's tree as a YAML tree; OpenCV matrices (any dt) become lists of rows.
YAML::Node fromFileNode(const cv::FileNode& node) {
  if (isOpenCvMatrix(node)) {
    // OpenCV allocates rows x cols before it counts the data: a 1 KB file saying 65536 x 65536 would ask for 32 GB.
    const double declaredRows = node["rows"].real(), declaredCols = node["cols"].real();
    const std::size_t values = node["data"].isSeq() ? node["data"].size() : 1;
    require(declaredRows >= 1 && declaredCols >= 1 && declaredRows * declaredCols <= static_cast<double>(values),
            "key '" + node.name() + "' says " + cv::format("%.0fx%.0f", declaredRows, declaredCols) + " but holds " +
                std::to_string(values) + " values");
    cv::Mat m;
    node >> m;
    if (m.channels() != 1) return YAML::Node(std::string("<matrix with channels>"));
    m.convertTo(m, CV_64F);
    YAML::Node rows(YAML::NodeType::Sequence);
    for (int r = 0; r < m.rows; ++r) {
      YAML::Node row(YAML::NodeType::Sequence);
      for (int c = 0; c < m.cols; ++c) row.push_back(numberNode(m.at<double>(r, c)));
      rows.push_back(row);
    }
    return rows;
  }
  if (node.isMap()) {
    YAML::Node map(YAML::NodeType::Map);
    for (const cv::FileNode& child : node) map[child.name()] = fromFileNode(child);
    return map;
  }
  if (node.isSeq()) {
    YAML::Node sequence(YAML::NodeType::Sequence);
    for (const cv::FileNode& child : node) sequence.push_back(fromFileNode(child));
    return sequence;
  }
  if (node.isInt()) return YAML::Node(std::to_string(static_cast<int>(node)));
  if (node.isReal()) return numberNode(static_cast<double>(node));
  if (node.isString()) return YAML::Node(static_cast<std::string>(node));
  return YAML::Node(YAML::NodeType::Null);
}

/// OpenCV writes "%YAML:1.0", which YAML parsers refuse, and XML; everything else goes to yaml-cpp (YAML and JSON).
bool writtenByFileStorage(const std::string& text) {
  const std::size_t start = text.find_first_not_of(" \t\r\n\f\v");
  if (start == std::string::npos) return false;
  const auto startsWith = [&](const char* prefix) { return text.compare(start, std::strlen(prefix), prefix) == 0; };
  return startsWith("%YAML:") || startsWith("<?xml") || startsWith("<opencv_storage");
}

double toNumber(const YAML::Node& value, const std::string& key) {
  if (!value.IsScalar()) throw Error("key '" + key + "' is not a matrix of numbers");
  try {
    return value.as<double>();
  } catch (const YAML::Exception&) {
    throw Error("key '" + key + "' is not a matrix of numbers ('" + value.Scalar() + "' is not a number)");
  }
}

}  // namespace

namespace {

/// An INI file (StereoMIS's StereoCalibration.ini): its first line that is not blank or a comment is a [section].
bool looksLikeIni(const std::string& text) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == ';' || line[first] == '#') continue;
    const std::size_t last = line.find_last_not_of(" \t\r");
    return line[first] == '[' && line[last] == ']' && last > first + 1 && line.find('=') == std::string::npos;
  }
  return false;
}

/// "[section]" and "key = value" lines as a map of sections, each a map of text values (the layouts read them as
/// YAML scalars). Error naming the line for anything else.
YAML::Node parseIni(const std::string& text) {
  YAML::Node root(YAML::NodeType::Map);
  std::string section;
  std::istringstream lines(text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == ';' || line[first] == '#') continue;
    const std::size_t last = line.find_last_not_of(" \t\r");
    const std::string content = line.substr(first, last - first + 1);
    if (content.front() == '[' && content.back() == ']') {
      section = content.substr(1, content.size() - 2);
      root[section] = YAML::Node(YAML::NodeType::Map);
      continue;
    }
    const std::size_t equals = content.find('=');
    require(equals != std::string::npos && equals > 0 && !section.empty(),
            "INI line " + std::to_string(number) + " is neither [section] nor key = value within a section");
    auto trim = [](std::string value) {
      value.erase(0, value.find_first_not_of(" \t"));
      value.erase(value.find_last_not_of(" \t") + 1);
      return value;
    };
    root[section][trim(content.substr(0, equals))] = trim(content.substr(equals + 1));
  }
  return root;
}

}  // namespace

CalibrationDocument CalibrationDocument::load(const std::string& path) {
  std::error_code ec;
  require(std::filesystem::is_regular_file(path, ec), "file does not exist");
  CalibrationDocument document;
  document.path = path;
  // Read once: the format test, the guard and the parser all take this text.
  std::ifstream file(path, std::ios::binary);
  require(file.good(), "the file is not readable");
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (looksLikeIni(text)) {
    document.root = parseIni(text);
  } else if (writtenByFileStorage(text)) {
    // OpenCV 4.6's YAML parser never returns on some malformed texts (fuzz_calibration): yaml-cpp reads them first.
    parameters::requireYamlOpenCvCanRead(text, "", "not a valid OpenCV YAML/XML file");
    const cv::FileStorage storage = parameters::openOpenCvText(text, "", "not a valid OpenCV YAML/XML file");
    try {
      document.root = fromFileNode(storage.root());
    } catch (const cv::Exception& e) {
      throw Error("not a valid OpenCV YAML/XML file (" + e.err + ")");
    }
  } else {
    try {
      document.root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw Error("not a valid YAML or JSON file (" + std::string(e.what()) + ")");
    }
  }
  require(document.root.IsMap() && document.root.size() > 0,
          "holds no keys: a calibration file is a map of named values at its top level");
  return document;
}

void CalibrationDocument::merge(const CalibrationDocument& other) {
  for (const auto& entry : other.root) {
    const std::string key = keyText(entry.first);
    require(!root[key], "key '" + key + "' is in both '" + path + "' and '" + other.path + "'");
    root[key] = entry.second;
  }
}

std::string keyText(const YAML::Node& key) {
  if (key.IsScalar()) return key.Scalar();
  YAML::Emitter flow;
  flow << YAML::Flow << key;
  return flow.c_str();
}

bool hasKeys(const YAML::Node& node, std::initializer_list<const char*> keys) {
  if (!node.IsMap()) return false;
  for (const char* key : keys)
    if (!node[key]) return false;
  return true;
}

YAML::Node requireKey(const YAML::Node& node, const std::string& key, const std::string& where) {
  const YAML::Node value = node.IsMap() ? node[key] : YAML::Node();
  require(value && !value.IsNull(), where + "key '" + key + "' is missing");
  return value;
}

cv::Mat readMatrix(const YAML::Node& node, const std::string& key) {
  const std::string notMatrix = "key '" + key + "' is not a matrix of numbers";
  if (node.IsMap()) {  // ROS: {rows, cols, data}
    require(static_cast<bool>(node["data"]), notMatrix + " (a map without 'data')");
    cv::Mat m = readMatrix(node["data"], key);
    if (node["rows"] && node["cols"]) {
      // Checked as doubles first: a count beyond int's range was undefined behaviour in the cast (fuzz_calibration_pair).
      const auto dimension = [&](const char* part) {
        const double value = toNumber(node[part], key + "." + part);
        require(value >= 1 && value <= 1e6 && value == std::floor(value),
                "key '" + key + "." + part + "' must be a whole number from 1 to 1000000, not " + cv::format("%g", value));
        return static_cast<int>(value);
      };
      const int rows = dimension("rows");
      const int cols = dimension("cols");
      require(static_cast<std::size_t>(rows) * cols == m.total(),
              "key '" + key + "' says " + std::to_string(rows) + "x" + std::to_string(cols) + " but holds " +
                  std::to_string(m.total()) + " values");
      m = m.reshape(1, rows);
    }
    return m;
  }
  require(node.IsSequence() && node.size() > 0, notMatrix);
  const bool nested = node[0].IsSequence();
  const int rows = nested ? static_cast<int>(node.size()) : 1;
  const int cols = static_cast<int>(nested ? node[0].size() : node.size());
  require(cols > 0, notMatrix);
  cv::Mat m(rows, cols, CV_64F);
  for (int r = 0; r < rows; ++r) {
    const YAML::Node row = nested ? node[r] : node;
    require(row.IsSequence() && static_cast<int>(row.size()) == cols, notMatrix + " (rows of unequal length)");
    for (int c = 0; c < cols; ++c) m.at<double>(r, c) = toNumber(row[c], key);
  }
  return m;
}

cv::Mat readMatrix(const YAML::Node& parent, const std::string& key, int rows, int cols, const std::string& where) {
  cv::Mat m = readMatrix(requireKey(parent, key, where), key);
  require(m.total() == static_cast<std::size_t>(rows) * cols,
          where + "key '" + key + "' must hold " + std::to_string(rows) + "x" + std::to_string(cols) + " values, not " +
              std::to_string(m.rows) + "x" + std::to_string(m.cols));
  return m.reshape(1, rows).clone();
}

double readNumber(const YAML::Node& node, const std::string& key) {
  const YAML::Node value = requireKey(node, key);
  if (value.IsSequence() && value.size() == 1) return toNumber(value[0], key);  // MATLAB scalars can be [x]
  return toNumber(value, key);
}

std::string readText(const YAML::Node& node, const std::string& key) {
  const YAML::Node value = requireKey(node, key);
  require(value.IsScalar(), "key '" + key + "' is not text");
  return value.Scalar();
}

}  // namespace tissuemosaic
