// main() for a fuzz target built without libFuzzer (gcc, the sanitizer step of run-tests.sh): runs the target once
// on every file of the folders given, as `fuzz_X -runs=0 corpus/fuzz_X` does in the fuzz build. Exit status 1 when
// a folder holds no input (a corpus gone missing must not pass); a finding aborts under the sanitizers.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  int status = argc > 1 ? 0 : 1;
  for (int a = 1; a < argc; ++a) {
    std::size_t replayed = 0;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(argv[a], error)) {
      if (!entry.is_regular_file()) continue;
      std::ifstream file(entry.path(), std::ios::binary);
      const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
      LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
      ++replayed;
    }
    std::printf("%s: %zu inputs replayed\n", argv[a], replayed);
    if (replayed == 0) status = 1;
  }
  return status;
}
