#pragma once
/// @file AtomicFile.h
/// @brief Every output file is written under a temporary name in its own folder and renamed over the target only
/// when complete: a write that fails midway (full disk, file-size limit, an error, a stop) leaves an existing file
/// exactly as it was, and a reader never sees half a file.
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace tissuemosaic {

/// All the outputs of one run, replaced together: while a batch is open on this thread, writeFileAtomically keeps
/// each complete temporary file and commit() renames them all over their targets; a batch closed without commit()
/// (the run failed) removes them, so that no output of a failed run replaces an existing file.
class OutputBatch {
public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;
  void commit();

  struct Pending {
    std::string temporaryPath, path, what;
  };

private:
  std::vector<Pending> pending_;
  OutputBatch* outer_;
  friend void writeFileAtomically(const std::string&, const std::string&,
                                  const std::function<bool(const std::string&)>&);
};

/// Throws Error naming `what` and `path` unless `path` can be written: its folder exists and is writable, and the
/// path itself is not a folder. Commands call it for every output before any work starts.
void requireWritableOutput(const std::string& path, const std::string& what);

/// Calls write(temporaryPath) for a file beside `path`, then renames it over `path`. The writer may use any library
/// that takes a file name (OpenCV, VTK); it throws, or returns false, when it failed. On failure the temporary file
/// is removed and Error("cannot write <what> '<path>': ...") is thrown.
void writeFileAtomically(const std::string& path, const std::string& what,
                         const std::function<bool(const std::string& temporaryPath)>& write);

/// The same for a writer of a stream (binary mode): a failed stream (disk full, file too large) is an error.
void writeStreamAtomically(const std::string& path, const std::string& what,
                           const std::function<void(std::ostream& stream)>& write);

}  // namespace tissuemosaic
