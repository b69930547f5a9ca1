# nclink_test_folder(): a test folder's declaration. Every folder under
# tests/unit/ and tests/integration/ (and tests/faults/) has a CMakeLists.txt
# that calls it once, naming what its tests need beyond the library, Catch2
# and tests/support (tests/README.md):
#
#   nclink_test_folder(
#     [NEEDS target...]          the folder is skipped unless these targets exist
#                                (an optional library, a program, the examples)
#     [LINKS target...]          libraries linked besides nclink_catch_main and nclink_test_support
#     [RUNS target...]           built before the tests, which run them (programs, plugins)
#     [RUNS_IF_BUILT target...]  the same, for programs whose tests skip when they are absent
#     [ALSO_COMPILES file...]    sources of another folder compiled into this binary
#                                (with DEFINES_FOR_ALSO_COMPILED)
#     [DEFINES_FOR_ALSO_COMPILED def...]
#     [DEFINES def...]           compile definitions of the whole binary
#     [INCLUDES dir...]          include directories of the whole binary
#     [NAME exe] [PREFIX text] [LABELS label...] [TIMEOUT seconds]
#     [RESOURCE_LOCK name])      tests holding the same lock never run at once
#                                (ctest -j): e.g. the RabbitMQ clusters
#
# Defaults follow the folder: tests/unit/<m>/ -> test_<m>, each TEST_CASE a
# ctest "<m>:<name>" labelled "unit;<m>"; tests/integration/<m>/ -> itest_<m>,
# "<m> (integration):<name>" labelled "integration;<m>"; timeout 300 s. (The
# prefix ends in a space; Catch2's discovery script drops it.)
function(nclink_test_folder)
  cmake_parse_arguments(T "" "NAME;PREFIX;TIMEOUT;RESOURCE_LOCK"
                        "NEEDS;LINKS;RUNS;RUNS_IF_BUILT;ALSO_COMPILES;DEFINES_FOR_ALSO_COMPILED;DEFINES;INCLUDES;LABELS" ${ARGN})
  if(T_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "${CMAKE_CURRENT_SOURCE_DIR}: nclink_test_folder: unknown arguments ${T_UNPARSED_ARGUMENTS}")
  endif()
  foreach(_target IN LISTS T_NEEDS)
    if(NOT TARGET ${_target})
      return()
    endif()
  endforeach()
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(NOT _sources)
    return()
  endif()

  get_filename_component(_module ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  # Tests of a module this build leaves out (NCLINK_BUILD_PLANT, _HTTP, _BRIDGE).
  if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/src/${_module} AND NOT TARGET nclink_${_module})
    return()
  endif()
  get_filename_component(_parent ${CMAKE_CURRENT_SOURCE_DIR} DIRECTORY)
  get_filename_component(_kind ${_parent} NAME)
  if(_kind STREQUAL "unit")
    set(_exe test_${_module})
    set(_prefix "${_module}: ")
  else()
    set(_exe itest_${_module})
    set(_prefix "${_module} (integration): ")
  endif()
  set(_labels ${_kind} ${_module})
  set(_timeout 300)
  if(T_NAME)
    set(_exe ${T_NAME})
  endif()
  if(DEFINED T_PREFIX)
    set(_prefix "${T_PREFIX}")
  endif()
  if(T_LABELS)
    set(_labels ${T_LABELS})
  endif()
  if(T_TIMEOUT)
    set(_timeout ${T_TIMEOUT})
  endif()

  # A ';' in a test name splits it in CMake's lists: ctest would then run a
  # fragment that matches nothing and "pass". Refuse such names outright.
  foreach(_src IN LISTS _sources T_ALSO_COMPILES)
    file(STRINGS ${_src} _bad REGEX "TEST_CASE\\(\"[^\"]*[;[]")
    if(_bad)
      message(FATAL_ERROR "${_src}: a TEST_CASE name contains ';' or '[' (ctest would split or misread it): ${_bad}")
    endif()
  endforeach()

  add_executable(${_exe} ${_sources} ${T_ALSO_COMPILES})
  if(T_ALSO_COMPILES AND T_DEFINES_FOR_ALSO_COMPILED)
    set_source_files_properties(${T_ALSO_COMPILES} PROPERTIES COMPILE_DEFINITIONS "${T_DEFINES_FOR_ALSO_COMPILED}")
  endif()
  if(T_DEFINES)
    target_compile_definitions(${_exe} PRIVATE ${T_DEFINES})
  endif()
  if(T_INCLUDES)
    target_include_directories(${_exe} PRIVATE ${T_INCLUDES})
  endif()
  target_link_libraries(${_exe} PRIVATE ${T_LINKS} nclink_catch_main nclink_test_support)
  foreach(_target IN LISTS T_RUNS)
    add_dependencies(${_exe} ${_target})
  endforeach()
  foreach(_target IN LISTS T_RUNS_IF_BUILT)
    if(TARGET ${_target})
      add_dependencies(${_exe} ${_target})
    endif()
  endforeach()
  add_dependencies(${_exe} nclink_test_plugins)
  set_target_properties(${_exe} PROPERTIES POSITION_INDEPENDENT_CODE OFF)
  target_precompile_headers(${_exe} REUSE_FROM nclink_catch_main)
  # Run from tests/ of the build tree, wherever the folder is.
  catch_discover_tests(${_exe} TEST_PREFIX "${_prefix}" WORKING_DIRECTORY ${NCLINK_TESTS_BINARY_DIR}
    PROPERTIES LABELS "${_labels}" TIMEOUT ${_timeout})
  # catch_discover_tests() hands its PROPERTIES on flattened: of "LABELS
  # unit transport" only the first label stuck, and `ctest -L transport` (or
  # -L cluster) found nothing, and TIMEOUT was never read (ctest's default of
  # 1500 s applied). A file ctest reads after the discovered tests sets every
  # label, the folder's timeout (the longest test outside the clusters took
  # 87 s of the default 300 here) and its resource lock.
  set(_props "LABELS \"${_labels}\" TIMEOUT ${_timeout}")
  if(T_RESOURCE_LOCK)
    string(APPEND _props " RESOURCE_LOCK ${T_RESOURCE_LOCK}")
  endif()
  set(_labels_file ${CMAKE_CURRENT_BINARY_DIR}/${_exe}_labels.cmake)
  file(WRITE ${_labels_file} "if(${_exe}_TESTS)\n  set_tests_properties(\${${_exe}_TESTS} PROPERTIES ${_props})\nendif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${_labels_file})
endfunction()
