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

# Whether `program` needs libnclink.so at run time (its DT_NEEDED entries).
function(needs_shared_nclink program out)
  find_program(READELF readelf REQUIRED)
  run(${READELF} -d ${program})
  if(LAST_OUTPUT MATCHES "libnclink\\.so")
    set(${out} TRUE PARENT_SCOPE)
  else()
    set(${out} FALSE PARENT_SCOPE)
  endif()
endfunction()

function(expect_linkage program flavour)
  needs_shared_nclink(${program} shared_needed)
  if(flavour STREQUAL "static" AND shared_needed)
    message(FATAL_ERROR "${program} was to link libnclink.a but needs libnclink.so")
  elseif(flavour STREQUAL "shared" AND NOT shared_needed)
    message(FATAL_ERROR "${program} was to link libnclink.so but does not need it")
  endif()
endfunction()

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
  expect_linkage(${bdir}/nclink_consumer ${flavour})
  message(STATUS "find_package consumer (${flavour}): ${LAST_OUTPUT}")
endforeach()

# pkg-config, as docs/building.md writes it: nclink (shared; its run path
# finds libnclink.so in the prefix without LD_LIBRARY_PATH or -rpath of our
# own) and nclink-static (libnclink.a).
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} "${prefix}/lib/pkgconfig:${prefix}/lib/x86_64-linux-gnu/pkgconfig")
set(ENV{LD_LIBRARY_PATH} "")
foreach(flavour shared static)
  if(flavour STREQUAL "static")
    run(${PKG_CONFIG} --cflags --libs --static nclink-static)
  else()
    run(${PKG_CONFIG} --cflags --libs nclink)
  endif()
  string(STRIP "${LAST_OUTPUT}" pc_flags)
  separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
  set(program ${WORK_DIR}/pc_consumer_${flavour})
  run(${CXX} -std=c++17 ${CONSUMER_SOURCE_DIR}/main.cpp -o ${program} ${pc_flags})
  run(${program})
  if(NOT LAST_OUTPUT MATCHES "Node not exists")
    message(FATAL_ERROR "pkg-config consumer (${flavour}) printed: ${LAST_OUTPUT}")
  endif()
  expect_linkage(${program} ${flavour})
  message(STATUS "pkg-config consumer (${flavour}): ${LAST_OUTPUT}")
endforeach()

# C firmware (docs/porting-guide.md, "From C firmware"): the example built by
# the C compiler alone, strict C11, with pkg-config's flags for the shared
# library; it starts its adapter (the broker is not there: it keeps trying),
# pushes from its servo thread and stops.
if(CC AND C_FIRMWARE_DIR)
  run(${PKG_CONFIG} --cflags --libs nclink)
  string(STRIP "${LAST_OUTPUT}" pc_flags)
  separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
  set(program ${WORK_DIR}/c_firmware)
  run(${CC} -std=c11 -Wall -Wextra -Werror -pedantic ${C_FIRMWARE_DIR}/main.c ${C_FIRMWARE_DIR}/machine.c
      ${C_FIRMWARE_DIR}/driver.c -o ${program} ${pc_flags} -lpthread -lm)
  expect_linkage(${program} shared)
  run(${program} --broker tcp://127.0.0.1:1 --model ${C_FIRMWARE_DIR}/model.json --seconds 1)
  if(NOT LAST_OUTPUT MATCHES "c-firmware: serving .* rows pushed, 0 refused")
    message(FATAL_ERROR "the C firmware printed: ${LAST_OUTPUT}")
  endif()
  message(STATUS "C firmware (cc + pkg-config): ${LAST_OUTPUT}")
endif()

# The template project, copied out of the installed SDK and built as-is
# (docs/porting-guide.md, "Quick start"), shared and static; then its
# adapter checks its configuration and model.
if(EXISTS ${prefix}/share/nclink/adapter-template/CMakeLists.txt)
  foreach(flavour shared static)
    set(tdir ${WORK_DIR}/my-adapter-${flavour})
    file(COPY ${prefix}/share/nclink/adapter-template/ DESTINATION ${tdir})
    if(flavour STREQUAL "static")
      set(prefer -DNCLINK_PREFER_STATIC=ON)
    else()
      set(prefer "")
    endif()
    run(${CMAKE_COMMAND} -S ${tdir} -B ${tdir}/build -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX} ${prefer})
    run(${CMAKE_COMMAND} --build ${tdir}/build)
    expect_linkage(${tdir}/build/my-adapter ${flavour})
    execute_process(COMMAND ${tdir}/build/my-adapter --config ${tdir}/adapter.json --check
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT out MATCHES "my-adapter: model .*model.json, broker tcp://127.0.0.1:1883, driver my-machine")
      message(FATAL_ERROR "the template's adapter (${flavour}) failed its check (${rc}): ${out}\n${err}")
    endif()
    message(STATUS "adapter template (${flavour}): ${out}")
  endforeach()
  # A starter model from the installed CLI validates strictly.
  run(${prefix}/bin/nclink model new --kind lathe --id acme-lathe -o ${WORK_DIR}/acme-lathe.json)
  run(${prefix}/bin/nclink validate --strict ${WORK_DIR}/acme-lathe.json)
else()
  message(FATAL_ERROR "the install has no share/nclink/adapter-template")
endif()
