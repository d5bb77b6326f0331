#include "vtkTissueMosaicLandmarksFile.h"

#include "IO/AtomicFile.h"
#include "Core/Error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <set>
#include <sstream>

namespace tissuemosaic {

namespace {

using nlohmann::json;

const char* const kMarkupsSchema =
    "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/"
    "markups-schema-v1.0.3.json#";

bool endsWith(const std::string& text, const std::string& suffix) {
  if (text.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), text.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

std::string trimmed(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r\n") - begin + 1);
}

/// The frame a markups file names: "LPS"/"RAS", or the numeric codes of old .fcsv files (0 = RAS, 1 = LPS).
AnatomicalFrame frameFromText(const std::string& value, const std::string& path) {
  std::string word = trimmed(value);
  std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return std::toupper(c); });
  if (word == "LPS" || word == "1") return AnatomicalFrame::LPS;
  if (word == "RAS" || word == "0") return AnatomicalFrame::RAS;
  throw Error("landmark file '" + path + "' names the coordinate system '" + value +
              "'; only LPS and RAS are supported");
}

AnatomicalFrame undeclared(std::optional<AnatomicalFrame> fallback, const std::string& path) {
  if (fallback) return *fallback;
  throw Error("landmark file '" + path + "' does not say whether it is in LPS or RAS; state the frame explicitly "
              "(e.g. --landmarks-frame lps)");
}

std::vector<LandmarkList> readMarkupsJson(const std::string& path, std::optional<AnatomicalFrame> fallback) {
  std::ifstream file(path);
  require(file.good(), "cannot read landmark file '" + path + "': the file does not exist or is not readable");
  json document;
  try {
    document = json::parse(file);
  } catch (const json::exception& error) {
    throw Error("landmark file '" + path + "' is not valid JSON: " + error.what());
  }
  require(document.is_object() && document.contains("markups") && document["markups"].is_array(),
          "landmark file '" + path + "' is not a Slicer markups file (no \"markups\" list)");
  std::vector<LandmarkList> lists;
  try {
    for (const json& markup : document["markups"]) {
      LandmarkList list;
      list.name = markup.value("name", std::string());
      list.fileFrame = markup.contains("coordinateSystem")
                           ? frameFromText(markup["coordinateSystem"].get<std::string>(), path)
                           : undeclared(fallback, path);
      if (markup.contains("coordinateUnits")) {
        const std::string units = markup["coordinateUnits"].get<std::string>();
        require(units == "mm", "landmark file '" + path + "' is in '" + units + "'; only mm is supported");
      }
      if (markup.contains("controlPoints")) {
        for (const json& point : markup["controlPoints"]) {
          if (point.value("positionStatus", std::string("defined")) == "missing") continue;
          const json& position = point.at("position");
          require(position.is_array() && position.size() == 3,
                  "landmark file '" + path + "': a control point's \"position\" is not three numbers");
          const Eigen::Vector3d p(position[0].get<double>(), position[1].get<double>(), position[2].get<double>());
          list.points.push_back({point.value("label", std::string()), toLps(p, list.fileFrame)});
        }
      }
      lists.push_back(std::move(list));
    }
  } catch (const json::exception& error) {
    throw Error("landmark file '" + path + "' is malformed: " + error.what());
  }
  return lists;
}

/// Splits one CSV line; double-quoted fields may hold commas and "" for a quote.
std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

std::vector<LandmarkList> readFcsv(const std::string& path, std::optional<AnatomicalFrame> fallback) {
  std::ifstream file(path);
  require(file.good(), "cannot read landmark file '" + path + "': the file does not exist or is not readable");
  std::optional<AnatomicalFrame> frame;
  // Slicer's default column order; a "# columns =" line overrides it.
  std::map<std::string, std::size_t> column = {{"x", 1}, {"y", 2}, {"z", 3}, {"label", 11}};
  LandmarkList list;
  std::string line;
  int lineNumber = 0;
  while (std::getline(file, line)) {
    ++lineNumber;
    if (trimmed(line).empty()) continue;
    if (line[0] == '#') {
      const auto equals = line.find('=');
      if (equals == std::string::npos) continue;
      const std::string key = trimmed(line.substr(1, equals - 1));
      const std::string value = trimmed(line.substr(equals + 1));
      if (key == "CoordinateSystem") frame = frameFromText(value, path);
      if (key == "columns") {
        column.clear();
        const auto names = splitCsv(value);
        for (std::size_t i = 0; i < names.size(); ++i) column[trimmed(names[i])] = i;
        require(column.count("x") && column.count("y") && column.count("z"),
                "landmark file '" + path + "': the columns line names no x, y, z");
      }
      continue;
    }
    const auto fields = splitCsv(line);
    const auto field = [&](const std::string& name) -> std::string {
      const auto found = column.find(name);
      return found != column.end() && found->second < fields.size() ? fields[found->second] : std::string();
    };
    Landmark landmark;
    try {
      std::size_t used = 0;
      for (int axis = 0; axis < 3; ++axis) {
        const std::string value = trimmed(field(std::string(1, static_cast<char>('x' + axis))));
        landmark.positionLps[axis] = std::stod(value, &used);
        if (used != value.size()) throw std::invalid_argument(value);
      }
    } catch (const std::exception&) {
      throw Error("landmark file '" + path + "', line " + std::to_string(lineNumber) +
                  ": x, y, z are not numbers");
    }
    landmark.label = field("label");
    list.points.push_back(landmark);
  }
  require(!list.points.empty(), "landmark file '" + path + "' holds no landmarks (no point lines)");
  list.fileFrame = frame ? *frame : undeclared(fallback, path);
  for (Landmark& landmark : list.points) landmark.positionLps = toLps(landmark.positionLps, list.fileFrame);
  return {list};
}

std::string formatted(double value) {
  std::ostringstream out;
  out << std::setprecision(17) << value;
  return out.str();
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

std::vector<LandmarkList> readLandmarkFile(const std::string& path, std::optional<AnatomicalFrame> frameIfUndeclared) {
  if (endsWith(path, ".json")) return readMarkupsJson(path, frameIfUndeclared);
  if (endsWith(path, ".fcsv")) return readFcsv(path, frameIfUndeclared);
  throw Error("cannot read landmark file '" + path + "': use a Slicer markups file (.mrk.json or .fcsv)");
}

LandmarkList readLandmarks(const std::string& path, std::optional<AnatomicalFrame> frameIfUndeclared) {
  auto lists = readLandmarkFile(path, frameIfUndeclared);
  require(lists.size() == 1, "landmark file '" + path + "' holds " + std::to_string(lists.size()) +
                                 " markups lists; expected exactly one");
  return std::move(lists.front());
}

void writeLandmarkFile(const std::string& path, const std::vector<LandmarkList>& lists, AnatomicalFrame fileFrame) {
  std::ostringstream file;  // built whole, then written atomically
  if (endsWith(path, ".fcsv")) {
    require(lists.size() == 1, "an .fcsv file holds exactly one landmark list; use .mrk.json for several");
    file << "# Markups fiducial file version = 4.11\n# CoordinateSystem = " << frameName(fileFrame)
         << "\n# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n";
    int id = 0;
    for (const Landmark& landmark : lists.front().points) {
      const Eigen::Vector3d p = fromLps(landmark.positionLps, fileFrame);
      file << ++id << ',' << formatted(p.x()) << ',' << formatted(p.y()) << ',' << formatted(p.z())
           << ",0,0,0,1,1,1,0," << csvField(landmark.label) << ",,\n";
    }
  } else {
    require(endsWith(path, ".mrk.json"), "cannot write landmark file '" + path + "': use .mrk.json or .fcsv");
    json markups = json::array();
    for (const LandmarkList& list : lists) {
      json points = json::array();
      int id = 0;
      for (const Landmark& landmark : list.points) {
        const Eigen::Vector3d p = fromLps(landmark.positionLps, fileFrame);
        points.push_back({{"id", std::to_string(++id)},
                          {"label", landmark.label},
                          {"description", ""},
                          {"associatedNodeID", ""},
                          {"position", {p.x(), p.y(), p.z()}},
                          {"orientation", {-1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0}},
                          {"selected", true},
                          {"locked", false},
                          {"visibility", true},
                          {"positionStatus", "defined"}});
      }
      json markup = {{"type", "Fiducial"},
                     {"coordinateSystem", frameName(fileFrame)},
                     {"coordinateUnits", "mm"},
                     {"locked", false},
                     {"fixedNumberOfControlPoints", false},
                     {"labelFormat", "%N-%d"},
                     {"lastUsedControlPointNumber", id},
                     {"controlPoints", points},
                     {"measurements", json::array()}};
      if (!list.name.empty()) markup["name"] = list.name;
      markups.push_back(markup);
    }
    file << json{{"@schema", kMarkupsSchema}, {"markups", markups}}.dump(4) << '\n';
  }
  writeStreamAtomically(path, "landmark file", [&](std::ostream& out) { out << file.str(); });
}

LandmarkPairs pairLandmarks(const LandmarkList& model, const LandmarkList& target) {
  LandmarkPairs pairs;
  const auto uniqueLabels = [](const LandmarkList& list) {
    std::set<std::string> labels;
    for (const Landmark& landmark : list.points) {
      if (landmark.label.empty() || !labels.insert(landmark.label).second) return std::set<std::string>();
    }
    return labels;
  };
  const auto modelLabels = uniqueLabels(model);
  const auto targetLabels = uniqueLabels(target);
  // Labels that match in part are a mistake (a misnamed or missing point): pairing such lists by order would pair
  // wrong points silently. Order is used only where the labels say nothing (missing, repeated, or none in common).
  std::vector<std::string> onlyModel, onlyTarget;
  std::set_difference(modelLabels.begin(), modelLabels.end(), targetLabels.begin(), targetLabels.end(),
                      std::back_inserter(onlyModel));
  std::set_difference(targetLabels.begin(), targetLabels.end(), modelLabels.begin(), modelLabels.end(),
                      std::back_inserter(onlyTarget));
  const bool someInCommon = onlyModel.size() < modelLabels.size();
  if (!modelLabels.empty() && !targetLabels.empty() && someInCommon && (!onlyModel.empty() || !onlyTarget.empty())) {
    const auto joined = [](const std::vector<std::string>& labels) {
      std::string text;
      for (const std::string& label : labels) text += (text.empty() ? "'" : ", '") + label + "'";
      return text.empty() ? std::string("none") : text;
    };
    throw Error("the landmark labels do not match: only on the model: " + joined(onlyModel) +
                "; only on the target: " + joined(onlyTarget) + " (landmarks are paired by label: rename them)");
  }
  if (!modelLabels.empty() && modelLabels == targetLabels) {
    std::map<std::string, Eigen::Vector3d> targetByLabel;
    for (const Landmark& landmark : target.points) targetByLabel[landmark.label] = landmark.positionLps;
    for (const Landmark& landmark : model.points) {
      pairs.labels.push_back(landmark.label);
      pairs.modelLps.push_back(landmark.positionLps);
      pairs.targetLps.push_back(targetByLabel.at(landmark.label));
    }
    pairs.pairedByLabel = true;
    return pairs;
  }
  require(model.points.size() == target.points.size(),
          "cannot pair the landmarks: " + std::to_string(model.points.size()) + " on the model but " +
              std::to_string(target.points.size()) +
              " on the target, and their labels do not match one to one (give both lists the same labels, or "
              "the same number of points in corresponding order)");
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    pairs.labels.push_back(model.points[i].label.empty() ? std::to_string(i + 1) : model.points[i].label);
    pairs.modelLps.push_back(model.points[i].positionLps);
    pairs.targetLps.push_back(target.points[i].positionLps);
  }
  return pairs;
}

LandmarkPairs readLandmarkPairs(const std::string& path, std::optional<AnatomicalFrame> frameIfUndeclared) {
  const auto lists = readLandmarkFile(path, frameIfUndeclared);
  require(lists.size() == 2, "landmark pairs file '" + path + "' holds " + std::to_string(lists.size()) +
                                 " markups lists; expected two (the model's first, the target's second)");
  return pairLandmarks(lists[0], lists[1]);
}

}  // namespace tissuemosaic
