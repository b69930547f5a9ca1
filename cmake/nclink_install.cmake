# Install rules, the exported CMake package (find_package(nclink CONFIG)) and
# the pkg-config file.
include(CMakePackageConfigHelpers)

# Every rule names its component, which is its Debian package
# (cmake/nclink_packaging.cmake): lib = the terminal library libnclink.so,
# dev = what building against it needs, plant_lib / plant_dev = the same for
# the plant library libnclink-plant, tools = the programs and their data.
set(NCLINK_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/nclink)

# nclink_install_library(STATIC SHARED EXPORT DEV_COMPONENT LIB_COMPONENT):
# one library's static and (when built) shared target with its export set.
function(nclink_install_library static shared export dev lib)
  install(TARGETS ${static}
    EXPORT ${export}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${dev}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  # `--strip` (and CPack) strip programs and shared libraries only; the
  # static library keeps its symbols but loses its debug information, as
  # Debian's -dev packages do (a RelWithDebInfo libnclink.a is mostly DWARF).
  if(CMAKE_STRIP)
    install(CODE "if(CMAKE_INSTALL_DO_STRIP)
  execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/$<TARGET_FILE_NAME:${static}>\")
endif()" COMPONENT ${dev})
  endif()
  if(TARGET ${shared})
    install(TARGETS ${shared}
      EXPORT ${export}
      LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${lib} NAMELINK_COMPONENT ${dev}
      RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${lib}
      INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

nclink_install_library(nclink_static nclink_shared nclinkTargets dev lib)
# The plant library: its own components, its own export set (a file of the
# CMake package that nclinkConfig.cmake includes when it is installed).
if(TARGET nclink_plant_static)
  nclink_install_library(nclink_plant_static nclink_plant_shared nclinkPlantTargets plant_dev plant_lib)
  install(EXPORT nclinkPlantTargets NAMESPACE nclink:: DESTINATION ${NCLINK_CMAKE_DIR} COMPONENT plant_dev)
endif()

# Headers: one folder, each header in the package of the library that owns
# it (the `public` and `library` lines of src/layers.txt). sim_driver.hpp
# belongs to the example simulator (drivers/sim), which is not part of the
# installed SDK.
file(STRINGS ${PROJECT_SOURCE_DIR}/src/layers.txt _layers_plant REGEX "^library plant:")
string(REGEX REPLACE "^library plant:" "" _layers_plant "${_layers_plant}")
separate_arguments(_layers_plant)
file(STRINGS ${PROJECT_SOURCE_DIR}/src/layers.txt _layers_public REGEX "^public [a-z_]+:")
set(NCLINK_PLANT_HEADERS "")
foreach(_line IN LISTS _layers_public)
  string(REGEX MATCH "^public ([a-z_]+):(.*)$" _ "${_line}")
  if(CMAKE_MATCH_1 IN_LIST _layers_plant)
    string(STRIP "${CMAKE_MATCH_2}" _headers)
    separate_arguments(_headers)
    list(APPEND NCLINK_PLANT_HEADERS ${_headers})
  endif()
endforeach()
set(_plant_header_excludes "")
foreach(_h IN LISTS NCLINK_PLANT_HEADERS)
  list(APPEND _plant_header_excludes PATTERN ${_h} EXCLUDE)
  if(TARGET nclink_plant_static)
    get_filename_component(_sub ${_h} DIRECTORY)
    install(FILES include/nclink/${_h} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/nclink/${_sub} COMPONENT plant_dev)
  endif()
endforeach()
install(DIRECTORY include/nclink DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev PATTERN "sim_driver.hpp" EXCLUDE
        ${_plant_header_excludes})
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
# What libnclink.a needs besides itself (nclink-static.pc) and what
# libnclink.so loads (nclink.pc, Libs.private).
set(NCLINK_PC_PRIVATE_LIBS "-lmosquitto")
if(NCLINK_WITH_TLS)
  string(APPEND NCLINK_PC_PRIVATE_LIBS " -lssl -lcrypto")
endif()
configure_file(cmake/nclink.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink.pc @ONLY)
configure_file(cmake/nclink-static.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink-static.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/nclink.pc ${CMAKE_CURRENT_BINARY_DIR}/nclink-static.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)
if(TARGET nclink_plant_static)
  configure_file(cmake/nclink-plant.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink-plant.pc @ONLY)
  configure_file(cmake/nclink-plant-static.pc.in ${CMAKE_CURRENT_BINARY_DIR}/nclink-plant-static.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/nclink-plant.pc ${CMAKE_CURRENT_BINARY_DIR}/nclink-plant-static.pc
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT plant_dev)
endif()
# The template project a vendor copies (docs/porting-guide.md): it builds
# against the SDK, so it ships with what building against nclink needs.
install(DIRECTORY examples/adapter-template/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/adapter-template COMPONENT dev)

install(DIRECTORY models/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/models COMPONENT tools
        FILES_MATCHING PATTERN "*.json" PATTERN "invalid" EXCLUDE)
# The configuration schemas (docs/configuration.md), for editors and checkers.
install(DIRECTORY docs/schema/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/schema COMPONENT tools
        FILES_MATCHING PATTERN "*.schema.json")
