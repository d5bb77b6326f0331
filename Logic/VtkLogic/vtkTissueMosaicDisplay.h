#pragma once
/// @file vtkTissueMosaicDisplay.h
/// @brief An X display for rendering on a headless machine. Debian's VTK (and Qt's xcb platform) render through
/// GLX, so even offscreen rendering needs an X server: when $DISPLAY is missing or cannot be opened, a private
/// Xvfb (Mesa's software OpenGL) is started for this process and stopped when it exits. Shared by the command
/// line (`tissuemosaic reconstruct --snapshot`) and the desktop application (`--offscreen`); no Qt here.
#include <string>

namespace tissuemosaic {

/// How ensureXDisplay found its display.
struct XDisplayStatus {
  std::string display;          ///< the value of $DISPLAY now, e.g. ":0" or ":99"
  bool privateServer = false;   ///< true: a private Xvfb this process started (and will stop)
  std::string description;      ///< one line for logs: which display, and why
};

/// True when an X connection to `display` (e.g. ":0") can be opened now.
bool canOpenXDisplay(const std::string& display);

/// Makes sure $DISPLAY names an X server this process can use and returns which. preferPrivate: start a private
/// Xvfb even when $DISPLAY works (nothing appears on the user's screen), falling back to $DISPLAY only when Xvfb
/// is not installed. Throws Error when there is no usable display and no Xvfb, saying what to install (Debian:
/// `apt-get install xvfb`) or to run under `xvfb-run -a`. Idempotent: later calls return the first result.
/// Call it before any window, render window or QApplication is created, from one thread.
XDisplayStatus ensureXDisplay(bool preferPrivate = false);

/// One connection to the display of ensureXDisplay(preferPrivate = true), opened on first use with the retries of
/// canOpenXDisplay and kept for the life of the process (Xlib's Display*). Give it to VTK render windows
/// (SetDisplayId): a window that opens its own connection aborts the process when the server refuses it. Throws
/// Error when the display cannot be opened. Not for use from several threads at once.
void* sharedXConnection();

/// Stops the private Xvfb, if one was started (also done automatically at exit).
void stopPrivateXServer();

}  // namespace tissuemosaic
