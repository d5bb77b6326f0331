#pragma once
/// @file FuzzFile.h
/// @brief What every fuzz target shares: the fuzzer's bytes written to a file (the readers take paths, as the CLI
/// gives them), and the rule that a reader may only fail with tissuemosaic::Error. Any other exception escapes to
/// libFuzzer, which reports it as a crash, as it does for ASan/UBSan findings, a hang or a leak.
#include "Core/Error.h"

#include <opencv2/core/utils/logger.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

namespace tissuemosaic::fuzz {

/// A file of this process (the fuzzer may run several processes in one folder) in $TMPDIR, removed at exit.
class FuzzFile {
public:
  /// `name` ends with the extension the reader dispatches on, e.g. "model.stl".
  explicit FuzzFile(const std::string& name) {
    const char* folder = std::getenv("TMPDIR");
    path_ = std::string(folder && *folder ? folder : "/tmp") + "/tm-fuzz-" + std::to_string(::getpid()) + "-" + name;
  }
  ~FuzzFile() { std::remove(path_.c_str()); }
  FuzzFile(const FuzzFile&) = delete;
  FuzzFile& operator=(const FuzzFile&) = delete;

  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::ofstream file(path_, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    file.close();
    if (!file) std::abort();  // the harness itself failed: stop rather than fuzz nothing
    return path_;
  }
  const std::string& path() const { return path_; }

private:
  std::string path_;
};

/// Runs a read; an Error (the readers' way to refuse bad input) is the expected outcome for most inputs.
/// TM_FUZZ_VERBOSE=1 prints each input's outcome (to check that the seeds are read without error).
template <class Read>
void expectOnlyErrors(Read&& read) {
  static const bool verbose = std::getenv("TM_FUZZ_VERBOSE") != nullptr;
  try {
    read();
    if (verbose) std::fprintf(stderr, "read without error\n");
  } catch (const Error& error) {
    if (verbose) std::fprintf(stderr, "Error: %s\n", error.what());
  }
}

/// OpenCV's own log lines (backend probing) cost time and say nothing here.
inline void quietOpenCv() { cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT); }

}  // namespace tissuemosaic::fuzz
