# Usage errors and an unusable broker exit with status 2 (1 is kept for "fail").
execute_process(COMMAND ${CONFORM} --device x RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "missing --broker: expected exit status 2, got ${rc}")
endif()
execute_process(COMMAND ${CONFORM} --broker tcp://127.0.0.1:9 --device x --bogus RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "unknown option: expected exit status 2, got ${rc}")
endif()
execute_process(COMMAND ${CONFORM} --broker tcp://127.0.0.1:9 --device x --timeout-ms 200
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET TIMEOUT 30)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "unreachable broker: expected exit status 2, got ${rc}")
endif()
