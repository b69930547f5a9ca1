# Install rules, the exported CMake package (find_package(nclink CONFIG)) and
# the pkg-config file.
include(CMakePackageConfigHelpers)

# Every rule names its component, which is its Debian package
# (cmake/nclink_packaging.cmake): lib = the shared library, dev = what
# building against nclink needs, tools = the programs and their data.
set(NCLINK_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/nclink)

install(TARGETS nclink_static
  EXPORT nclinkTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# `--strip` (and CPack) strip programs and shared libraries only; the static
# library keeps its symbols but loses its debug information, as Debian's -dev
# packages do (a RelWithDebInfo libnclink.a is mostly DWARF).
if(CMAKE_STRIP)
  install(CODE "if(CMAKE_INSTALL_DO_STRIP)
  execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/$<TARGET_FILE_NAME:nclink_static>\")
endif()" COMPONENT dev)
endif()
if(TARGET nclink_shared)
  install(TARGETS nclink_shared
    EXPORT nclinkTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT lib NAMELINK_COMPONENT dev
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT lib
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()
# sim_driver.hpp belongs to the example simulator (drivers/sim), which is
# not part of the installed SDK.
install(DIRECTORY include/nclink DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev PATTERN "sim_driver.hpp" EXCLUDE)
install(EXPORT nclinkTargets NAMESPACE nclink:: DESTINATION ${NCLINK_CMAKE_DIR} COMPONENT dev)

configure_package_config_file(cmake/nclinkConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/nclinkConfig.cmake
  INSTALL_DESTINATION ${NCLINK_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/nclinkConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/nclinkConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/nclinkConfigVersion.cmake
        DESTINATION ${NCLINK_CMAKE_DIR} COMPONENT dev)

# Relocatable: the prefix is found relative to the .pc file itself.
file(RELATIVE_PATH NCLINK_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(cmake/nclink.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink.pc @ONLY)
configure_file(cmake/nclink-static.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink-static.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/nclink.pc ${CMAKE_CURRENT_BINARY_DIR}/nclink-static.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)
# The template project a vendor copies (docs/porting-guide.md): it builds
# against the SDK, so it ships with what building against nclink needs.
install(DIRECTORY examples/adapter-template/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/adapter-template COMPONENT dev)

install(DIRECTORY models/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/models COMPONENT tools
        FILES_MATCHING PATTERN "*.json" PATTERN "invalid" EXCLUDE)
# The configuration schemas (docs/configuration.md), for editors and checkers.
install(DIRECTORY docs/schema/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/schema COMPONENT tools
        FILES_MATCHING PATTERN "*.schema.json")
