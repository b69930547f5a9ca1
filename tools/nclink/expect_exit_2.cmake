# `nclink validate` without a file is a usage error: exit status 2, not 1.
execute_process(COMMAND ${CLI} validate RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "expected exit status 2, got ${rc}")
endif()
execute_process(COMMAND ${CLI} no-such-command RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "expected exit status 2 for an unknown command, got ${rc}")
endif()
