#include "vtkTissueMosaicDisplay.h"

#include "Core/Error.h"

#include <X11/Xlib.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

namespace tissuemosaic {

namespace {

std::mutex displayMutex;
std::optional<XDisplayStatus> established;
pid_t privateServerPid = -1;

/// The Xvfb executable on PATH, or empty.
std::string findXvfb() {
  const char* path = std::getenv("PATH");
  std::string paths = path ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= paths.size()) {
    const std::size_t end = std::min(paths.find(':', start), paths.size());
    const std::filesystem::path candidate = std::filesystem::path(paths.substr(start, end - start)) / "Xvfb";
    if (!candidate.parent_path().empty() && access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return {};
}

void stopServerAtExit() { stopPrivateXServer(); }

/// Starts `xvfb -displayfd`: the server picks a free display number itself and writes it to the pipe once it
/// accepts connections, so there is neither a race for the number nor a sleep. Returns ":N".
std::string startXvfb(const std::string& xvfb) {
  int fds[2];
  require(pipe(fds) == 0, std::string("cannot create a pipe for Xvfb: ") + std::strerror(errno));
  const std::string fdText = std::to_string(fds[1]);
  const pid_t pid = fork();
  require(pid >= 0, std::string("cannot start Xvfb: ") + std::strerror(errno));
  if (pid == 0) {
    close(fds[0]);
    prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive a crashed parent
    const int devNull = open("/dev/null", O_RDWR);
    if (devNull >= 0) {
      dup2(devNull, STDIN_FILENO);
      dup2(devNull, STDOUT_FILENO);
      dup2(devNull, STDERR_FILENO);
    }
    // 24-bit colour and a screen larger than any window we render; GLX is on by default (Mesa llvmpipe).
    execl(xvfb.c_str(), xvfb.c_str(), "-displayfd", fdText.c_str(), "-screen", "0", "2560x1600x24", "-nolisten",
          "tcp", "-noreset", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  std::string number;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (number.find('\n') == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    pollfd readable{fds[0], POLLIN, 0};
    if (poll(&readable, 1, 200) <= 0) continue;
    char buffer[16];
    const ssize_t got = read(fds[0], buffer, sizeof buffer);
    if (got <= 0) break;  // Xvfb exited without a display
    number.append(buffer, static_cast<std::size_t>(got));
  }
  close(fds[0]);
  if (number.find('\n') == std::string::npos) {
    kill(pid, SIGTERM);
    waitpid(pid, nullptr, 0);
    throw Error("the private X server (" + xvfb + " -displayfd) did not start within 20 s");
  }
  privateServerPid = pid;
  std::atexit(stopServerAtExit);
  return ":" + number.substr(0, number.find('\n'));
}

}  // namespace

namespace {

Display* sharedConnection = nullptr;

/// XOpenDisplay, retried: a local server that exists can still refuse a connection now and then when many clients
/// connect at once (seen with parallel tests on a loaded machine). Null when it cannot be opened.
Display* openXConnection(const std::string& display) {
  if (display.empty()) return nullptr;
  const bool localSocketExists = display.size() > 1 && display[0] == ':' &&
                                 std::filesystem::exists("/tmp/.X11-unix/X" + display.substr(1, display.find('.') - 1));
  const int attempts = localSocketExists ? 5 : 1;
  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(50 << attempt));
    if (Display* connection = XOpenDisplay(display.c_str())) return connection;
  }
  return nullptr;
}

}  // namespace

bool canOpenXDisplay(const std::string& display) {
  Display* connection = openXConnection(display);
  if (!connection) return false;
  XCloseDisplay(connection);
  return true;
}

void* sharedXConnection() {
  const XDisplayStatus status = ensureXDisplay(/*preferPrivate=*/true);
  const std::lock_guard<std::mutex> lock(displayMutex);
  if (!sharedConnection) sharedConnection = openXConnection(status.display);
  if (!sharedConnection) {
    throw Error("cannot connect to the X display " + status.display + " (" + status.description +
                "): the X server refused or is gone");
  }
  return sharedConnection;
}

XDisplayStatus ensureXDisplay(bool preferPrivate) {
  const std::lock_guard<std::mutex> lock(displayMutex);
  if (established) return *established;

  const char* current = std::getenv("DISPLAY");
  const std::string currentDisplay = current ? current : "";
  const bool currentWorks = canOpenXDisplay(currentDisplay);
  XDisplayStatus status;
  if (currentWorks && !preferPrivate) {
    status.display = currentDisplay;
    status.description = "X display " + currentDisplay + " (from $DISPLAY)";
  } else {
    const std::string xvfb = findXvfb();
    if (xvfb.empty()) {
      if (currentWorks) {
        status.display = currentDisplay;
        status.description = "X display " + currentDisplay + " (Xvfb is not installed: windows may appear there)";
      } else {
        throw Error(std::string(currentDisplay.empty() ? "no X display ($DISPLAY is not set)"
                                                       : "cannot open the X display '" + currentDisplay + "'") +
                    " and Xvfb is not installed: rendering needs an X server (VTK and Qt use GLX). Install it "
                    "(Debian/Ubuntu: sudo apt-get install xvfb xauth) or run the command under `xvfb-run -a`.");
      }
    } else {
      status.display = startXvfb(xvfb);
      status.privateServer = true;
      status.description = "private X server " + xvfb + " on " + status.display + " (" +
                           (currentDisplay.empty() ? std::string("$DISPLAY was not set")
                            : currentWorks ? std::string("offscreen requested")
                                           : "cannot open $DISPLAY '" + currentDisplay + "'") +
                           ")";
      setenv("DISPLAY", status.display.c_str(), 1);
    }
  }
  established = status;
  return status;
}

void stopPrivateXServer() {
  if (privateServerPid <= 0) return;
  if (sharedConnection) {
    XCloseDisplay(sharedConnection);
    sharedConnection = nullptr;
  }
  kill(privateServerPid, SIGTERM);
  waitpid(privateServerPid, nullptr, 0);
  privateServerPid = -1;
  if (established && established->privateServer) established.reset();
}

}  // namespace tissuemosaic
