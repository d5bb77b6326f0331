// libsgm-timing: libSGM's device time per pair at a given size, disparity count and path count, as JSON with the
// median, mean and p99 milliseconds (the same statistics as `tissuemosaic bench stereo`). Input and output stay on
// the device (EXECUTE_INOUT_CUDA2CUDA), as our own stage times exclude the upload: the pair is a random texture
// and the same texture shifted by a smooth disparity ramp inside the range (SGM's work does not depend on content).
#include <libsgm.h>

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) {
    std::fprintf(stderr, "libsgm-timing: %s: %s\n", what, cudaGetErrorString(status));
    std::exit(1);
  }
}

int intArgument(int argc, char** argv, const std::string& name, int fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (name == argv[i]) return std::atoi(argv[i + 1]);
  }
  return fallback;
}

double percentile(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  const std::size_t index = std::min(values.size() - 1, static_cast<std::size_t>(fraction * (values.size() - 1) + 0.5));
  return values[index];
}

}  // namespace

int main(int argc, char** argv) {
  const int width = intArgument(argc, argv, "--width", 960);
  const int height = intArgument(argc, argv, "--height", 540);
  const int disparities = intArgument(argc, argv, "--disparities", 128);
  const int paths = intArgument(argc, argv, "--paths", 4);
  const int repeats = intArgument(argc, argv, "--repeats", 100);
  if (width < 16 || height < 16 || (disparities != 64 && disparities != 128 && disparities != 256) ||
      (paths != 4 && paths != 8) || repeats < 1) {
    std::fprintf(stderr, "usage: libsgm-timing [--width W] [--height H] [--disparities 64|128|256] [--paths 4|8] "
                         "[--repeats N]\n");
    return 2;
  }

  std::mt19937 random(7);
  std::uniform_int_distribution<int> grey(0, 255);
  std::vector<uint8_t> left(static_cast<std::size_t>(width) * height), right(left.size());
  for (uint8_t& value : left) value = static_cast<uint8_t>(grey(random));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int shift = (disparities / 4) + (disparities / 2) * x / width;  // a ramp inside the range
      const int source = std::min(width - 1, x + shift);
      right[static_cast<std::size_t>(y) * width + x] = left[static_cast<std::size_t>(y) * width + source];
    }
  }

  uint8_t *leftDevice = nullptr, *rightDevice = nullptr;
  uint16_t* disparityDevice = nullptr;
  check(cudaMalloc(&leftDevice, left.size()), "cudaMalloc");
  check(cudaMalloc(&rightDevice, right.size()), "cudaMalloc");
  check(cudaMalloc(&disparityDevice, left.size() * sizeof(uint16_t)), "cudaMalloc");
  check(cudaMemcpy(leftDevice, left.data(), left.size(), cudaMemcpyHostToDevice), "upload");
  check(cudaMemcpy(rightDevice, right.data(), right.size(), cudaMemcpyHostToDevice), "upload");

  const sgm::StereoSGM::Parameters parameters(10, 120, 0.95f, false,
                                              paths == 4 ? sgm::PathType::SCAN_4PATH : sgm::PathType::SCAN_8PATH);
  sgm::StereoSGM sgm(width, height, disparities, 8, 16, sgm::EXECUTE_INOUT_CUDA2CUDA, parameters);

  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "cudaEventCreate");
  check(cudaEventCreate(&stop), "cudaEventCreate");
  for (int i = 0; i < 5; ++i) sgm.execute(leftDevice, rightDevice, disparityDevice);  // warm-up
  check(cudaDeviceSynchronize(), "warm-up");
  std::vector<double> milliseconds;
  for (int i = 0; i < repeats; ++i) {
    check(cudaEventRecord(start), "cudaEventRecord");
    sgm.execute(leftDevice, rightDevice, disparityDevice);
    check(cudaEventRecord(stop), "cudaEventRecord");
    check(cudaEventSynchronize(stop), "cudaEventSynchronize");
    float elapsed = 0;
    check(cudaEventElapsedTime(&elapsed, start, stop), "cudaEventElapsedTime");
    milliseconds.push_back(elapsed);
  }
  double sum = 0;
  for (double value : milliseconds) sum += value;
  cudaDeviceProp properties{};
  check(cudaGetDeviceProperties(&properties, 0), "cudaGetDeviceProperties");
  std::printf("{\"command\": \"libsgm-timing\", \"device\": \"%s\", \"width\": %d, \"height\": %d, "
              "\"disparities\": %d, \"paths\": %d, \"repeats\": %d, \"median_ms\": %.4f, \"mean_ms\": %.4f, "
              "\"p99_ms\": %.4f}\n",
              properties.name, width, height, disparities, paths, repeats, percentile(milliseconds, 0.5),
              sum / milliseconds.size(), percentile(milliseconds, 0.99));
  return 0;
}
