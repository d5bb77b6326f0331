# libFuzzer targets for every reader of outside input (issue 32, docs/RELIABILITY.md "Fuzzed readers").
# Clang only, in a build folder of its own (the normal build stays gcc + nvcc):
#   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DTISSUEMOSAIC_FUZZ=ON -DTM_WITH_CUDA=OFF
# Testing/Fuzz/run-fuzzers.sh does that and runs each target for a given time.
option(TISSUEMOSAIC_FUZZ "Build the libFuzzer targets of the file readers (clang; ASan + UBSan)" OFF)
if(NOT TISSUEMOSAIC_FUZZ)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "TISSUEMOSAIC_FUZZ needs clang (libFuzzer): configure a separate build folder with "
                      "CC=clang CXX=clang++ and -DTM_WITH_CUDA=OFF")
endif()
if(TM_WITH_CUDA)
  message(FATAL_ERROR "TISSUEMOSAIC_FUZZ builds the host code only: add -DTM_WITH_CUDA=OFF")
endif()
# Every library the readers live in gets coverage (fuzzer-no-link) and the sanitizers; undefined behaviour stops
# the run like a crash, so that the fuzzer keeps the input. The fuzz targets add libFuzzer's main at link time.
set(TM_FUZZ_SANITIZERS -fsanitize=address,undefined -fno-sanitize-recover=undefined)
add_compile_options($<$<COMPILE_LANGUAGE:C,CXX>:-fsanitize=fuzzer-no-link> ${TM_FUZZ_SANITIZERS}
                    -fno-omit-frame-pointer -gline-tables-only)
add_link_options(${TM_FUZZ_SANITIZERS})
enable_testing()
add_subdirectory(${PROJECT_SOURCE_DIR}/Testing/Fuzz ${PROJECT_BINARY_DIR}/Testing/Fuzz)
