#pragma once
/// @file Stopwatch.h
/// @brief The one way the engine and its commands time a stage: wall milliseconds on the steady clock.
#include <chrono>

namespace tissuemosaic {

/// Milliseconds elapsed since `start` (std::chrono::steady_clock::now() when the stage began).
inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace tissuemosaic
