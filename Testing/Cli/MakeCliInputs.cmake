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
# Reliability inputs (issue 32): a JPEG cut short, parameters files with a misspelt key or node, an empty one.
execute_process(COMMAND ${CLI} stereo --left ${WORK}/pair/left.png --right ${WORK}/pair/right.png --out ${WORK}/jpeg.pfm
                        --rectified-left ${WORK}/left.jpg --device cpu --min-disparity 10 --max-disparity 40
                RESULT_VARIABLE status OUTPUT_QUIET)
execute_process(COMMAND head -c 4000 ${WORK}/left.jpg OUTPUT_FILE ${WORK}/truncated.jpg RESULT_VARIABLE cut)
if(NOT status EQUAL 0 OR NOT cut EQUAL 0)
  message(FATAL_ERROR "cannot make the truncated JPEG (${status}, ${cut})")
endif()
file(WRITE ${WORK}/params-typo-key.yml "%YAML:1.0\n---\nstereo:\n   znccWindw: 9\n")
file(WRITE ${WORK}/params-typo-node.yml "%YAML:1.0\n---\nfusoin:\n   maxPoints: 5\n")
file(WRITE ${WORK}/params-empty.yml "")
file(WRITE ${WORK}/params-comment-only.yml "%YAML:1.0\n---\n# nothing here\n")
file(WRITE ${WORK}/garbage.stl "this is not an STL file, only a few words that no reader can take for triangles\n")
