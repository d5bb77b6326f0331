#include "StageClock.h"

#include "CudaRuntime.h"

namespace tissuemosaic {

StageClock::StageClock(Device device) : device_(device) { mark(); }

StageClock::~StageClock() {
  for (void* event : events_) cuda::destroyEvent(event);
}

void StageClock::mark() {
  if (device_ == Device::Cuda) {
    events_.push_back(cuda::createEvent());
    cuda::recordEvent(events_.back());
  } else {
    times_.push_back(std::chrono::steady_clock::now());
  }
}

std::vector<double> StageClock::stageMilliseconds() {
  std::vector<double> stages;
  if (device_ == Device::Cuda) {
    for (std::size_t i = 1; i < events_.size(); ++i) stages.push_back(cuda::millisecondsBetween(events_[i - 1], events_[i]));
  } else {
    for (std::size_t i = 1; i < times_.size(); ++i) {
      stages.push_back(std::chrono::duration<double, std::milli>(times_[i] - times_[i - 1]).count());
    }
  }
  return stages;
}

}  // namespace tissuemosaic
