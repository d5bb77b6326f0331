# cmake -DCLI=tissuemosaic -DSCAN=dir -P CheckDeformationOutputs.cmake
# Reconstructs the breathing scan in SCAN (a still scope, made by cli.reconstruct.deformation.setup) with
# --deformation on, --deformation-out and --quality-json, and checks the contracts of docs/DEFORMATION.md: one JSON
# line per fitted frame with "frame", "time_s" and "nodes" of nine numbers each, node count never falling; the
# quality records' "deformation_mean_mm", "deformation_max_mm", "live_share_within_1mm", "rigid_share_within_1mm":
# null on the first frame, numbers on every later tracked frame; --canonical-out's PLY; --live-out's model: the
# model at rest (--out) moved where the tissue is at the end, point for point (the engine test
# DeformationPipeline.FollowsBreathingTissueAndFusesIt measures both against the truth).
set(record "${SCAN}/deformation.jsonl")
set(quality "${SCAN}/deformation_quality.json")
file(REMOVE "${record}" "${quality}")
file(REMOVE_RECURSE "${SCAN}/live")
foreach(mode on off)
  execute_process(COMMAND "${CLI}" reconstruct --left-frames "${SCAN}/left" --right-frames "${SCAN}/right"
                          --calib "${SCAN}/rig.yml" --rectified --device cpu --quiet --out "${SCAN}/model_${mode}.ply"
                          --deformation ${mode} --quality-json "${SCAN}/quality_${mode}.json"
                  RESULT_VARIABLE status ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "reconstruct --deformation ${mode} failed (${status}): ${err}")
  endif()
endforeach()
execute_process(COMMAND "${CLI}" reconstruct --left-frames "${SCAN}/left" --right-frames "${SCAN}/right"
                        --calib "${SCAN}/rig.yml" --rectified --device cpu --quiet --out "${SCAN}/model_record.ply"
                        --deformation on --deformation-out "${record}" --quality-json "${quality}"
                        --canonical-out "${SCAN}/canonical.ply" --live-out "${SCAN}/live_record.ply"
                        --live-frames "${SCAN}/live" --live-every 5
                RESULT_VARIABLE status ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "reconstruct --deformation-out failed (${status}): ${err}")
endif()
# The live model: as many points as the model at rest, elsewhere (the tissue breathed).
file(READ "${SCAN}/model_record.ply" rest_header LIMIT 400)
file(READ "${SCAN}/live_record.ply" live_header LIMIT 400)
string(REGEX MATCH "element vertex [0-9]+" rest_count "${rest_header}")
string(REGEX MATCH "element vertex [0-9]+" live_count "${live_header}")
if(NOT rest_count OR NOT rest_count STREQUAL live_count)
  message(FATAL_ERROR "--live-out holds '${live_count}', the model at rest '${rest_count}'")
endif()
# --live-frames: live_NNNNNN.ply every 5th frame of the 12, the last of them the model where the tissue was then.
file(GLOB live_frames RELATIVE "${SCAN}/live" "${SCAN}/live/*.ply")
list(SORT live_frames)
if(NOT live_frames STREQUAL "live_000000.ply;live_000005.ply;live_000010.ply")
  message(FATAL_ERROR "--live-frames wrote '${live_frames}', expected live_000000.ply;live_000005.ply;live_000010.ply")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" -E compare_files "${SCAN}/model_record.ply" "${SCAN}/live_record.ply"
                RESULT_VARIABLE live_differs)
if(NOT live_differs)
  message(FATAL_ERROR "--live-out is the model at rest: the breathing tissue did not move it")
endif()

file(STRINGS "${record}" lines)
list(LENGTH lines line_count)
file(READ "${quality}" q)
string(JSON records LENGTH "${q}")
math(EXPR expected_lines "${records} - 1")  # every frame but the first (no graph yet) is tracked and fitted here
if(NOT line_count EQUAL expected_lines)
  message(FATAL_ERROR "${line_count} deformation lines for ${records} frames (expected ${expected_lines})")
endif()
set(previous_nodes 0)
set(previous_frame 0)
foreach(line IN LISTS lines)
  string(JSON frame GET "${line}" frame)
  string(JSON time GET "${line}" time_s)
  string(JSON nodes LENGTH "${line}" nodes)
  string(JSON values LENGTH "${line}" nodes 0)
  if(NOT frame GREATER previous_frame OR nodes LESS previous_nodes OR nodes LESS 1 OR NOT values EQUAL 9)
    message(FATAL_ERROR "bad deformation line (frame ${frame} after ${previous_frame}, ${nodes} nodes after "
                        "${previous_nodes}, ${values} values a node): ${line}")
  endif()
  set(previous_frame ${frame})
  set(previous_nodes ${nodes})
endforeach()

math(EXPR last_record "${records} - 1")
foreach(i RANGE ${last_record})
  foreach(key deformation_mean_mm deformation_max_mm live_share_within_1mm rigid_share_within_1mm)
    string(JSON type TYPE "${q}" ${i} ${key})
    if(i EQUAL 0 AND NOT type STREQUAL "NULL")
      message(FATAL_ERROR "frame 0: ${key} should be null (nothing to deform yet), is ${type}")
    elseif(i GREATER 0 AND NOT type STREQUAL "NUMBER")
      message(FATAL_ERROR "frame ${i}: ${key} should be a number, is ${type}")
    endif()
  endforeach()
endforeach()
file(READ "${SCAN}/quality_off.json" q_off)
string(JSON off_type TYPE "${q_off}" 1 deformation_max_mm)
if(NOT off_type STREQUAL "NULL")
  message(FATAL_ERROR "with --deformation off the deformation figures should be null")
endif()
# --canonical-out: a PLY of the samples with normals.
file(READ "${SCAN}/canonical.ply" header LIMIT 600)
if(NOT header MATCHES "element vertex ([0-9]+)" OR CMAKE_MATCH_1 LESS 100 OR NOT header MATCHES "property float nx")
  message(FATAL_ERROR "--canonical-out wrote no PLY of 100 samples or more with normals: ${header}")
endif()
message(STATUS "ok: ${line_count} deformation lines, ${previous_nodes} nodes at the end; live model of ${live_count}")
