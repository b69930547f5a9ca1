# Install the build tree into a scratch prefix, then build and run a program
# against it with find_package(nclink CONFIG) (shared and static) and pkg-config.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(LAST_OUTPUT "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${NCLINK_BUILD_DIR} --prefix ${prefix})

foreach(flavour shared static)
  set(bdir ${WORK_DIR}/build-${flavour})
  if(flavour STREQUAL "static")
    set(prefer -DNCLINK_PREFER_STATIC=ON)
  else()
    set(prefer "")
  endif()
  run(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${bdir} -DCMAKE_PREFIX_PATH=${prefix}
      -DCMAKE_CXX_COMPILER=${CXX} ${prefer})
  run(${CMAKE_COMMAND} --build ${bdir})
  run(${bdir}/nclink_consumer)
  if(NOT LAST_OUTPUT MATCHES "Node not exists")
    message(FATAL_ERROR "consumer (${flavour}) printed: ${LAST_OUTPUT}")
  endif()
  message(STATUS "find_package consumer (${flavour}): ${LAST_OUTPUT}")
endforeach()

# pkg-config
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} "${prefix}/lib/pkgconfig:${prefix}/lib/x86_64-linux-gnu/pkgconfig")
run(${PKG_CONFIG} --cflags --libs --static nclink)
string(STRIP "${LAST_OUTPUT}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
run(${CXX} -std=c++17 ${CONSUMER_SOURCE_DIR}/main.cpp -o ${WORK_DIR}/pc_consumer ${pc_flags}
    -Wl,-rpath,${prefix}/lib)
run(${WORK_DIR}/pc_consumer)
if(NOT LAST_OUTPUT MATCHES "Node not exists")
  message(FATAL_ERROR "pkg-config consumer printed: ${LAST_OUTPUT}")
endif()
message(STATUS "pkg-config consumer: ${LAST_OUTPUT}")
