#include "BatchManifest.h"

#include "CommonOptions.h"

#include "Core/Error.h"

#include <CLI/CLI.hpp>
#include <opencv2/core/utility.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace tissuemosaic::cli {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> requiredColumns = {"name", "out", "args"};
const std::vector<std::string> optionalColumns = {"params", "device"};

struct CsvRecord {
  int line = 0;  ///< where the record starts, for messages
  std::vector<std::string> fields;
};

/// RFC 4180 records: fields separated by commas, a field in double quotes may hold commas, newlines and "" for a
/// quote. Blank lines are skipped. Throws Error for a quote left open or text after a closing quote.
std::vector<CsvRecord> readCsvRecords(const std::string& text, const std::string& path) {
  std::vector<CsvRecord> records;
  CsvRecord record;
  std::string field;
  bool quoted = false, afterQuote = false, recordHasText = false;
  int line = 1, quoteLine = 0;
  record.line = 1;
  auto endField = [&] {
    record.fields.push_back(field);
    field.clear();
    afterQuote = false;
  };
  auto endRecord = [&] {
    endField();
    if (recordHasText) records.push_back(record);
    record = CsvRecord{};
    record.line = line;
    recordHasText = false;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
        afterQuote = true;
      } else {
        if (c == '\n') ++line;
        field += c;
      }
      continue;
    }
    if (c == '\r') continue;
    if (c == '\n') {
      endRecord();
      ++line;
      record.line = line;
      continue;
    }
    if (c == ',') {
      endField();
      recordHasText = true;
      continue;
    }
    if (afterQuote) {
      throw Error(cv::format("manifest '%s' line %d: text after a closing quote (a quote inside a quoted field is "
                             "written \"\")", path.c_str(), line));
    }
    if (c == '"' && field.find_first_not_of(" \t") == std::string::npos) {
      field.clear();
      quoted = true;
      quoteLine = line;
      recordHasText = true;
      continue;
    }
    field += c;
    if (c != ' ' && c != '\t') recordHasText = true;
  }
  if (quoted) {
    throw Error(cv::format("manifest '%s' line %d: a quoted field is never closed", path.c_str(), quoteLine));
  }
  endRecord();
  return records;
}

std::string trimmed(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

using RowFields = std::map<std::string, std::string>;
struct RawRow {
  int line = 0;
  RowFields fields;
};

std::vector<RawRow> readCsvRows(const std::string& text, const std::string& path) {
  const std::vector<CsvRecord> records = readCsvRecords(text, path);
  if (records.empty()) throw Error("manifest '" + path + "' is empty: it needs the header line name,out,args");
  std::vector<std::string> header;
  for (const std::string& column : records.front().fields) header.push_back(trimmed(column));
  std::vector<RawRow> rows;
  for (std::size_t r = 1; r < records.size(); ++r) {
    const CsvRecord& record = records[r];
    if (record.fields.size() != header.size()) {
      throw Error(cv::format("manifest '%s' line %d: %zu fields, but the header has %zu (%s); a field with commas "
                             "is written in double quotes",
                             path.c_str(), record.line, record.fields.size(), header.size(),
                             CLI::detail::join(header, ",").c_str()));
    }
    RawRow row;
    row.line = record.line;
    for (std::size_t c = 0; c < header.size(); ++c) row.fields[header[c]] = trimmed(record.fields[c]);
    rows.push_back(row);
  }
  for (const std::string& column : header) {
    const bool known = std::count(requiredColumns.begin(), requiredColumns.end(), column) +
                       std::count(optionalColumns.begin(), optionalColumns.end(), column);
    if (!known) {
      throw Error("manifest '" + path + "' line 1: unknown column '" + column +
                  "' (columns: name, out, args, and optionally params, device)");
    }
  }
  for (const std::string& column : requiredColumns) {
    if (std::find(header.begin(), header.end(), column) == header.end()) {
      throw Error("manifest '" + path + "' line 1: the column '" + column +
                  "' is missing (the header must name name, out and args)");
    }
  }
  return rows;
}

/// YAML: `studies:` (or the document itself) a list of maps with the CSV's column names as keys.
std::vector<RawRow> readYamlRows(const std::string& text, const std::string& path) {
  YAML::Node document;
  try {
    document = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw Error("manifest '" + path + "' is not readable YAML: " + error.what());
  }
  const YAML::Node studies = document.IsMap() ? document["studies"] : document;
  if (!studies || !studies.IsSequence()) {
    throw Error("manifest '" + path + "': expected a list 'studies:' of maps with the keys name, out, args");
  }
  std::vector<RawRow> rows;
  for (const YAML::Node& study : studies) {
    RawRow row;
    row.line = study.Mark().line + 1;
    if (!study.IsMap()) {
      throw Error(cv::format("manifest '%s' line %d: a study is a map with the keys name, out, args", path.c_str(),
                             row.line));
    }
    for (const auto& entry : study) {
      const std::string key = entry.first.as<std::string>();
      const bool known = std::count(requiredColumns.begin(), requiredColumns.end(), key) +
                         std::count(optionalColumns.begin(), optionalColumns.end(), key);
      if (!known) {
        throw Error(cv::format("manifest '%s' line %d: unknown key '%s' (keys: name, out, args, and optionally "
                               "params, device)", path.c_str(), row.line, key.c_str()));
      }
      if (!entry.second.IsScalar()) {
        throw Error(cv::format("manifest '%s' line %d: '%s' must be one string", path.c_str(), row.line, key.c_str()));
      }
      row.fields[key] = trimmed(entry.second.as<std::string>());
    }
    for (const std::string& key : requiredColumns) {
      if (!row.fields.count(key)) {
        throw Error(cv::format("manifest '%s' line %d: the key '%s' is missing", path.c_str(), row.line, key.c_str()));
      }
    }
    rows.push_back(row);
  }
  return rows;
}

std::string lowerExtension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

}  // namespace

