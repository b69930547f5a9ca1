# libnclink.so exports the SDK API and nothing else: every defined dynamic
# symbol demangles into the nclink namespace, and none into a detail
# namespace (include/nclink/export.hpp, cmake/libnclink.map), or is a
# function of the C embedding API (include/nclink/nclink.h: nclink_*).
#   cmake -DLIB=<libnclink.so> -P exported_symbols.cmake
execute_process(COMMAND nm -D --defined-only -C ${LIB} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${LIB}: ${err}")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(bad "")
set(count 0)
foreach(line IN LISTS lines)
  if(line STREQUAL "")
    continue()
  endif()
  string(REGEX REPLACE "^[0-9a-f]* *[A-Za-z] " "" symbol "${line}")
  math(EXPR count "${count} + 1")
  if(symbol MATCHES "^nclink_[a-z_]+$")
    continue()  # nclink.h
  endif()
  if(symbol MATCHES "detail::" OR NOT symbol MATCHES "nclink::")
    string(APPEND bad "  ${symbol}\n")
  endif()
endforeach()
if(count LESS 50)
  message(FATAL_ERROR "only ${count} exported symbols: is the API exported at all?")
endif()
if(bad)
  message(FATAL_ERROR "libnclink.so exports symbols that are not SDK API:\n${bad}")
endif()
message(STATUS "${count} exported symbols, all nclink API")
