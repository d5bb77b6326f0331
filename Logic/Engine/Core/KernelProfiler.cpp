#include "KernelProfiler.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <vector>

namespace tissuemosaic::profiling {

namespace {
struct Entry {
  int calls = 0;
  double milliseconds = 0;
};
std::mutex mutex;
std::map<std::string, Entry>& entries() {
  static std::map<std::string, Entry> table;
  return table;
}
/// TM_PROFILE_KERNELS, read once.
const char* setting() {
  static const char* value = std::getenv("TM_PROFILE_KERNELS");
  return value;
}
}  // namespace

bool enabled() {
  static const bool on = setting() && *setting() && std::string(setting()) != "0";
  return on;
}

bool synchronisingLaunches() {
  static const bool on = enabled() && std::string(setting()) != "host";
  return on;
}

void record(const std::string& kernel, double milliseconds) {
  std::lock_guard<std::mutex> lock(mutex);
  Entry& entry = entries()[kernel];
  ++entry.calls;
  entry.milliseconds += milliseconds;
}

std::string report() {
  std::lock_guard<std::mutex> lock(mutex);
  std::vector<std::pair<std::string, Entry>> rows(entries().begin(), entries().end());
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.second.milliseconds > b.second.milliseconds; });
  std::string text;
  char line[512];
  for (const auto& [name, entry] : rows) {
    std::snprintf(line, sizeof line, "%10.3f ms %7d calls  %s\n", entry.milliseconds, entry.calls, name.c_str());
    text += line;
  }
  return text;
}

std::string reportKind() {
  return synchronisingLaunches() ? "kernel profile (TM_PROFILE_KERNELS; each launch synchronised)"
                                 : "host sections and CPU loops (TM_PROFILE_KERNELS=host; nothing synchronised)";
}

void reset() {
  std::lock_guard<std::mutex> lock(mutex);
  entries().clear();
}

}  // namespace tissuemosaic::profiling
