#include "RowProcess.h"

#include "BatchRowOptions.h"

#include "Core/Error.h"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>

namespace tissuemosaic::cli {
namespace {

namespace fs = std::filesystem;

/// Removes what an atomic write of a killed process left (".NAME.tmp-PID-N", IO/AtomicFile.cpp).
void removeTemporaryFiles(const std::string& folder) {
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 1 && name[0] == '.' && name.find(".tmp-") != std::string::npos) fs::remove(entry.path(), error);
  }
}

/// The last error line the command printed ("tissuemosaic reconstruct: error: ..."), without the prefix.
std::string errorLine(const std::string& logPath) {
  std::ifstream log(logPath);
  std::string line, found;
  const std::regex error("^tissuemosaic[^:]*: (OpenCV )?error: (.*)$");
  std::smatch match;
  while (std::getline(log, line)) {
    if (std::regex_match(line, match, error)) found = (match[1].matched ? "OpenCV error: " : "") + match[2].str();
  }
  return found;
}

std::string quotedForLog(const std::string& word) {
  if (!word.empty() && word.find_first_of(" \t'\"\\$") == std::string::npos) return word;
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

std::string thisExecutable() { return fs::read_symlink("/proc/self/exe").string(); }

RunningRow startRow(const BatchRow& row, const std::string& workingFolder, int slot, const std::string& cudaDevice) {
  std::error_code error;
  fs::create_directories(row.out, error);
  require(fs::is_directory(row.out), "cannot make the row's out folder '" + row.out + "': " + error.message());
  removeTemporaryFiles(row.out);
  const RowFiles files = rowFiles(row);
  const std::string executable = thisExecutable();
  std::vector<std::string> words = reconstructArguments(row);
  words.insert(words.begin(), executable);
  {
    std::ofstream log(files.log, std::ios::trunc);
    require(static_cast<bool>(log), "cannot write the row's log '" + files.log + "'");
    log << "# in " << workingFolder << ":";
    for (const std::string& word : words) log << " " << quotedForLog(word);
    log << "\n";
  }
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  sigset_t none;
  sigemptyset(&none);
  const pid_t parent = getpid();
  RunningRow running{&row, -1, slot, std::chrono::steady_clock::now()};
  running.pid = fork();
  require(running.pid >= 0, std::string("cannot start a process for the row: ") + std::strerror(errno));
  if (running.pid == 0) {
    // The child: its own process group, killed with the batch, the batch's blocked signals unblocked.
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    const int logFd = open(files.log.c_str(), O_WRONLY | O_APPEND);
    const int nullFd = open("/dev/null", O_RDONLY);
    if (logFd < 0 || nullFd < 0 || chdir(workingFolder.c_str()) != 0) _exit(127);
    dup2(nullFd, 0);
    dup2(logFd, 1);
    dup2(logFd, 2);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGCHLD, SIG_DFL);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    if (!cudaDevice.empty()) setenv("CUDA_VISIBLE_DEVICES", cudaDevice.c_str(), 1);
    execv(argv[0], argv.data());
    const char message[] = "tissuemosaic batch: error: cannot run the row's command\n";
    (void)!write(2, message, sizeof message - 1);
    _exit(127);
  }
  setpgid(running.pid, running.pid);  // also here, so that the group exists before any signal is sent to it
  return running;
}

RowRecord finishedRowRecord(const RunningRow& running, int waitStatus) {
  const BatchRow& row = *running.row;
  RowRecord record;
  record.timeS = std::chrono::duration<double>(std::chrono::steady_clock::now() - running.start).count();
  removeTemporaryFiles(row.out);
  if (WIFSIGNALED(waitStatus)) {
    record.status = "failed";
    record.exitStatus = 128 + WTERMSIG(waitStatus);
    record.reason = std::string("ended by signal ") + std::to_string(WTERMSIG(waitStatus)) + " (" +
                    strsignal(WTERMSIG(waitStatus)) + "); log: " + rowFiles(row).log;
    return record;
  }
  record.exitStatus = WEXITSTATUS(waitStatus);
  if (record.exitStatus == 0) {
    try {
      RowRecord measured = measureRow(row);
      measured.exitStatus = 0;
      measured.timeS = record.timeS;
      measured.status = "done";
      return measured;
    } catch (const Error& error) {
      record.reason = error.what();
    }
  } else {
    record.reason = errorLine(rowFiles(row).log);
    if (record.reason.empty() && record.exitStatus > 128) {
      // reconstruct stopped by a signal (a time limit, scancel) writes its partial outputs and exits 128 + the
      // signal: measureRow says why they do not count (stopped_by_signal in the timing JSON).
      try {
        measureRow(row);
      } catch (const Error& error) {
        record.reason = error.what();
      }
    }
    if (record.reason.empty()) record.reason = "exit status " + std::to_string(record.exitStatus);
  }
  record.status = "failed";
  return record;
}

void stopRow(const RunningRow& running) {
  kill(-running.pid, SIGKILL);
  int status = 0;
  while (waitpid(running.pid, &status, 0) < 0 && errno == EINTR) {
  }
  removeTemporaryFiles(running.row->out);
}

}  // namespace tissuemosaic::cli
