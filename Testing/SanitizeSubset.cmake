# The sanitizer build's CI subset: ctest label "sanitize" (docs/TESTING.md, Resources/scripts/run-sanitize-tests.sh):
# the readers of outside input (images, PFM, PLY, videos and frame folders, TUM trajectories, parameter files,
# calibration layouts and rigs, atomic files) on a library and a test driver of their own, and the OpenIGTLink fuzz
# corpora replayed (what the network links read), so that CI's 2 cores
# build and run it in a few minutes. The whole engine, logic and CLI suites under the sanitizers are the longer run
# of docs/TESTING.md. Included at the end of Testing/Engine/CMakeLists.txt.

if(TISSUEMOSAIC_SANITIZE)
  # The subset's own driver: the readers' test files only, on the readers' library (TissueMosaicReaders,
  # Logic/Engine/CMakeLists.txt), so that CI compiles about 40 files under the sanitizers instead of 150.
  set(sanitize_test_files
    TestImageFile TestDisparityPfm TestPointCloudPly TestMeshPly TestStereoFrameSource TestAtomicFile
    TestTrajectoryError TestParameterFiles TestCalibrationLayouts TestStereoRig TestPinholeIntrinsics)
  list(TRANSFORM sanitize_test_files APPEND .cpp)
  add_executable(TissueMosaicSanitizeTests ${sanitize_test_files})
  target_link_libraries(TissueMosaicSanitizeTests PRIVATE TissueMosaicReaders GTest::gtest_main)
  target_compile_definitions(TissueMosaicSanitizeTests PRIVATE TM_TEST_OUTPUT_DIR="${CMAKE_CURRENT_BINARY_DIR}/output")
  # gtest suites (the discovered tests exist only at test time): one entry per group, run with a filter. Only in
  # the sanitizer build; the plain build runs the same tests through discovery.
  set(groups
    images_and_maps "ImageFile.*:DisparityPfm.*:PointCloudPly.*:MeshPly.*"
    frames_and_trajectories "StereoFrameSource.*:TrajectoryTumReader.*:TrajectoryError.*:AtomicFile.*"
    parameters "ParameterFiles.*"
    calibration "CalibrationLayouts.*:StereoRig.*:StereoRigModes.*:PinholeIntrinsics.*")
  while(groups)
    list(POP_FRONT groups group filter)
    add_test(NAME sanitize.engine.${group} COMMAND TissueMosaicSanitizeTests --gtest_filter=${filter})
    # A filter that no longer names any test (a suite renamed) fails instead of passing empty.
    set_tests_properties(sanitize.engine.${group} PROPERTIES LABELS sanitize ${TM_GTEST_SKIP}
                         FAIL_REGULAR_EXPRESSION "Running 0 tests")
  endwhile()

  # The network readers' fuzz corpora replayed once under the sanitizers: what the OpenIGTLink client and server
  # read (issue 54). gcc has no libFuzzer: Testing/Fuzz/ReplayCorpus.cpp is their main. They need neither the
  # engine nor sockets (TissueMosaicIgtLinkReader). run-sanitize-tests.sh builds tm_sanitize_replays.
  add_custom_target(tm_sanitize_replays)
  if(TM_WITH_IGTLINK)
    set(fuzz ${PROJECT_SOURCE_DIR}/Testing/Fuzz)
    foreach(target fuzz_igtl_client fuzz_igtl_server)
      add_executable(replay_${target} ${fuzz}/${target}.cpp ${fuzz}/ReplayCorpus.cpp)
      target_include_directories(replay_${target} PRIVATE ${fuzz})
      target_link_libraries(replay_${target} PRIVATE TissueMosaicIgtLinkReader)
      add_dependencies(tm_sanitize_replays replay_${target})
      add_test(NAME sanitize.fuzz_corpus.${target} COMMAND replay_${target} ${fuzz}/corpus/${target})
      set_tests_properties(sanitize.fuzz_corpus.${target} PROPERTIES LABELS sanitize)
    endforeach()
  endif()
endif()
