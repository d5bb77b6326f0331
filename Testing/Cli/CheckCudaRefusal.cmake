# With the CUDA backend built: on a machine without a GPU, --device cuda must fail with the reason (exit != 0);
# with a GPU it must succeed.
execute_process(COMMAND nvidia-smi -L RESULT_VARIABLE no_gpu OUTPUT_QUIET ERROR_QUIET)
execute_process(COMMAND ${CLI} stereo --left ${WORK}/pair/left.png --right ${WORK}/pair/right.png --out ${WORK}/cuda.pfm
                --device cuda RESULT_VARIABLE status ERROR_VARIABLE stderr OUTPUT_QUIET)
if(no_gpu)
  if(status EQUAL 0 OR NOT stderr MATCHES "CUDA")
    message(FATAL_ERROR "--device cuda without a GPU: exit ${status}, stderr: ${stderr}")
  endif()
  message(STATUS "refused as expected: ${stderr}")
elseif(NOT status EQUAL 0)
  message(FATAL_ERROR "--device cuda on a GPU machine failed: ${stderr}")
endif()
