#include "ProgressBar.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace tissuemosaic::cli {

ProgressBar::ProgressBar(int total, bool enabled) : total_(total), enabled_(enabled), terminal_(isatty(STDERR_FILENO) == 1) {}

void ProgressBar::update(int done, const std::string& status) {
  if (!enabled_) return;
  if (terminal_) {
    constexpr int width = 30;
    std::string line;
    if (total_ > 0) {
      const int filled = static_cast<int>(static_cast<long long>(width) * done / total_);
      line = "[" + std::string(filled, '#') + std::string(width - filled, '.') + "] " + std::to_string(done) + "/" +
             std::to_string(total_);
    } else {
      line = "frame " + std::to_string(done);
    }
    line += "  " + status;
    std::cerr << "\r" << line;
    if (line.size() < lastLine_.size()) std::cerr << std::string(lastLine_.size() - line.size(), ' ');
    std::cerr << std::flush;
    lastLine_ = line;
    drawn_ = true;
    return;
  }
  const int decile = total_ > 0 ? 10 * done / total_ : done / 100;
  if (decile != lastDecile_) {
    lastDecile_ = decile;
    std::cerr << (total_ > 0 ? std::to_string(done) + "/" + std::to_string(total_) : std::to_string(done)) << " frames: "
              << status << "\n";
  }
}

void ProgressBar::message(const std::string& text) {
  if (!enabled_) return;
  if (terminal_ && drawn_) std::cerr << "\r" << std::string(lastLine_.size(), ' ') << "\r";
  std::cerr << text << "\n";
  if (terminal_ && drawn_) std::cerr << lastLine_ << std::flush;
}

void ProgressBar::finish() {
  if (enabled_ && terminal_ && drawn_) std::cerr << "\n";
  drawn_ = false;
}

}  // namespace tissuemosaic::cli
