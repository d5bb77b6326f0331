# TISSUEMOSAIC_SANITIZE: AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer on the project's own
# targets; third-party libraries stay as Debian built them. How to build and run it: docs/TESTING.md.
option(TISSUEMOSAIC_SANITIZE "Build with AddressSanitizer + UndefinedBehaviorSanitizer (turns the CUDA backend off)" OFF)
if(NOT TISSUEMOSAIC_SANITIZE)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  message(FATAL_ERROR "TISSUEMOSAIC_SANITIZE needs GCC or Clang (found ${CMAKE_CXX_COMPILER_ID})")
endif()
# The CUDA runtime and ASan do not mix: cudart reserves device-visible address ranges where ASan keeps its shadow
# memory (it needs protect_shadow_gap=0) and ASan sees none of the device allocations. The CUDA paths are checked
# against the CPU paths on the GPU machine instead (label cuda).
if(TM_WITH_CUDA AND NOT TM_WITH_CUDA STREQUAL "AUTO")
  message(WARNING "TISSUEMOSAIC_SANITIZE: the CUDA backend is turned off (TM_WITH_CUDA=${TM_WITH_CUDA} ignored)")
endif()
set(TM_WITH_CUDA OFF)

# -fno-sanitize-recover: undefined behaviour ends the program like an ASan error, so that a test fails on it.
add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
add_link_options(-fsanitize=address,undefined)
message(STATUS "TissueMosaic: AddressSanitizer + UndefinedBehaviorSanitizer on")

# Every executable carries the runtime defaults (SanitizerDefaults.cpp): stop at the first error with a signal (a
# test that expects a failure must not take an ASan exit for its own), and read the suppressions of third-party
# leaks from the checked-in file. Added at the end of the configure step, when every target exists.
function(tm_sanitize_add_defaults directory)
  get_property(targets DIRECTORY ${directory} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "EXECUTABLE")
      target_sources(${target} PRIVATE ${PROJECT_BINARY_DIR}/SanitizerDefaults.cpp)
    endif()
  endforeach()
  get_property(subdirectories DIRECTORY ${directory} PROPERTY SUBDIRECTORIES)
  foreach(subdirectory IN LISTS subdirectories)
    tm_sanitize_add_defaults(${subdirectory})
  endforeach()
endfunction()
# Mesa's GL driver, kept loaded in every executable of this build (SanitizerDefaults.cpp says why). Empty where the
# machine has none: nothing is loaded then.
find_file(TM_SANITIZE_GL_DRIVER swrast_dri.so
          PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/dri /usr/lib64/dri /usr/lib/dri NO_DEFAULT_PATH
          DOC "Mesa's software GL driver, kept loaded under LeakSanitizer")
if(NOT TM_SANITIZE_GL_DRIVER)
  set(TM_SANITIZE_GL_DRIVER_PATH "")
else()
  set(TM_SANITIZE_GL_DRIVER_PATH "${TM_SANITIZE_GL_DRIVER}")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/SanitizerDefaults.cpp.in ${PROJECT_BINARY_DIR}/SanitizerDefaults.cpp @ONLY)
cmake_language(DEFER CALL tm_sanitize_add_defaults ${PROJECT_SOURCE_DIR})
