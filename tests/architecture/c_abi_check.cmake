# The C ABI check of tools/check-c-abi.sh (docs/abi.md):
# 1. the built library's C ABI (nclink.h, driver_plugin.h) matches the
#    baseline in cmake/abi/libnclink.c.abi;
# 2. the check catches a planted field insertion: a probe library built from
#    a copy of the headers with one field inserted mid-struct into
#    nclink_driver_descriptor is reported as changed (exit 1, naming the
#    struct), while the probe built from the headers as they are matches its
#    own dump (exit 0).
#   cmake -DSOURCE=<repo> -DLIB=<libnclink.so> -DCC=<c compiler> -DWORK=<dir> -P c_abi_check.cmake
set(script ${SOURCE}/tools/check-c-abi.sh)
execute_process(COMMAND bash ${script} ${LIB} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the C ABI differs from cmake/abi/libnclink.c.abi (${rc}):\n${out}${err}\n"
                      "An intended append (docs/abi.md): tools/check-c-abi.sh --update <lib>.")
endif()
message(STATUS "${out}")

file(REMOVE_RECURSE ${WORK})
foreach(variant same planted)
  file(MAKE_DIRECTORY ${WORK}/${variant}/nclink)
  foreach(header nclink.h driver_plugin.h)
    file(READ ${SOURCE}/include/nclink/${header} text)
    if(variant STREQUAL "planted" AND header STREQUAL "driver_plugin.h")
      string(REPLACE "    uint32_t flags;\n" "    uint32_t flags;\n    uint32_t planted_field;\n" planted "${text}")
      if(planted STREQUAL text)
        message(FATAL_ERROR "could not plant a field: driver_plugin.h has no 'uint32_t flags;' line")
      endif()
      set(text "${planted}")
    endif()
    file(WRITE ${WORK}/${variant}/nclink/${header} "${text}")
  endforeach()
  execute_process(COMMAND ${CC} -std=c11 -g -O0 -shared -fPIC -fvisibility=hidden -I${WORK}/${variant}
                          ${SOURCE}/tests/architecture/c_abi_probe.c -o ${WORK}/${variant}.so
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the probe library (${variant}) did not build:\n${err}")
  endif()
endforeach()
execute_process(COMMAND bash ${script} --dump ${WORK}/same.so OUTPUT_FILE ${WORK}/same.abi RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "no dump of the probe: ${err}")
endif()
execute_process(COMMAND bash ${script} --baseline ${WORK}/same.abi ${WORK}/same.so
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the unchanged probe does not match its own dump (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND bash ${script} --baseline ${WORK}/same.abi ${WORK}/planted.so
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "a field inserted into nclink_driver_descriptor was not reported (exit ${rc}):\n${out}${err}")
endif()
if(NOT out MATCHES "nclink_driver_descriptor" OR NOT out MATCHES "planted_field")
  message(FATAL_ERROR "the report does not name the changed struct and field:\n${out}${err}")
endif()
message(STATUS "planted field insertion caught")
