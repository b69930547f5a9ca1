# A copy of src/ and include/ with one upward include planted (sampling ->
# adapter): tools/check-layers.sh must fail and name it. Proves the layer
# check is not a check that cannot fail.
#   cmake -DSOURCE=<project> -DWORK=<scratch> -P planted_upward_include.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(COPY ${SOURCE}/src ${SOURCE}/include DESTINATION ${WORK})
file(APPEND ${WORK}/src/sampling/uploader.cpp "\n#include \"adapter/model_host.hpp\"\n")
execute_process(COMMAND bash ${SOURCE}/tools/check-layers.sh ${WORK}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(REMOVE_RECURSE ${WORK})
if(rc EQUAL 0)
  message(FATAL_ERROR "check-layers passed a tree with an upward include:\n${out}${err}")
endif()
if(NOT out MATCHES "src/sampling/uploader.cpp:[0-9]+: sampling includes adapter/model_host.hpp")
  message(FATAL_ERROR "check-layers failed, but did not name the planted include:\n${out}${err}")
endif()
message(STATUS "planted include caught: ${out}")
