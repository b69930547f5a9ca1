# `nclink model new` writes a model that passes `nclink validate --strict`
# (no problem at all), for each kind and a few flag combinations.
# NAME|ARG ARG ... (a space between arguments: a ';' would split the case
# itself, since every quoted element of `cases` is already a list element).
set(cases
  "lathe|--kind lathe"
  "lathe-3ch|--kind lathe --axes X,Z,C --spindles 2 --channels 3"
  "mc|--kind machining-center --axes X,Y,Z,A,C"
  "generic|--kind generic"
  "generic-axes|--kind generic --axes X,Y --spindles 1 --channels 0")
foreach(case IN LISTS cases)
  string(REPLACE "|" " " parts "${case}")
  separate_arguments(parts UNIX_COMMAND "${parts}")
  list(GET parts 0 name)
  list(REMOVE_AT parts 0)
  set(file ${WORK}/${name}.json)
  execute_process(COMMAND ${CLI} model new ${parts} --id ${name} -o ${file} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "nclink model new ${parts} failed (${rc}): ${err}")
  endif()
  execute_process(COMMAND ${CLI} validate --strict ${file} RESULT_VARIABLE rc OUTPUT_VARIABLE out)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "0 fatal, 0 conformance, 0 warnings")
    message(FATAL_ERROR "starter model ${name} does not validate cleanly:\n${out}")
  endif()
endforeach()
execute_process(COMMAND ${CLI} model new --kind lathe --axes X,Q RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "not a table 9 number")
  message(FATAL_ERROR "a bad axis should be a usage error naming table 9, got ${rc}: ${err}")
endif()
