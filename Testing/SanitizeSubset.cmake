# The sanitizer build's CI subset: ctest label "sanitize" (docs/TESTING.md, Resources/scripts/run-sanitize-tests.sh).
# Included at the end of Testing/Engine/CMakeLists.txt and Testing/Cli/CMakeLists.txt: it labels that folder's
# entries. CI builds only TissueMosaicEngineTests and tissuemosaic for it, without the GUI, so entries that need
# another binary stay out. Chosen for what outside input and the CPU pipeline reach, within a few minutes under ASan.

if(CMAKE_CURRENT_SOURCE_DIR STREQUAL "${PROJECT_SOURCE_DIR}/Testing/Engine")
  # gtest suites (the discovered tests exist only at test time): one entry per group, run with a filter. Only in the
  # sanitizer build; the plain build runs the same tests through discovery.
  if(TISSUEMOSAIC_SANITIZE)
    set(groups
      readers "ImageFile.*:DisparityPfm.*:PointCloudPly.*:PixelFormat.*:StereoFrameSource.*:StereoVideoLayout.*:TrajectoryTumReader.*:TrajectoryError.*"
      parameters "ParameterFiles.*:FusionParameters.*:RefinementParameters.*:TrackingParameters.*:ReconstructionParameters.*"
      calibration "CalibrationLayouts.*:StereoRig.*:StereoRigModes.*:PinholeIntrinsics.*"
      atomic_files "AtomicFile.*"
      stereo "StereoStages.*:StereoAdCensus.*:SubPixelMatch.*:DisparityRange.*:LeftRightMatching.*:StereoMatcher.*"
      tracking "Orb*:HammingMatcher.*:FrameTracker.*:HistogramVoting.*:KeyFrameDecision.*:PnpSolver.*"
      fusion "PointFusion.*:SurfaceMeasurement.*")
    while(groups)
      list(POP_FRONT groups group filter)
      add_test(NAME sanitize.engine.${group} COMMAND TissueMosaicEngineTests --gtest_filter=${filter})
      # A filter that no longer names any test (a suite renamed) fails instead of passing empty.
      set_tests_properties(sanitize.engine.${group} PROPERTIES LABELS sanitize ${TM_GTEST_SKIP}
                           FAIL_REGULAR_EXPRESSION "Running 0 tests")
    endwhile()
  endif()
elseif(CMAKE_CURRENT_SOURCE_DIR STREQUAL "${PROJECT_SOURCE_DIR}/Testing/Cli")
  # Bad input of every kind, the atomic outputs, and one good run of stereo, track and reconstruct.
  set(cli_subset "^cli\\.(bad\\..*|atomic_outputs|params\\..*|stereo\\.(good_pair|read_back|ad_census)|track\\.synthetic_scan|reconstruct\\.synthetic_scan)$")
  get_property(cli_tests DIRECTORY PROPERTY TESTS)
  foreach(test IN LISTS cli_tests)
    if(test MATCHES "${cli_subset}")
      set_property(TEST ${test} APPEND PROPERTY LABELS sanitize)
    endif()
  endforeach()
endif()
