#pragma once
/// @file KernelProfiler.h
/// @brief Optional per-kernel timing for performance work: with the environment variable TM_PROFILE_KERNELS=1,
/// every parallelFor (CPU or CUDA) and the hand-written kernels are timed (CUDA launches synchronised), and report() lists the total
/// milliseconds per kernel. TM_PROFILE_KERNELS=host times only the host sections and the CPU parallelFor loops, with
/// no synchronisation, so that they are timed as they overlap in the undisturbed pipeline. Off by default: it costs
/// one getenv at start-up and one branch per launch.
#include <chrono>
#include <string>

namespace tissuemosaic::profiling {

bool enabled();
/// True when timing synchronises the device at each timed launch (TM_PROFILE_KERNELS set, and not to "host").
bool synchronisingLaunches();
/// Adds one timed call of `kernel` (a type or kernel name).
void record(const std::string& kernel, double milliseconds);
/// Per kernel: calls and total milliseconds, slowest first; empty when profiling is off.
std::string report();
/// What report() lists, for its heading: which setting, and whether launches were synchronised.
std::string reportKind();
void reset();

/// Records the wall time of a host section (from construction to destruction) under `name` when profiling is on;
/// costs one branch when it is off.
/// With `synchronize` (e.g. cuda::synchronize around a kernel launch), the calling thread's device work is waited for at both ends, so
/// that the section's time is the device work it started; such a section is not timed under TM_PROFILE_KERNELS=host.
class ScopedTimer {
public:
  explicit ScopedTimer(const char* name, void (*synchronize)() = nullptr)
      : name_(name), on_(synchronize ? synchronisingLaunches() : enabled()), synchronize_(synchronize) {
    if (!on_) return;
    if (synchronize_) synchronize_();
    start_ = std::chrono::steady_clock::now();
  }
  ~ScopedTimer() {
    if (!on_) return;
    if (synchronize_) synchronize_();
    record(name_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

private:
  const char* name_;
  bool on_;
  void (*synchronize_)();
  std::chrono::steady_clock::time_point start_;
};

}  // namespace tissuemosaic::profiling
