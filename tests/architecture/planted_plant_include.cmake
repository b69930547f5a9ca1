# A copy of src/ and include/ in which the terminal library reaches into the
# plant library: the gateway's line of src/layers.txt names client, and
# gateway.cpp includes the client's header. The include table alone would
# allow it then; tools/check-layers.sh must still fail on the library lines
# and name both the table entry and the include (libnclink holds no plant code).
#   cmake -DSOURCE=<project> -DWORK=<scratch> -P planted_plant_include.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(COPY ${SOURCE}/src ${SOURCE}/include DESTINATION ${WORK})
file(READ ${WORK}/src/layers.txt table)
string(REGEX REPLACE "\ngateway: " "\ngateway: client " table "${table}")
file(WRITE ${WORK}/src/layers.txt "${table}")
file(APPEND ${WORK}/src/gateway/gateway.cpp "\n#include <nclink/client.hpp>\n")
execute_process(COMMAND bash ${SOURCE}/tools/check-layers.sh ${WORK}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(REMOVE_RECURSE ${WORK})
if(rc EQUAL 0)
  message(FATAL_ERROR "check-layers passed a terminal module that includes the plant library:\n${out}${err}")
endif()
if(NOT out MATCHES "src/layers.txt: gateway \\(terminal library\\) names client of the plant library")
  message(FATAL_ERROR "check-layers failed, but did not name the planted table entry:\n${out}${err}")
endif()
if(NOT out MATCHES "src/gateway/gateway.cpp:[0-9]+: gateway \\(terminal library\\) includes nclink/client.hpp of client \\(plant library\\)")
  message(FATAL_ERROR "check-layers failed, but did not name the planted include:\n${out}${err}")
endif()
message(STATUS "planted plant include caught: ${out}")
