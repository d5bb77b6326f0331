#include "BatchRunner.h"

#include "BatchRecord.h"
#include "RowProcess.h"

#include "Core/Device.h"
#include "Core/Error.h"

#include <opencv2/core/utility.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace tissuemosaic::cli {
namespace {

/// The GPUs a row may be given: CUDA_VISIBLE_DEVICES's entries, else one per GPU the NVIDIA driver lists; none in a
/// build without CUDA.
std::vector<std::string> visibleGpus() {
  if (!cudaCompiledIn()) return {};
  std::vector<std::string> gpus;
  if (const char* visible = std::getenv("CUDA_VISIBLE_DEVICES")) {
    std::stringstream list(visible);
    for (std::string gpu; std::getline(list, gpu, ',');) {
      if (!gpu.empty()) gpus.push_back(gpu);
    }
    return gpus;
  }
  std::error_code error;
  int count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/driver/nvidia/gpus", error)) {
    gpus.push_back(std::to_string(count++));
  }
  return gpus;
}

/// Blocks SIGINT, SIGTERM and SIGCHLD for the batch's life: it takes them with sigtimedwait between rows, and a row
/// ending or a stop request is never lost between two checks. The old mask comes back at the end.
class BlockedSignals {
public:
  BlockedSignals() {
    sigemptyset(&set_);
    for (int signal : {SIGINT, SIGTERM, SIGCHLD}) sigaddset(&set_, signal);
    pthread_sigmask(SIG_BLOCK, &set_, &old_);
  }
  ~BlockedSignals() {
    timespec none{0, 0};
    while (sigtimedwait(&set_, nullptr, &none) > 0) {  // drop the SIGCHLDs of rows already collected
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  /// The next of the signals within `seconds`, 0 when none came.
  int wait(double seconds) {
    timespec timeout{static_cast<time_t>(seconds), static_cast<long>((seconds - static_cast<time_t>(seconds)) * 1e9)};
    const int signal = sigtimedwait(&set_, nullptr, &timeout);
    return signal > 0 ? signal : 0;
  }

private:
  sigset_t set_{}, old_{};
};

class Progress {
public:
  explicit Progress(int total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  void line(const BatchRunResult& result, const std::vector<RunningRow>& running) const {
    std::string names;
    for (const RunningRow& row : running) names += (names.empty() ? "" : ", ") + row.row->name;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::cerr << cv::format("batch: %d/%d rows finished (%d done, %d failed, %d already done); running: %s; %.0f s\n",
                            result.done + result.failed + result.skipped, total_, result.done, result.failed,
                            result.skipped, names.empty() ? "none" : names.c_str(), elapsed);
  }

private:
  int total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

int defaultBatchJobs() { return std::max<int>(1, static_cast<int>(visibleGpus().size())); }

BatchRunResult runBatchRows(const BatchManifest& manifest, const std::vector<int>& rowNumbers, int jobs) {
  require(jobs >= 1, "--jobs must be at least 1");
  std::deque<const BatchRow*> waiting;
  if (rowNumbers.empty()) {
    for (const BatchRow& row : manifest.rows) waiting.push_back(&row);
  } else {
    for (int number : rowNumbers) waiting.push_back(&manifest.row(number));
  }
  const std::vector<std::string> gpus = visibleGpus();
  BatchRunResult result;
  Progress progress(static_cast<int>(waiting.size()));
  BlockedSignals signals;
  std::vector<RunningRow> running;
  std::vector<bool> slotBusy(jobs, false);
  while (!waiting.empty() || !running.empty()) {
    while (!waiting.empty() && static_cast<int>(running.size()) < jobs) {
      const BatchRow& row = *waiting.front();
      waiting.pop_front();
      if (rowIsDone(row)) {
        ++result.skipped;
        std::cerr << "row " << row.number << " " << row.name << ": already done (" << row.out << "/done.json), skipped\n";
        continue;
      }
      const int slot = static_cast<int>(std::find(slotBusy.begin(), slotBusy.end(), false) - slotBusy.begin());
      // One GPU per slot where there are several; with one GPU (or none) the rows share what there is.
      const std::string gpu = gpus.size() > 1 ? gpus[slot % gpus.size()] : "";
      running.push_back(startRow(row, manifest.folder, slot, gpu));
      slotBusy[slot] = true;
      std::cerr << "row " << row.number << " " << row.name << ": started (log " << row.out << "/reconstruct.log)\n";
      progress.line(result, running);
    }
    const int signal = signals.wait(1.0);
    if (signal == SIGINT || signal == SIGTERM) {
      for (const RunningRow& row : running) stopRow(row);
      result.stopped = static_cast<int>(running.size());
      result.signal = signal;
      std::cerr << "batch: stopped by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << ": " << running.size()
                << " running rows were stopped and " << waiting.size()
                << " did not start; run the batch again to finish them\n";
      return result;
    }
    for (auto it = running.begin(); it != running.end();) {
      int status = 0;
      const pid_t ended = waitpid(it->pid, &status, WNOHANG);
      if (ended != it->pid) {
        ++it;
        continue;
      }
      const RowRecord record = finishedRowRecord(*it, status);
      writeRowRecord(*it->row, record);
      const BatchRow& row = *it->row;
      if (record.status == "done") {
        ++result.done;
        std::cerr << cv::format("row %d %s: done in %.1f s\n", row.number, row.name.c_str(), record.timeS);
      } else {
        ++result.failed;
        std::cerr << "row " << row.number << " " << row.name << ": failed (exit status " << record.exitStatus
                  << "): " << record.reason << "\n";
      }
      slotBusy[it->slot] = false;
      it = running.erase(it);
      progress.line(result, running);
    }
  }
  return result;
}

}  // namespace tissuemosaic::cli
