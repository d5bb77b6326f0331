# The public data sets' own layouts as inputs (issue 55, docs/INPUT.md): SCARED key-frame folders, rectified Hamlyn
# sequences, StereoMIS side-by-side videos. Fixtures made by the test from a synthetic scan (no data committed);
# each layout's run must equal, byte for byte, the run with the plain options it stands for, and each missing part
# is a clear error. Included by CMakeLists.txt (${cli}, ${work}, ${expect}).
add_executable(tm-make-dataset-layouts MakeDatasetLayouts.cpp)
target_link_libraries(tm-make-dataset-layouts PRIVATE TissueMosaicEngine)
set(datasets ${CMAKE_CURRENT_BINARY_DIR}/datasets)
set(same ${CMAKE_CURRENT_SOURCE_DIR}/same-model.sh)

add_test(NAME cli.dataset.setup
         COMMAND sh -c "set -e; rm -rf \"$2\"; \"$1\" synth scan --out \"$2/scan\" --frames 12 --width 320 --height 240 --seed 5 > /dev/null; \"$3\" \"$2/scan\" \"$2\""
                 setup ${cli} ${datasets} $<TARGET_FILE:tm-make-dataset-layouts>)
set_tests_properties(cli.dataset.setup PROPERTIES FIXTURES_SETUP cli_datasets LABELS "cli;dataset")

# same-model.sh CLI DIR NAME 'OPTIONS A' 'OPTIONS B' [differ]: two reconstructs, the same model (or, with differ,
# not: the control that the comparison can fail).
add_test(NAME cli.dataset.scared
         COMMAND ${same} ${cli} ${datasets} scared "--scared scared"
                 "--video scared/data/rgb.mp4 --video-layout tb --calib scared/endoscope_calibration.yaml --start-tum scared_first_pose.txt")
add_test(NAME cli.dataset.scared_start_pose_matters
         COMMAND ${same} ${cli} ${datasets} scared_control "--scared scared"
                 "--video scared/data/rgb.mp4 --video-layout tb --calib scared/endoscope_calibration.yaml" differ)
add_test(NAME cli.dataset.stereomis
         COMMAND ${same} ${cli} ${datasets} stereomis "--stereomis stereomis"
                 "--video stereomis/sequence.mp4 --calib scan/rig.yml")
add_test(NAME cli.dataset.stereomis_video
         COMMAND ${same} ${cli} ${datasets} stereomis_video "--stereomis stereomis/sequence.mp4"
                 "--video stereomis/sequence.mp4 --calib stereomis/StereoCalibration.ini")
add_test(NAME cli.dataset.hamlyn
         COMMAND sh -c "exec \"$1\" \"$2\" \"$3\" hamlyn \"--hamlyn hamlyn/rectified01 --baseline-mm $(sed -n 's/.*--baseline-mm //p' \"$3/hamlyn_options.txt\")\" \"--left-frames scan/left --right-frames scan/right $(cat \"$3/hamlyn_options.txt\")\""
                 hamlyn ${same} ${cli} ${datasets})
# SCARED's poses are the ground truth of track: the synthetic scan's own trajectory, so the error is the tracker's
# on a lossy MPEG-4 video. Measured 2026-11-28: RMS 0.651 mm over 12 frames; twice that lies beyond the requirement
# (1 mm, as cli.track's), which binds.
tm_output_test(NAME cli.dataset.scared_track_groundtruth
               MATCH "absolute trajectory error \\(no alignment, 12 frames\\)"
               BOUND "ATE mm (requirement <= 1.0)~absolute trajectory error [^:]*: RMS ([0-9.]+) mm~0~1.0"
               COMMAND ${cli} track --scared ${datasets}/scared --device cpu --out ${datasets}/scared_track.txt)
set_tests_properties(cli.dataset.scared cli.dataset.scared_start_pose_matters cli.dataset.stereomis
                     cli.dataset.stereomis_video cli.dataset.hamlyn cli.dataset.scared_track_groundtruth
                     PROPERTIES FIXTURES_REQUIRED cli_datasets LABELS "cli;dataset")

function(tm_dataset_failure name status regex)
  add_test(NAME cli.dataset.bad.${name} COMMAND ${expect} "${regex}" ${cli} ${ARGN})
  set_tests_properties(cli.dataset.bad.${name} PROPERTIES FIXTURES_REQUIRED cli_datasets LABELS "cli;dataset"
                       ENVIRONMENT EXPECT_STATUS=${status})
endfunction()
set(out --out ${datasets}/bad.ply)
tm_dataset_failure(scared_missing 1 "SCARED key-frame folder '.*/nothing' does not exist"
                   reconstruct --scared ${datasets}/nothing ${out})
tm_dataset_failure(scared_no_video 1 "SCARED key-frame folder '.*/stereomis': the calibration '.*endoscope_calibration.yaml' is missing"
                   reconstruct --scared ${datasets}/stereomis ${out})
tm_dataset_failure(scared_with_calib 2 "--scared gives the geometry from the data set's own files: leave out --calib"
                   reconstruct --scared ${datasets}/scared --calib ${datasets}/scan/rig.yml ${out})
tm_dataset_failure(scared_and_video 2 "give exactly one input: --scared, --hamlyn and --stereomis are inputs themselves"
                   reconstruct --scared ${datasets}/scared --video ${datasets}/stereomis/sequence.mp4 ${out})
tm_dataset_failure(hamlyn_no_baseline 2 "--hamlyn '.*': its intrinsics.txt holds no baseline: give --baseline-mm"
                   reconstruct --hamlyn ${datasets}/hamlyn/rectified01 ${out})
tm_dataset_failure(hamlyn_no_frames 1 "Hamlyn folder '.*/scared': the frame folder '.*image01' is missing"
                   reconstruct --hamlyn ${datasets}/scared --baseline-mm 5 ${out})
tm_dataset_failure(stereomis_no_calibration 1 "StereoMIS sequence '.*/scared/data/rgb.mp4': '.*StereoCalibration.ini' is missing"
                   reconstruct --stereomis ${datasets}/scared/data/rgb.mp4 ${out})
tm_dataset_failure(stereomis_no_video 1 "StereoMIS folder '.*/scan' holds no video"
                   reconstruct --stereomis ${datasets}/scan ${out})
tm_dataset_failure(baseline_alone 2 "--baseline-mm needs --focal-px \\(or --hamlyn"
                   reconstruct --left-frames ${datasets}/scan/left --right-frames ${datasets}/scan/right --baseline-mm 5 ${out})
