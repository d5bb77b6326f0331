#include "BatchRecord.h"

#include "BatchRowOptions.h"

#include "Core/Error.h"
#include "IO/AtomicFile.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace tissuemosaic::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json readJsonFile(const std::string& path, const std::string& what) {
  std::ifstream file(path);
  if (!file) throw Error("cannot read the row's " + what + " '" + path + "'");
  try {
    return json::parse(file);
  } catch (const json::exception& error) {
    throw Error("the row's " + what + " '" + path + "' is not valid JSON: " + error.what());
  }
}

template <class T>
json orNull(const std::optional<T>& value) {
  return value ? json(*value) : json(nullptr);
}

template <class T>
std::optional<T> optionalField(const json& object, const char* key) {
  if (!object.contains(key) || object[key].is_null()) return std::nullopt;
  return object[key].get<T>();
}

json recordObject(const RowRecord& record) {
  return json{{"status", record.status},      {"exit_status", record.exitStatus}, {"reason", record.reason},
              {"time_s", record.timeS},        {"frames", orNull(record.frames)},  {"tracked", orNull(record.tracked)},
              {"lost", orNull(record.lost)},   {"key_frames", orNull(record.keyFrames)},
              {"points", orNull(record.points)}, {"agreement", orNull(record.agreement)}};
}

RowRecord recordFrom(const json& object) {
  RowRecord record;
  record.status = object.at("status").get<std::string>();
  record.exitStatus = object.at("exit_status").get<int>();
  record.reason = object.value("reason", "");
  record.timeS = object.value("time_s", 0.0);
  record.frames = optionalField<int>(object, "frames");
  record.tracked = optionalField<int>(object, "tracked");
  record.lost = optionalField<int>(object, "lost");
  record.keyFrames = optionalField<int>(object, "key_frames");
  record.points = optionalField<long long>(object, "points");
  record.agreement = optionalField<double>(object, "agreement");
  return record;
}

}  // namespace

RowRecord measureRow(const BatchRow& row) {
  const RowFiles files = rowFiles(row);
  const json timing = readJsonFile(files.timing, "timing JSON");
  const json quality = readJsonFile(files.quality, "quality JSON");
  RowRecord record;
  // reconstruct stops cleanly on SIGTERM and exits 0 with the frames it did: under Slurm, the time limit or scancel
  // signals every process of the task, so a row can end so before the batch hears of it. Partial is not done.
  if (timing.value("stopped_by_signal", false)) {
    throw Error("reconstruct was stopped by a signal before the end of its input (a time limit, scancel?): its " +
                std::to_string(timing.value("frames", 0)) + "-frame model is partial");
  }
  try {
    record.frames = timing.at("frames").get<int>();
    record.lost = timing.at("lost").get<int>();
    record.tracked = *record.frames - *record.lost;
    record.keyFrames = timing.at("key_frames").get<int>();
    record.points = timing.at("model_points").get<long long>();
    double sum = 0;
    int measured = 0;
    for (const json& frame : quality) {
      if (frame.contains("share_within_1mm") && frame["share_within_1mm"].is_number()) {
        sum += frame["share_within_1mm"].get<double>();
        ++measured;
      }
    }
    if (measured > 0) record.agreement = sum / measured;
  } catch (const json::exception& error) {
    throw Error("the row's timing or quality JSON in '" + row.out + "' lacks a figure: " + error.what());
  }
  return record;
}

bool rowIsDone(const BatchRow& row) {
  const RowFiles files = rowFiles(row);
  return fs::is_regular_file(files.doneRecord) && fs::is_regular_file(files.model);
}

RowRecord readRowRecord(const BatchRow& row) {
  const RowFiles files = rowFiles(row);
  for (const std::string& path : {files.doneRecord, files.failedRecord}) {
    if (!fs::is_regular_file(path)) continue;
    if (path == files.doneRecord && !rowIsDone(row)) continue;  // a done record without its model is not done
    try {
      return recordFrom(readJsonFile(path, "record"));
    } catch (const json::exception& error) {
      throw Error("the row's record '" + path + "' lacks a field: " + error.what());
    }
  }
  RowRecord record;
  record.status = "not run";
  return record;
}

void writeRowRecord(const BatchRow& row, const RowRecord& record) {
  const RowFiles files = rowFiles(row);
  const bool done = record.status == "done";
  const std::string text = recordObject(record).dump(2) + "\n";
  writeStreamAtomically(done ? files.doneRecord : files.failedRecord, done ? "done record" : "failure record",
                        [&](std::ostream& out) { out << text; });
  std::error_code ignored;
  fs::remove(done ? files.failedRecord : files.doneRecord, ignored);
}

std::string rowRecordJson(const BatchRow& row, const RowRecord& record) {
  json object = {{"row", row.number}, {"name", row.name}, {"out", row.out}};
  object.update(recordObject(record));
  return object.dump();
}

}  // namespace tissuemosaic::cli
