# End-to-end check of mocap-detect-bench (not of its timings): writes a small synthetic frames
# directory, benchmarks it with --json, and checks the contract keys and that our centroids
# equal the double-precision reference. Run by ctest with -DBENCH=<exe> -DDIR=<scratch dir>.
file(REMOVE_RECURSE ${DIR})
execute_process(COMMAND ${BENCH} --make-frames ${DIR} --count 4 --markers 25 --width 333
                        --height 201 --seed 3
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "--make-frames failed (${rc}): ${err}")
endif()
execute_process(COMMAND ${BENCH} --frames ${DIR} --json --repeat 1 --formats
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "--frames failed (${rc}): ${err}")
endif()
foreach(key ours_ms_per_frame read_pass_ms_per_frame opencv_ms_per_frame max_centroid_diff_px)
    if(NOT out MATCHES "\"${key}\": [0-9.e+-]+")
        message(FATAL_ERROR "JSON lacks ${key}: ${out}")
    endif()
endforeach()
string(REGEX MATCH "\"max_centroid_diff_px\": ([0-9.e+-]+)" _ "${out}")
if(CMAKE_MATCH_1 GREATER 0.01)
    message(FATAL_ERROR "centroids differ from the reference by ${CMAKE_MATCH_1} px")
endif()
string(REGEX MATCH "\"frames\": ([0-9]+)" _ "${out}")
if(NOT CMAKE_MATCH_1 EQUAL 4)
    message(FATAL_ERROR "expected 4 frames: ${out}")
endif()
string(REGEX MATCH "\"blobs_matched\": ([0-9]+)" _ "${out}")
if(CMAKE_MATCH_1 LESS 80)
    message(FATAL_ERROR "too few blobs paired with the reference: ${out}")
endif()
# --formats: a line per camera pixel format, every lossless one giving the frame's own blobs.
foreach(format GREY NV12 YU12 Y10 Y16 YUYV UYVY RGB3 BGR3 BX24 XR24)
    if(NOT out MATCHES "\"format\": \"${format}\", \"convert_ms_per_frame\": [0-9.e+-]+, \"total_ms_per_frame\": [0-9.e+-]+, \"same_blobs\": true")
        message(FATAL_ERROR "no timing with the same blobs for ${format}: ${out}")
    endif()
endforeach()
execute_process(COMMAND ${BENCH} --frames ${DIR}/missing RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "not found")
    message(FATAL_ERROR "a missing directory must fail with a reason, got ${rc}: ${err}")
endif()
file(REMOVE_RECURSE ${DIR})
