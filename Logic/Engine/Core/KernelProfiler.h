#pragma once
/// @file KernelProfiler.h
/// @brief Optional per-kernel timing for performance work: with the environment variable TM_PROFILE_KERNELS=1,
/// every parallelFor (CPU or CUDA) and the hand-written kernels are timed (CUDA launches synchronised), and report() lists the total
/// milliseconds per kernel. Off by default: it costs one getenv at start-up and one branch per launch.
#include <chrono>
#include <string>

namespace tissuemosaic::profiling {

bool enabled();
/// Adds one timed call of `kernel` (a type or kernel name).
void record(const std::string& kernel, double milliseconds);
/// Per kernel: calls and total milliseconds, slowest first; empty when profiling is off.
std::string report();
void reset();

}  // namespace tissuemosaic::profiling