std::vector<std::string> BatchRow::options() const {
  std::vector<std::string> words = CLI::detail::split_up(args);
  if (!params.empty()) words.insert(words.end(), {"--params", params});
  if (!device.empty()) words.insert(words.end(), {"--device", device});
  return words;
}

bool BatchRow::wantsGpu() const {
  const std::vector<std::string> words = options();
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (words[i] == "--device=cuda" || (words[i] == "--device" && i + 1 < words.size() && words[i + 1] == "cuda")) {
      return true;
    }
  }
  return false;
}

const BatchRow& BatchManifest::row(int number) const {
  if (number < 1 || number > static_cast<int>(rows.size())) {
    throw UsageError(cv::format("--row %d: the manifest '%s' has rows 1 to %zu", number, path.c_str(), rows.size()));
  }
  return rows[number - 1];
}

BatchManifest readBatchManifest(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error("cannot read manifest '" + path + "': " + (fs::exists(path) ? "not readable" : "no such file"));
  std::ostringstream text;
  text << file.rdbuf();
  BatchManifest manifest;
  manifest.path = fs::absolute(path).lexically_normal().string();
  manifest.folder = fs::path(manifest.path).parent_path().string();
  const std::string extension = lowerExtension(path);
  std::string content = text.str();
  if (content.rfind("\xEF\xBB\xBF", 0) == 0) content.erase(0, 3);  // the byte-order mark spreadsheets write
  const std::vector<RawRow> raw = extension == ".yml" || extension == ".yaml" ? readYamlRows(content, path)
                                                                                : readCsvRows(content, path);
  if (raw.empty()) throw Error("manifest '" + path + "' has no study (one row per study after the header)");
  std::set<std::string> names, outs;
  for (const RawRow& fields : raw) {
    BatchRow row;
    row.number = static_cast<int>(manifest.rows.size()) + 1;
    auto field = [&](const std::string& key) {
      const auto found = fields.fields.find(key);
      return found == fields.fields.end() ? std::string() : found->second;
    };
    row.name = field("name");
    row.args = field("args");
    row.params = field("params");
    row.device = field("device");
    const std::string out = field("out");
    const std::string where = cv::format("manifest '%s' line %d (row %d)", path.c_str(), fields.line, row.number);
    require(!row.name.empty(), where + ": the name is empty");
    require(!out.empty(), where + ": the out folder is empty");
    require(!row.args.empty(), where + ": args is empty (the study's input and geometry, as for reconstruct)");
    row.out = (fs::path(manifest.folder) / out).lexically_normal().string();
    require(names.insert(row.name).second, where + ": the name '" + row.name + "' is given to an earlier row too");
    require(outs.insert(row.out).second, where + ": the out folder '" + out + "' is an earlier row's too");
    manifest.rows.push_back(row);
  }
  return manifest;
}

}  // namespace tissuemosaic::cli
