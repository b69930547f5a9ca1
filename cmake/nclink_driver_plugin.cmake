# nclink_driver_plugin(TARGET name LIBRARY lib SOURCE file OUTPUT_NAME out COMPONENT component)
#
# A driver plugin (include/nclink/driver_plugin.h) shipped with nclink:
# lib/OUT.so, a MODULE built from SOURCE (the plugin's entry point) and the
# driver's static library LIB, installed into nclink's directory of driver
# plugins (/usr/lib/<multiarch>/nclink/drivers) as part of COMPONENT, the
# package that carries it (cmake/nclink_packaging.cmake).
#
# Why every plugin is linked this way: it carries its own copy of the static
# nclink (the model engine, values), and --exclude-libs,ALL keeps every symbol
# of the linked archives local, so that copy can never interpose on (or be
# interposed by) the host's nclink; hidden visibility leaves the entry point
# (nclink_driver_entry) as the plugin's only export.
function(nclink_driver_plugin)
  cmake_parse_arguments(P "" "TARGET;LIBRARY;SOURCE;OUTPUT_NAME;COMPONENT" "" ${ARGN})
  foreach(arg TARGET LIBRARY SOURCE OUTPUT_NAME COMPONENT)
    if(NOT P_${arg})
      message(FATAL_ERROR "nclink_driver_plugin: ${arg} is required")
    endif()
  endforeach()
  add_library(${P_TARGET} MODULE ${P_SOURCE})
  target_link_libraries(${P_TARGET} PRIVATE ${P_LIBRARY} nclink_flags)
  target_link_options(${P_TARGET} PRIVATE -Wl,--exclude-libs,ALL -Wl,--as-needed)
  set_target_properties(${P_TARGET} PROPERTIES
    PREFIX "" OUTPUT_NAME ${P_OUTPUT_NAME}
    LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/lib
    CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  install(TARGETS ${P_TARGET} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/nclink/drivers COMPONENT ${P_COMPONENT})
endfunction()
