#include "BatchSummary.h"

#include "IO/AtomicFile.h"

#include <opencv2/core/utility.hpp>

#include <filesystem>
#include <sstream>

namespace tissuemosaic::cli {
namespace {

template <class T>
std::string text(const std::optional<T>& value) {
  if (!value) return "";
  std::ostringstream out;
  out << *value;
  return out.str();
}

std::string agreementText(const std::optional<double>& agreement) {
  return agreement ? cv::format("%.4f", *agreement) : "";
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
std::string csvField(const std::string& value) {
  if (value.find_first_of(",\"\n\r") == std::string::npos) return value;
  std::string quoted = "\"";
  for (const char c : value) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

BatchSummary collectSummary(const BatchManifest& manifest) {
  BatchSummary summary;
  for (const BatchRow& row : manifest.rows) {
    summary.records.push_back(readRowRecord(row));
    const std::string& status = summary.records.back().status;
    (status == "done" ? summary.done : status == "failed" ? summary.failed : summary.notRun) += 1;
  }
  return summary;
}

std::string defaultSummaryPath(const BatchManifest& manifest, const std::string& extension) {
  const std::filesystem::path path(manifest.path);
  return (path.parent_path() / (path.stem().string() + "-summary" + extension)).string();
}

void writeSummaryFiles(const BatchManifest& manifest, const BatchSummary& summary, const std::string& csvPath,
                       const std::string& jsonPath) {
  std::ostringstream csv, json;
  csv << "row,name,status,exit_status,frames,tracked,lost,key_frames,points,agreement,time_s,reason,out\n";
  json << "{\"rows\": [";
  for (std::size_t i = 0; i < manifest.rows.size(); ++i) {
    const BatchRow& row = manifest.rows[i];
    const RowRecord& r = summary.records[i];
    csv << row.number << "," << csvField(row.name) << "," << r.status << ","
        << (r.exitStatus >= 0 ? std::to_string(r.exitStatus) : "") << "," << text(r.frames) << "," << text(r.tracked)
        << "," << text(r.lost) << "," << text(r.keyFrames) << "," << text(r.points) << ","
        << agreementText(r.agreement) << "," << (r.status == "not run" ? "" : cv::format("%.1f", r.timeS)) << ","
        << csvField(r.reason) << "," << csvField(row.out) << "\n";
    json << (i ? ",\n  " : "\n  ") << rowRecordJson(row, r);
  }
  json << "\n], \"done\": " << summary.done << ", \"failed\": " << summary.failed << ", \"not_run\": " << summary.notRun
       << "}\n";
  writeStreamAtomically(csvPath, "summary CSV", [&](std::ostream& out) { out << csv.str(); });
  writeStreamAtomically(jsonPath, "summary JSON", [&](std::ostream& out) { out << json.str(); });
}

std::string summaryTable(const BatchManifest& manifest, const BatchSummary& summary) {
  std::ostringstream out;
  for (std::size_t i = 0; i < manifest.rows.size(); ++i) {
    const BatchRow& row = manifest.rows[i];
    const RowRecord& r = summary.records[i];
    out << "row " << row.number << " " << row.name << ": " << r.status;
    if (r.status == "done") {
      out << cv::format(" in %.1f s: %s frames (%s tracked, %s lost), %s key frames, %s points, agreement %s",
                        r.timeS, text(r.frames).c_str(), text(r.tracked).c_str(), text(r.lost).c_str(),
                        text(r.keyFrames).c_str(), text(r.points).c_str(),
                        r.agreement ? cv::format("%.0f%%", 100 * *r.agreement).c_str() : "not measured");
    } else if (r.status == "failed") {
      out << " (exit status " << r.exitStatus << "): " << r.reason;
    }
    out << "\n";
  }
  out << "summary: " << summary.done << " done, " << summary.failed << " failed, " << summary.notRun << " not run, of "
      << manifest.rows.size() << " rows\n";
  return out.str();
}

}  // namespace tissuemosaic::cli
