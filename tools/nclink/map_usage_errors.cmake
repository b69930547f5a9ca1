# `nclink map` usage errors exit 2 (not 1), --help exits 0.
foreach(args "map" "map mtconnect" "map xml MODEL" "map mtconnect MODEL --profile cnc"
             "map opcua MODEL --profile fancy" "map opcua MODEL --bogus" "map opcua A B"
             "map opcua MODEL --device")
  separate_arguments(argv UNIX_COMMAND "${args}")
  execute_process(COMMAND ${CLI} ${argv} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "nclink ${args}: expected exit status 2, got ${rc}")
  endif()
endforeach()
execute_process(COMMAND ${CLI} map --help RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_QUIET)
if(NOT rc EQUAL 0 OR NOT out MATCHES "usage: nclink map")
  message(FATAL_ERROR "nclink map --help: expected usage and exit 0, got ${rc}")
endif()
