# Inputs for the command-line tests: a small synthetic pair, a corrupt image, an image of another size and a broken
# calibration file.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
# The output names the pair's rectified geometry (for the --focal-px tests): kept in pair-synth.txt.
execute_process(COMMAND ${CLI} synth pair --out ${WORK}/pair --width 320 --height 180 --seed 3 RESULT_VARIABLE status
                OUTPUT_FILE ${WORK}/pair-synth.txt)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "tissuemosaic synth pair failed (${status})")
endif()
file(WRITE ${WORK}/corrupt.png "this is not a PNG file")
file(WRITE ${WORK}/corrupt.mp4 "this is not a video file")
file(WRITE ${WORK}/broken.yml "%YAML:1.0\nK1: [1, 2\n")
execute_process(COMMAND ${CLI} synth pair --out ${WORK}/small --width 160 --height 90 RESULT_VARIABLE status)
file(COPY_FILE ${WORK}/small/left.png ${WORK}/small.png)
