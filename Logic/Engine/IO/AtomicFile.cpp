#include "AtomicFile.h"

#include "Core/Error.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace tissuemosaic {
namespace {

namespace fs = std::filesystem;

std::string folderOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

/// A name beside the target that no other writer of this process or another uses at the same time.
std::string temporaryNameFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  // The extension stays last: OpenCV picks its encoder by it.
  const fs::path target(path);
  return (target.parent_path() / ("." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                  std::to_string(counter++) + target.extension().string()))
      .string();
}

/// Writing past a file-size limit (ulimit -f) raises SIGXFSZ, whose default action kills the process before it can
/// clean up; ignored, the write fails with EFBIG and is reported like a full disk.
void ignoreFileSizeSignal() {
  static const bool once = [] {
    std::signal(SIGXFSZ, SIG_IGN);
    return true;
  }();
  (void)once;
}

thread_local OutputBatch* openBatch = nullptr;

void renameOver(const OutputBatch::Pending& file) {
  std::error_code error;
  fs::rename(file.temporaryPath, file.path, error);
  if (error) {
    fs::remove(file.temporaryPath, error);
    throw Error("cannot write " + file.what + " '" + file.path + "': " + error.message());
  }
}

}  // namespace

OutputBatch::OutputBatch() : outer_(openBatch) { openBatch = this; }

OutputBatch::~OutputBatch() {
  openBatch = outer_;
  for (const Pending& file : pending_) {
    std::error_code ignored;
    fs::remove(file.temporaryPath, ignored);
  }
}

void OutputBatch::commit() {
  std::vector<Pending> files;
  files.swap(pending_);
  for (const Pending& file : files) renameOver(file);
}

void requireWritableOutput(const std::string& path, const std::string& what) {
  const std::string context = "cannot write " + what + " '" + path + "': ";
  require(!path.empty(), "cannot write " + what + ": the path is empty");
  std::error_code error;
  require(!fs::is_directory(path, error), context + "it is a folder");
  const std::string folder = folderOf(path);
  require(fs::is_directory(folder, error), context + "the folder does not exist ('" + folder + "')");
  require(::access(folder.c_str(), W_OK | X_OK) == 0, context + "the folder is not writable ('" + folder + "')");
  if (fs::exists(path, error)) require(::access(path.c_str(), W_OK) == 0, context + "the file is not writable");
}

void writeFileAtomically(const std::string& path, const std::string& what,
                         const std::function<bool(const std::string& temporaryPath)>& write) {
  requireWritableOutput(path, what);
  ignoreFileSizeSignal();
  const std::string temporary = temporaryNameFor(path);
  const auto discard = [&] {
    std::error_code ignored;
    fs::remove(temporary, ignored);
  };
  bool written = false;
  try {
    written = write(temporary);
  } catch (...) {
    discard();
    throw;
  }
  std::error_code error;
  if (!written || !fs::is_regular_file(temporary, error)) {
    discard();
    throw Error("cannot write " + what + " '" + path + "': writing failed (disk full or file-size limit?)");
  }
  if (openBatch) {
    openBatch->pending_.push_back({temporary, path, what});
    return;
  }
  renameOver({temporary, path, what});
}

void writeStreamAtomically(const std::string& path, const std::string& what,
                           const std::function<void(std::ostream& stream)>& write) {
  writeFileAtomically(path, what, [&](const std::string& temporary) {
    std::ofstream file(temporary, std::ios::binary);
    if (!file.good()) return false;
    write(file);
    file.flush();
    file.close();
    return !file.fail();
  });
}

}  // namespace tissuemosaic
