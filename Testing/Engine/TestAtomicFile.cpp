// Atomic outputs: a write that fails midway (file-size limit, an error in the writer) leaves an existing file exactly
// as it was and no temporary file behind; a path that cannot be written is refused before any work, with its reason.
#include "Core/Error.h"
#include "ErrorText.h"
#include "IO/AtomicFile.h"
#include "IO/DisparityPfm.h"
#include "IO/TrajectoryTum.h"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace tissuemosaic {
namespace {

namespace fs = std::filesystem;

std::string outputFolder(const std::string& name) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/AtomicFile/" + name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

std::string readBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

std::size_t filesIn(const std::string& folder) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
}

/// Lowers the file-size limit (as `ulimit -f` does) for its lifetime.
class FileSizeLimit {
public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    rlimit lowered = saved_;
    lowered.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &lowered);
  }
  ~FileSizeLimit() { setrlimit(RLIMIT_FSIZE, &saved_); }

private:
  rlimit saved_{};
};

TEST(AtomicFile, WriteCutShortByAFileSizeLimitKeepsTheOldFile) {
  const std::string folder = outputFolder("limit");
  const std::string path = folder + "/keep.pfm";
  writeBytes(path, "the old contents");
  const cv::Mat disparity(200, 200, CV_32FC1, cv::Scalar(3.5f));  // 160 kB, far over the limit
  std::string message;
  {
    const FileSizeLimit limit(4096);
    message = errorOf([&] { writePfm(path, disparity); });
  }
  EXPECT_NE(message.find("cannot write PFM '" + path + "': writing failed"), std::string::npos) << message;
  EXPECT_EQ(readBytes(path), "the old contents");
  EXPECT_EQ(filesIn(folder), 1u) << "the temporary file must be removed";
  // Without the limit the same write replaces the file whole.
  writePfm(path, disparity);
  EXPECT_EQ(readPfm(path).at<float>(199, 199), 3.5f);
  EXPECT_EQ(filesIn(folder), 1u);
}

TEST(AtomicFile, WriterErrorKeepsTheOldFile) {
  const std::string folder = outputFolder("error");
  const std::string path = folder + "/keep.txt";
  writeBytes(path, "old");
  const std::string message = errorOf([&] {
    writeStreamAtomically(path, "test file", [](std::ostream& out) {
      out << "half a file";
      throw Error("stopped midway");
    });
  });
  EXPECT_EQ(message, "stopped midway");
  EXPECT_EQ(readBytes(path), "old");
  EXPECT_EQ(filesIn(folder), 1u);
  const std::string refused = errorOf([&] { writeFileAtomically(path, "test file", [](const std::string&) { return false; }); });
  EXPECT_NE(refused.find("cannot write test file"), std::string::npos) << refused;
  EXPECT_EQ(readBytes(path), "old");
}

TEST(AtomicFile, UnwritablePathsAreNamedBeforeAnyWork) {
  const std::string folder = outputFolder("paths");
  EXPECT_EQ(errorOf([&] { requireWritableOutput(folder, "PFM"); }), "cannot write PFM '" + folder + "': it is a folder");
  EXPECT_EQ(errorOf([&] { requireWritableOutput(folder + "/missing/d.pfm", "PFM"); }),
            "cannot write PFM '" + folder + "/missing/d.pfm': the folder does not exist ('" + folder + "/missing')");
  EXPECT_EQ(errorOf([&] { requireWritableOutput(folder + "/d.pfm", "PFM"); }), "no error");
  EXPECT_EQ(errorOf([&] { requireWritableOutput("d.pfm", "PFM"); }), "no error");  // the working folder
  EXPECT_EQ(errorOf([&] { writeTumTrajectory(folder, {}, ""); }), "cannot write trajectory '" + folder + "': it is a folder");
}

}  // namespace
}  // namespace tissuemosaic

namespace tissuemosaic {
namespace {

// Issue 32: a TUM file with a repeated time stamp was read without a word (associations by time then ambiguous).
TEST(TrajectoryTumReader, RepeatedTimeStampsAndNonFiniteValuesAreNamed) {
  const std::string folder = outputFolder("tum");
  const std::string path = folder + "/t.txt";
  writeBytes(path, "# t tx ty tz qx qy qz qw\n0.5 1 2 3 0 0 0 1\n0.6 1 2 3 0 0 0 1\n0.5 4 5 6 0 0 0 1\n");
  EXPECT_EQ(errorOf([&] { readTumTrajectory(path); }),
            "trajectory '" + path + "' line 4 repeats the time stamp 0.500000 of line 2");
  writeBytes(path, "0.5 inf 2 3 0 0 0 1\n");
  EXPECT_NE(errorOf([&] { readTumTrajectory(path); }).find("line 1: "), std::string::npos);
  writeBytes(path, "0.5 1 2 3 0 0 0 1\n0.6 1 2 3 0 0 0 1\n");
  EXPECT_EQ(readTumTrajectory(path).size(), 2u);
}

}  // namespace
}  // namespace tissuemosaic
