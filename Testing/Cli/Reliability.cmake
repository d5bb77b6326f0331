# Issue 32: bad input answered by a clear message and a non-zero exit (each case of the issue's list), atomic
# outputs, stops on a signal that write what they have, and strict parameters files. Included by CMakeLists.txt
# (its ${cli}, ${work}, ${pair}, ${scan_frames}, tm_cli_failure and tm_cli_usage_error).

# Item 1 (BAD): a JPEG cut short is an error, not a half-grey image with libjpeg's warning.
tm_cli_failure(truncated_jpeg "cannot read image '.*truncated.jpg': the JPEG file is truncated"
               stereo --left ${work}/truncated.jpg --right ${work}/left.jpg --out ${work}/bad.pfm --device cpu)
# WEAK: a disparity range beyond the image is named (it gave 0 % and exit 0).
tm_cli_failure(range_beyond_image "the disparity range 400..500 px lies beyond the 320-pixel-wide frames"
               stereo ${pair} --device cpu --min-disparity 400 --max-disparity 500)
# WEAK: --out a folder is named as a folder; a missing folder before any work.
tm_cli_failure(out_is_folder "cannot write PFM '.*pair': it is a folder"
               stereo --left ${work}/pair/left.png --right ${work}/pair/right.png --out ${work}/pair --device cpu)
tm_cli_failure(secondary_output_missing_folder "cannot write trajectory \\(--trajectory\\) '.*/missing/k.txt': the folder"
               reconstruct ${scan_frames} --calib ${work}/scan/rig.yml --rectified --out ${work}/m.ply
               --trajectory ${work}/missing/k.txt)
# WEAK: a frame rate and a principal point far out of range.
tm_cli_usage_error(fps_tiny "--fps: must be a number of frames per second within \\[0.01, 10000\\], got '1e-300'"
                   track ${scan_frames} --calib ${work}/scan/rig.yml --rectified --fps 1e-300 --out ${work}/t.txt)
tm_cli_failure(cx_far_outside "error: --cx-px: the principal point's x -1e\\+09 px lies far outside the 480-pixel-wide frames"
               track ${scan_frames} --focal-px 500 --baseline-mm 5 --cx-px -1e9 --out ${work}/t.txt)
tm_cli_failure(max_frames_negative "--max-frames must be positive"
               reconstruct ${scan_frames} --calib ${work}/scan/rig.yml --rectified --max-frames -1 --out ${work}/m.ply)
# WEAK: a video file that is empty or text says so once, without OpenCV's backend noise.
add_test(NAME cli.bad.empty_video_setup COMMAND ${CMAKE_COMMAND} -E touch ${work}/empty.mp4)
set_tests_properties(cli.bad.empty_video_setup PROPERTIES FIXTURES_SETUP cli_empty_video FIXTURES_REQUIRED cli_inputs
                     LABELS cli)
# The whole output is the one error line: nothing from OpenCV, FFmpeg or GStreamer before it.
tm_output_test(NAME cli.bad.empty_video STATUS 1
               MATCH "^tissuemosaic track: error: cannot open video '[^'\n]*empty.mp4': the file is empty\n$"
               COMMAND ${cli} track --video ${work}/empty.mp4 --calib ${work}/scan/rig.yml --out ${work}/t.txt)
set_tests_properties(cli.bad.empty_video PROPERTIES FIXTURES_REQUIRED "cli_inputs;cli_scan;cli_empty_video" LABELS cli)
tm_output_test(NAME cli.bad.text_video STATUS 1
               MATCH "^tissuemosaic reconstruct: error: cannot open video '[^'\n]*corrupt.mp4': not a readable video \\(corrupt or unsupported codec\\)\n$"
               COMMAND ${cli} reconstruct --video ${work}/corrupt.mp4 --calib ${work}/scan/rig.yml --out ${work}/m.ply)
set_tests_properties(cli.bad.text_video PROPERTIES LABELS cli)
foreach(name range_beyond_image out_is_folder truncated_jpeg)
  set_tests_properties(cli.bad.${name} PROPERTIES FIXTURES_REQUIRED cli_inputs)
endforeach()
foreach(name secondary_output_missing_folder fps_tiny cx_far_outside max_frames_negative text_video)
  set_tests_properties(cli.bad.${name} PROPERTIES FIXTURES_REQUIRED "cli_inputs;cli_scan")
endforeach()

# Item 3: parameters files are strict, and every preset still loads (stereo and reconstruct both read them whole).
tm_cli_failure(params_typo_key "unknown key 'znccWindw' in node 'stereo' \\(did you mean 'znccWindowPx'\\?\\)"
               stereo ${pair} --device cpu --params ${work}/params-typo-key.yml)
