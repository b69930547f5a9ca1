# Install rules, the exported CMake package (find_package(nclink CONFIG)) and
# the pkg-config file.
include(CMakePackageConfigHelpers)

set(NCLINK_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/nclink)
set(_nclink_targets nclink_static)
if(TARGET nclink_shared)
  list(APPEND _nclink_targets nclink_shared)
endif()

install(TARGETS ${_nclink_targets}
  EXPORT nclinkTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# sim_driver.hpp belongs to the example simulator (drivers/sim), which is
# not part of the installed SDK.
install(DIRECTORY include/nclink DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN "sim_driver.hpp" EXCLUDE)
install(EXPORT nclinkTargets NAMESPACE nclink:: DESTINATION ${NCLINK_CMAKE_DIR})

configure_package_config_file(cmake/nclinkConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/nclinkConfig.cmake
  INSTALL_DESTINATION ${NCLINK_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/nclinkConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/nclinkConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/nclinkConfigVersion.cmake
        DESTINATION ${NCLINK_CMAKE_DIR})

# Relocatable: the prefix is found relative to the .pc file itself.
file(RELATIVE_PATH NCLINK_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(cmake/nclink.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink.pc @ONLY)
configure_file(cmake/nclink-static.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink-static.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/nclink.pc ${CMAKE_CURRENT_BINARY_DIR}/nclink-static.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
# The template project a vendor copies (docs/porting-guide.md).
install(DIRECTORY examples/adapter-template/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/adapter-template)

install(DIRECTORY models/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/models
        FILES_MATCHING PATTERN "*.json" PATTERN "invalid" EXCLUDE)
