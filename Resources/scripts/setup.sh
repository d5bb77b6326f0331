# shellcheck shell=bash
# Shared set-up for run-demo.sh and run-tests.sh (sourced, not run): installs the Debian 12 packages that are
# missing, configures (Release) and builds. Idempotent: a second call only rebuilds what changed.
#
# Environment (all optional):
#   TM_BUILD_DIR    build directory (default: <repo>/build)
#   TM_CMAKE_ARGS   extra configure arguments, e.g. "-DTM_WITH_CUDA=OFF" or "-DTM_WITH_GUI=OFF"
#   TM_JOBS         parallel build jobs (default: nproc)
# The CUDA backend is built when nvcc is on PATH (CMake finds it); it is optional.

TM_REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
TM_BUILD_DIR="${TM_BUILD_DIR:-$TM_REPO_ROOT/build}"
TM_JOBS="${TM_JOBS:-$(nproc)}"

TM_PACKAGES=(build-essential cmake libopencv-dev libeigen3-dev libtbb-dev libgtest-dev libvtk9-dev libvtk9-qt-dev
             nlohmann-json3-dev libcli11-dev libyaml-cpp-dev libopenigtlink-dev
             gstreamer1.0-plugins-base gstreamer1.0-plugins-good qtbase5-dev libqt5opengl5-dev xvfb xauth xdotool imagemagick
             pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module and its tests (docs/PYTHON.md)
             slurm-wlm munge)  # slurm-wlm, munge: the batch test's own one-node Slurm (docs/BATCH.md)

tm_log() { printf '\n== %s\n' "$*"; }

tm_install_missing_packages() {
  local missing=() package
  for package in "${TM_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q 'install ok installed'; then
      missing+=("$package")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#TM_PACKAGES[@]} Debian packages are installed"
    return 0
  fi
  tm_log "installing missing packages: ${missing[*]}"
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install ${missing[*]}" >&2; return 1; }
    sudo=(sudo)
  fi
  # --no-install-recommends: OpenCV alone would otherwise pull in Java.
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

tm_configure_and_build() {
  # Configure on the first run, after a configure that did not finish, or when extra arguments are given.
  if [ -n "${TM_CMAKE_ARGS:-}" ] || [ ! -f "$TM_BUILD_DIR/CMakeCache.txt" ] ||
     { [ ! -f "$TM_BUILD_DIR/Makefile" ] && [ ! -f "$TM_BUILD_DIR/build.ninja" ]; }; then
    tm_log "configuring $TM_BUILD_DIR (Release)"
    if command -v nvcc >/dev/null; then echo "setup: nvcc found: the CUDA backend will be built"; fi
    # shellcheck disable=SC2086  # TM_CMAKE_ARGS is a list of words on purpose
    cmake -S "$TM_REPO_ROOT" -B "$TM_BUILD_DIR" -DCMAKE_BUILD_TYPE=Release ${TM_CMAKE_ARGS:-}
  fi
  tm_log "building with $TM_JOBS jobs"
  # The build re-runs the configure step by itself when a CMakeLists.txt or a globbed folder changed.
  cmake --build "$TM_BUILD_DIR" -j "$TM_JOBS"
}

tm_setup() {
  tm_install_missing_packages
  tm_configure_and_build
}