tm_cli_failure(params_typo_node "unknown node 'fusoin' \\(did you mean 'fusion'\\?\\)"
               reconstruct ${scan_frames} --calib ${work}/scan/rig.yml --rectified --out ${work}/m.ply
               --params ${work}/params-typo-node.yml)
tm_cli_failure(params_typo_node_in_track "unknown node 'fusoin'"
               track ${scan_frames} --calib ${work}/scan/rig.yml --rectified --out ${work}/t.txt
               --params ${work}/params-typo-node.yml)
tm_cli_failure(params_empty "cannot read parameters file '.*params-empty.yml': the file is empty"
               stereo ${pair} --device cpu --params ${work}/params-empty.yml)
tm_cli_failure(params_comment_only "params-comment-only.yml': the file holds no parameter node"
               stereo ${pair} --device cpu --params ${work}/params-comment-only.yml)
set_tests_properties(cli.bad.params_typo_key cli.bad.params_empty cli.bad.params_comment_only PROPERTIES
                     FIXTURES_REQUIRED cli_inputs)
set_tests_properties(cli.bad.params_typo_node cli.bad.params_typo_node_in_track PROPERTIES
                     FIXTURES_REQUIRED "cli_inputs;cli_scan")
file(GLOB presets ${PROJECT_SOURCE_DIR}/Resources/Presets/*.yml)
foreach(preset ${presets})
  get_filename_component(name ${preset} NAME_WE)
  tm_output_test(NAME cli.params.preset_${name} MATCH "disparity 320x180"
                 COMMAND ${cli} stereo --left ${work}/pair/left.png --right ${work}/pair/right.png --device cpu
                         --out ${work}/preset_${name}.pfm --params ${preset} --min-disparity 10 --max-disparity 40)
  set_tests_properties(cli.params.preset_${name} PROPERTIES FIXTURES_REQUIRED cli_inputs LABELS cli)
endforeach()

# Item 2: a failed run leaves existing outputs exactly as they were (file-size limit, a missing folder, a corrupt
# frame midway); a run stopped by SIGTERM writes what it has, whole, and says so.
add_test(NAME cli.atomic_outputs COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/atomic-outputs.sh ${cli} ${work})
set_tests_properties(cli.atomic_outputs PROPERTIES FIXTURES_REQUIRED "cli_inputs;cli_scan" LABELS cli
                     PASS_REGULAR_EXPRESSION "atomic outputs: PASS" TIMEOUT 300)
add_test(NAME cli.stop_on_signal COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/stop-on-signal.sh ${cli} ${work}/live_scan
         ${work}/stopped)
set_tests_properties(cli.stop_on_signal PROPERTIES FIXTURES_REQUIRED cli_live_scan LABELS cli
                     PASS_REGULAR_EXPRESSION "stop on signal: PASS" TIMEOUT 300)

# Item 1 (BAD): eval and register of NaN points, and a reference of degenerate faces (Testing/VtkLogic/
# TestEvaluationCli.cxx writes them).
if(TARGET TissueMosaicLogicTests)
  set(TM_EVAL_EXPECT_FILE -DEXPECT_FILE=${eval_work}/half_nan.expect)
  # Half the points NaN, the others 0.25 mm off: the NaN ones are left out and counted; the score is the others'.
  tm_eval_check(half_nan "rmse_mm:0.247:0.253,p95_mm:0.247:0.253" --model ${eval_work}/half_nan.ply ${reference})
  set(TM_EVAL_EXPECT_FILE)
  tm_eval_failure(all_nan "the model '.*all_nan.ply' has no finite point: all [0-9]+ have NaN or infinite coordinates"
                  --model ${eval_work}/all_nan.ply ${reference} --json)
  tm_eval_failure(degenerate_reference "the target model has no non-degenerate triangles: all 3 have zero area"
                  --model ${eval_work}/offset.ply --reference ${eval_work}/degenerate_reference.ply --json)
  set_tests_properties(cli.bad.eval_degenerate_reference PROPERTIES TIMEOUT 30)
  add_test(NAME cli.bad.register_all_nan COMMAND ${expect} "the model '.*all_nan.ply' has no finite point"
           ${cli} register --model ${eval_work}/all_nan.ply --target ${eval_work}/reference.ply --icp
           --out-transform ${work}/nan.tfm --report ${work}/nan.json)
  set_tests_properties(cli.bad.register_all_nan PROPERTIES FIXTURES_REQUIRED "eval_inputs;cli_inputs" LABELS "cli;logic")
endif()

# WEAK: a colour PFM as ground truth is named as such (it said "needs CV_32F maps").
add_test(NAME cli.bad.colour_pfm_setup COMMAND sh -c
         "printf 'PF\\n320 180\\n-1.0\\n' > \"$1\" && head -c 691200 /dev/zero >> \"$1\"" make-pfm ${work}/colour.pfm)
set_tests_properties(cli.bad.colour_pfm_setup PROPERTIES FIXTURES_SETUP cli_colour_pfm FIXTURES_REQUIRED cli_inputs
                     LABELS cli)
tm_cli_failure(colour_pfm_ground_truth "--ground-truth '.*colour.pfm' is a colour PFM \\('PF', 3 channels\\)"
               stereo ${pair} --device cpu --min-disparity 10 --max-disparity 40 --ground-truth ${work}/colour.pfm)
set_tests_properties(cli.bad.colour_pfm_ground_truth PROPERTIES FIXTURES_REQUIRED "cli_inputs;cli_colour_pfm")
if(TARGET TissueMosaicLogicTests)
  # WEAK: a bin width no histogram can hold (it gave "vector larger than max_size()").
  add_test(NAME cli.bad.register_tiny_bin COMMAND ${expect} "--bin-mm must be a number of mm within"
           ${cli} register --model ${eval_work}/offset.ply --target ${eval_work}/reference.ply --icp --bin-mm 1e-300
           --out-transform ${work}/bin.tfm --report ${work}/bin.json)
  set_tests_properties(cli.bad.register_tiny_bin PROPERTIES FIXTURES_REQUIRED "eval_inputs;cli_inputs" LABELS "cli;logic")
endif()
if(TARGET TissueMosaicLogicTests)
  # WEAK: a garbage STL says why in one line, without VTK's vtkInformation dump or object addresses.
  tm_output_test(NAME cli.bad.eval_garbage_stl STATUS 1 MATCH "cannot read surface model '.*garbage.stl'"
                 NO_MATCH "vtkInformation|Modified Time|Reference Count|0x[0-9a-f]"
                 COMMAND ${cli} eval --model ${eval_work}/offset.ply --reference ${work}/garbage.stl --json)
  set_tests_properties(cli.bad.eval_garbage_stl PROPERTIES FIXTURES_REQUIRED "eval_inputs;cli_inputs" LABELS "cli;logic")
endif()

# WEAK: all-black frames in track: the error says why (no feature anywhere), not only that tracking was lost.
add_test(NAME cli.bad.black_frames_setup COMMAND sh -c "mkdir -p \"$1/left\" \"$1/right\" && for i in 0 1 2; do
         for eye in left right; do { printf 'P6\\n320 180\\n255\\n'; head -c 172800 /dev/zero; } > \"$1/$eye/$i.ppm\";
         done; done" make-black ${work}/black)
set_tests_properties(cli.bad.black_frames_setup PROPERTIES FIXTURES_SETUP cli_black FIXTURES_REQUIRED cli_inputs
                     LABELS cli)
tm_cli_failure(track_black_frames "tracking was lost on every frame after the first \\(no frame has a single ORB feature"
               track --left-frames ${work}/black/left --right-frames ${work}/black/right --focal-px 300
               --baseline-mm 5 --device cpu --quiet --out ${work}/black.txt --min-disparity 0 --max-disparity 30)
# (With the automatic range, the default, the range cannot be chosen on them, and the message says why.)
tm_cli_failure(track_black_frames_auto_range "cannot choose the disparity range automatically: .*0 left-right feature matches"
               track --left-frames ${work}/black/left --right-frames ${work}/black/right --focal-px 300
               --baseline-mm 5 --device cpu --quiet --out ${work}/black.txt)
# ... and AD-Census on a black pair estimates nothing, and warns (it gave 93.8 %, every value -20).
tm_output_test(NAME cli.stereo.ad_census_black_pair
               MATCH "0 of 57600 pixels estimated \\(0.0%\\).*warning: no pixel has a disparity"
               COMMAND ${cli} stereo --left ${work}/black/left/0.ppm --right ${work}/black/right/0.ppm --device cpu
                       --method ad-census --min-disparity 0 --max-disparity 30 --out ${work}/black.pfm)
set_tests_properties(cli.bad.track_black_frames cli.bad.track_black_frames_auto_range cli.stereo.ad_census_black_pair PROPERTIES
                     FIXTURES_REQUIRED "cli_inputs;cli_black" LABELS cli)

# WEAK: a disparity bound far out of range names the parameter and its range (it said "expects an integer").
tm_cli_failure(min_disparity_huge "minDisparityPx = 2147483647 is out of range \\[-1000, 1000\\]"
               stereo ${pair} --device cpu --min-disparity 2147483647 --max-disparity 2147483647)
set_tests_properties(cli.bad.min_disparity_huge PROPERTIES FIXTURES_REQUIRED cli_inputs)
