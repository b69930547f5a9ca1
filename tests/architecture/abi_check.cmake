# The ABI check of tools/check-abi.sh, run on the built library:
# 1. it is compatible with the baseline of the last release (cmake/abi/);
# 2. a planted break is caught: a baseline that exports one function more
#    than the library (= the library removed a released function) fails with
#    exit 1 and names the symbol.
#   cmake -DSOURCE=<repo> -DLIB=<libnclink.so> -DWORK=<dir> -P abi_check.cmake
set(script ${SOURCE}/tools/check-abi.sh)
execute_process(COMMAND bash ${script} ${LIB} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "check-abi against the release baseline failed (${rc}):\n${out}${err}\n"
                      "An intended change at a release: tools/check-abi.sh --update <lib> (docs/architecture.md).")
endif()
message(STATUS "${out}")

file(MAKE_DIRECTORY ${WORK})
file(READ ${SOURCE}/cmake/abi/libnclink.symbols.abi base)
set(planted_symbol "_ZN6nclink19planted_abi_removalEv")
string(FIND "${base}" "<elf-symbol " at)
if(at LESS 0)
  message(FATAL_ERROR "the baseline has no elf-symbol entries")
endif()
string(SUBSTRING "${base}" 0 ${at} head)
string(SUBSTRING "${base}" ${at} -1 tail)
file(WRITE ${WORK}/planted.abi
     "${head}<elf-symbol name='${planted_symbol}' type='func-type' binding='global-binding' visibility='default-visibility' is-defined='yes'/>\n    ${tail}")
execute_process(COMMAND bash ${script} --baseline ${WORK}/planted.abi ${LIB}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "a removed function was not reported as incompatible (exit ${rc}):\n${out}${err}")
endif()
if(NOT out MATCHES "${planted_symbol}" OR NOT err MATCHES "INCOMPATIBLE")
  message(FATAL_ERROR "the report does not name the removed symbol:\n${out}${err}")
endif()
message(STATUS "planted removal caught")
