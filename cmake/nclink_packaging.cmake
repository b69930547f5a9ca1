# Debian packages (CPack DEB): `cpack -G DEB` in the build tree, after a
# build (docs/install.md). One package per install component:
#
#   component  package             what
#   lib        libnclink0          the terminal library libnclink.so (named after its soname)
#   dev        libnclink-dev       its headers, static library, CMake package, pkg-config
#   plant_lib  libnclink-plant0    the plant library libnclink-plant.so (client, agent, mappings)
#   plant_dev  libnclink-plant-dev its headers, static library, CMake targets, pkg-config
#   tools      nclink-tools     nclink, nclink-conform, nclink-sim and its plugin,
#                               models, configuration schemas
#   driver_modbus     nclink-driver-modbus     the Modbus TCP/RTU driver plugin
#   driver_mtconnect  nclink-driver-mtconnect  the MTConnect/SHDR source driver plugin
#   <service>  nclink-<service> a program run by systemd: the table at the end
#                               (agent now; bridge and the OPC UA server when
#                               their programs are in the tree)
#
# Where the files are: packaging/systemd (the unit template), packaging/debian
# (maintainer scripts, copyright, changelog), packaging/config (default
# configurations, conffiles under /etc/nclink), packaging/sysusers (the nclink
# user), packaging/lintian (overrides, each explained).
#
# System paths: with the prefix /usr (as in a package) the configuration goes
# to /etc and units to /lib/systemd/system; with any other prefix (a plain
# `cmake --install --prefix DIR`) both stay under the prefix, so an install
# into a scratch directory never touches the machine.

set(NCLINK_PACKAGE_MAINTAINER "nclink maintainers <nclink@packages.invalid>" CACHE STRING
    "Maintainer field of the Debian packages")
set(NCLINK_PACKAGE_RELEASE 1 CACHE STRING "Debian revision of the packages (the -N in 0.1.0-N)")
set(NCLINK_DEB_VERSION "${PROJECT_VERSION}-${NCLINK_PACKAGE_RELEASE}")
set(NCLINK_SOURCE_PACKAGE nclink)
set(_pkg_src ${PROJECT_SOURCE_DIR}/packaging)
set(_pkg_out ${CMAKE_BINARY_DIR}/packaging)
file(MAKE_DIRECTORY ${_pkg_out})
# Reproducible: SOURCE_DATE_EPOCH, when set, fixes the changelog's date.
string(TIMESTAMP NCLINK_PACKAGE_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
string(TIMESTAMP NCLINK_PACKAGE_YEAR "%Y" UTC)

# Install-time system directories (see above), without their leading "/":
# the rules name them as "/${...}" so CMake takes them for absolute paths
# (DESTDIR applies) instead of putting the prefix in front. Runs before the
# rules of every component that needs them.
set(_system_dirs_code [[
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(NCLINK_ETC_DIR etc)
  set(NCLINK_UNIT_DIR lib/systemd/system)
else()
  string(REGEX REPLACE "^/+" "" _nclink_prefix "${CMAKE_INSTALL_PREFIX}")
  set(NCLINK_ETC_DIR ${_nclink_prefix}/etc)
  set(NCLINK_UNIT_DIR ${_nclink_prefix}/lib/systemd/system)
endif()
]])

set(NCLINK_PACKAGE_COMPONENTS "")

# nclink_package(COMPONENT NAME SUMMARY DESCRIPTION [SECTION s] [DEPENDS d]
#                [SCRIPTS files...] [CONFFILES paths...])
# A Debian package of one install component, with the files every package
# needs: copyright, changelog, lintian overrides (packaging/lintian/NAME).
function(nclink_package component)
  cmake_parse_arguments(P "" "NAME;SUMMARY;DESCRIPTION;SECTION;DEPENDS;ARCHITECTURE" "SCRIPTS;CONFFILES;CONTROL" ${ARGN})
  string(TOUPPER ${component} C)
  set(doc ${CMAKE_INSTALL_DATADIR}/doc/${P_NAME})
  set(out ${_pkg_out}/${P_NAME})
  file(MAKE_DIRECTORY ${out})
  configure_file(${_pkg_src}/debian/copyright.in ${out}/copyright @ONLY)
  configure_file(${_pkg_src}/debian/changelog.in ${out}/changelog.Debian @ONLY)
  # gzip -9n: compressed and without a time stamp (Debian policy 12.7).
  add_custom_command(OUTPUT ${out}/changelog.Debian.gz
    COMMAND gzip -9nc changelog.Debian > changelog.Debian.gz
    DEPENDS ${out}/changelog.Debian WORKING_DIRECTORY ${out} VERBATIM)
  add_custom_target(nclink_package_doc_${component} ALL DEPENDS ${out}/changelog.Debian.gz)
  install(FILES ${out}/copyright ${out}/changelog.Debian.gz DESTINATION ${doc} COMPONENT ${component})
  if(EXISTS ${_pkg_src}/lintian/${P_NAME})
    install(FILES ${_pkg_src}/lintian/${P_NAME} DESTINATION ${CMAKE_INSTALL_DATADIR}/lintian/overrides
            COMPONENT ${component})
  endif()

  set(extra ${P_SCRIPTS} ${P_CONTROL})
  if(P_CONFFILES)
    string(REPLACE ";" "\n" lines "${P_CONFFILES}")
    file(WRITE ${out}/conffiles "${lines}\n")
    list(APPEND extra ${out}/conffiles)
  endif()
  set(CPACK_DEBIAN_${C}_PACKAGE_NAME ${P_NAME} PARENT_SCOPE)
  set(CPACK_DEBIAN_${C}_FILE_NAME DEB-DEFAULT PARENT_SCOPE)
  # The first line is the synopsis; CPack puts a space in front of every
  # other line and turns empty ones into " ." (Debian policy 5.6.13).
  set(CPACK_COMPONENT_${C}_DESCRIPTION "${P_SUMMARY}\n${P_DESCRIPTION}" PARENT_SCOPE)
  set(CPACK_DEBIAN_${C}_PACKAGE_SECTION ${P_SECTION} PARENT_SCOPE)
  set(CPACK_DEBIAN_${C}_PACKAGE_DEPENDS "${P_DEPENDS}" PARENT_SCOPE)
  if(P_ARCHITECTURE)
    set(CPACK_DEBIAN_${C}_PACKAGE_ARCHITECTURE ${P_ARCHITECTURE} PARENT_SCOPE)
  endif()
  set(CPACK_DEBIAN_${C}_PACKAGE_CONTROL_EXTRA "${extra}" PARENT_SCOPE)
  set(NCLINK_PACKAGE_COMPONENTS ${NCLINK_PACKAGE_COMPONENTS} ${component} PARENT_SCOPE)
endfunction()

# The shared library: a shlibs file for packages built against it, and the
# ldconfig trigger (Debian policy 8.1.1).
file(WRITE ${_pkg_out}/triggers "activate-noawait ldconfig\n")
set(_dev_depends "libnclink${NCLINK_SOVERSION} (= ${NCLINK_DEB_VERSION}), nlohmann-json3-dev (>= 3.11), libfmt-dev, libmosquitto-dev")
if(NCLINK_WITH_TLS)
  string(APPEND _dev_depends ", libssl-dev")
endif()
nclink_package(lib NAME libnclink${NCLINK_SOVERSION} SECTION libs CONTROL ${_pkg_out}/triggers
  SUMMARY "NC-Link (GB/T 41970-2022) SDK - terminal library"
  DESCRIPTION "nclink lets CNC controllers and factory applications speak NC-Link over
MQTT. The terminal library is what controller firmware links: the model
engine, value operations, the adapter runtime and the gateway, over
libmosquitto.

This package holds the shared library libnclink.so.")

nclink_package(dev NAME libnclink-dev SECTION libdevel
  DEPENDS "${_dev_depends}"
  SUMMARY "NC-Link (GB/T 41970-2022) SDK - terminal library, development files"
  DESCRIPTION "nclink lets CNC controllers and factory applications speak NC-Link over
MQTT.

This package holds the terminal library's headers, its static library, the
CMake package (find_package(nclink CONFIG)) and the pkg-config files
(nclink.pc, nclink-static.pc).")

if(TARGET nclink_plant_static)
  # dpkg-shlibdeps finds libnclink.so.0 in the build tree (it is in no
  # installed package while the packages are being made); the dependency on
  # the exact terminal package is stated here, as the -dev packages do.
  nclink_package(plant_lib NAME libnclink-plant${NCLINK_SOVERSION} SECTION libs CONTROL ${_pkg_out}/triggers
    DEPENDS "libnclink${NCLINK_SOVERSION} (= ${NCLINK_DEB_VERSION})"
    SUMMARY "NC-Link (GB/T 41970-2022) SDK - plant library"
    DESCRIPTION "nclink lets CNC controllers and factory applications speak NC-Link over
MQTT. The plant library is what applications and plant services link: the
application client, the agent and the MTConnect / OPC UA mappings, over
paho-mqtt-cpp (MQTT 5, WebSocket). It uses the terminal library.

This package holds the shared library libnclink-plant.so.")
  nclink_package(plant_dev NAME libnclink-plant-dev SECTION libdevel
    DEPENDS "libnclink-plant${NCLINK_SOVERSION} (= ${NCLINK_DEB_VERSION}), libnclink-dev (= ${NCLINK_DEB_VERSION}), libpaho-mqttpp-dev, libpaho-mqtt-dev"
    SUMMARY "NC-Link (GB/T 41970-2022) SDK - plant library, development files"
    DESCRIPTION "nclink lets CNC controllers and factory applications speak NC-Link over
MQTT.

This package holds the plant library's headers (client, agent, mappings,
the paho transport), its static library, its CMake targets
(nclink::plant) and the pkg-config files (nclink-plant.pc,
nclink-plant-static.pc).")
endif()

nclink_package(tools NAME nclink-tools SECTION net
  SUMMARY "NC-Link (GB/T 41970-2022) command-line tools and simulated machine"
  DESCRIPTION "nclink: probe, query, set, watch (and a full-screen view), call methods,
send models, check configuration files. nclink-conform: the chapter-9
conformance tester. nclink-sim: a simulated machine (a 3-axis mill, or any
model) with its driver plugin. Also the configuration JSON Schemas under
/usr/share/nclink/schema.")

# The drivers a plant installs for the machines it has (docs/drivers/), each
# in a package of its own so that one machine's protocol library (libmodbus,
# libxml2) is only on the boxes that serve such machines.
if(TARGET nclink_modbus_plugin)
  nclink_package(driver_modbus NAME nclink-driver-modbus SECTION net
    SUMMARY "NC-Link (GB/T 41970-2022) driver for Modbus TCP and RTU machines"
    DESCRIPTION "nclink: the driver plugin nclink/drivers/nclink-modbus.so that serves a PLC
or machine speaking Modbus TCP, or Modbus RTU on a serial line shared by
several machines, as an NC-Link terminal. Its map (the driver's
configuration) names each model item's registers; see nclink-tools for
nclink-sim --plugin and the gateway for serving many machines.")
endif()
if(TARGET nclink_mtconnect_plugin)
  nclink_package(driver_mtconnect NAME nclink-driver-mtconnect SECTION net
    SUMMARY "NC-Link (GB/T 41970-2022) driver for MTConnect agents and SHDR adapters"
    DESCRIPTION "nclink: the driver plugin nclink/drivers/nclink-mtconnect.so that serves a
machine already reachable through an MTConnect agent (HTTP) or an SHDR
adapter (TCP) as an NC-Link terminal, its model generated from the agent's
probe document (nclink map --from-mtconnect).")
endif()

# ---------------------------------------------------------------- services
# nclink_service(SERVICE ...): a program run by systemd, packaged as
# nclink-SERVICE with a hardened unit (packaging/systemd/nclink-service.service.in),
# its default configuration as a conffile, the nclink user and its state
# directory /var/lib/nclink/SERVICE. Skipped when the program is not in the
# tree (TARGET not built, DIRECTORY absent), so a table entry can wait for it.
#   TARGET t... | DIRECTORY d  the program: a CMake target (the first of the
#                            names that exists), or a folder to ship under
#                            /usr/share/nclink/SERVICE (a Node program; SKIP
#                            names files of it not to ship)
#   EXEC "..."               ExecStart= (absolute paths; {main}: the Node
#                            program's entry point)
#   RELOAD_CHECK "..."       a command that checks the configuration; when
#                            given, reload = this check, then SIGHUP
#   RELOAD                   reload = SIGHUP without a check
#   CONFIG file              default configuration -> /etc/nclink/SERVICE.EXT
#                            (a conffile); a .env file is the unit's
#                            EnvironmentFile= (options of a program without
#                            a configuration file)
#   JIT                      the program needs writable+executable memory (Node)
function(nclink_service service)
  cmake_parse_arguments(S "RELOAD;JIT" "DIRECTORY;EXEC;RELOAD_CHECK;CONFIG;SUMMARY;DESCRIPTION;DEPENDS;ARCHITECTURE"
                        "TARGET;SKIP" ${ARGN})
  if(S_TARGET)
    set(found "")
    foreach(t IN LISTS S_TARGET)
      if(TARGET ${t} AND NOT found)
        set(found ${t})
      endif()
    endforeach()
    if(NOT found)
      return()
    endif()
    set(S_TARGET ${found})
  endif()
  if(S_DIRECTORY AND NOT IS_DIRECTORY ${PROJECT_SOURCE_DIR}/${S_DIRECTORY})
    return()
  endif()
  if(S_CONFIG AND NOT EXISTS ${PROJECT_SOURCE_DIR}/${S_CONFIG})
    message(FATAL_ERROR "nclink-${service}: add its default configuration ${S_CONFIG}")
  endif()
  # {main}: the entry point a Node program's package.json names.
  if(S_DIRECTORY AND S_EXEC MATCHES "{main}")
    # package.json's "main", else <folder name>.js, else index.js.
    get_filename_component(folder ${S_DIRECTORY} NAME)
    set(main index.js)
    if(EXISTS ${PROJECT_SOURCE_DIR}/${S_DIRECTORY}/${folder}.js)
      set(main ${folder}.js)
    endif()
    if(EXISTS ${PROJECT_SOURCE_DIR}/${S_DIRECTORY}/package.json)
      file(READ ${PROJECT_SOURCE_DIR}/${S_DIRECTORY}/package.json package_json)
      string(JSON declared ERROR_VARIABLE no_main GET "${package_json}" main)
      if(NOT no_main)
        set(main ${declared})
      endif()
    endif()
    string(REPLACE "{main}" "${main}" S_EXEC "${S_EXEC}")
  endif()
  set(component ${service})
  set(NCLINK_SERVICE ${service})
  set(NCLINK_PACKAGE nclink-${service})
  set(NCLINK_SERVICE_SUMMARY "${S_SUMMARY}")
  set(NCLINK_SERVICE_EXEC "${S_EXEC}")
  set(NCLINK_SERVICE_MDWE yes)
  if(S_JIT)
    set(NCLINK_SERVICE_MDWE no)
  endif()
  set(NCLINK_SERVICE_RELOAD "# No ExecReload: the program does not re-read its configuration; restart it.")
  if(S_RELOAD_CHECK)
    set(NCLINK_SERVICE_RELOAD "# Reload: check the file first, so `systemctl reload` reports a broken one;\n# then SIGHUP (a broken file is refused and logged by the program as well).\nExecReload=${S_RELOAD_CHECK}\nExecReload=/bin/kill -HUP $MAINPID")
  elseif(S_RELOAD)
    set(NCLINK_SERVICE_RELOAD "ExecReload=/bin/kill -HUP $MAINPID")
  endif()
  set(NCLINK_CONFIG_FILE "")
  set(NCLINK_SERVICE_ENVIRONMENT "")
  set(conffiles "")
  if(S_CONFIG)
    get_filename_component(ext ${S_CONFIG} LAST_EXT)
    set(NCLINK_CONFIG_FILE /etc/nclink/${service}${ext})
    set(conffiles ${NCLINK_CONFIG_FILE})
    if(ext STREQUAL ".env")
      set(NCLINK_SERVICE_ENVIRONMENT "EnvironmentFile=${NCLINK_CONFIG_FILE}")
    endif()
  endif()
  set(NCLINK_SYSUSERS_FILE /usr/lib/sysusers.d/${NCLINK_PACKAGE}.conf)

  set(out ${_pkg_out}/${NCLINK_PACKAGE})
  file(MAKE_DIRECTORY ${out}/scripts)
  configure_file(${_pkg_src}/systemd/nclink-service.service.in ${out}/${NCLINK_PACKAGE}.service @ONLY)
  foreach(script postinst prerm postrm)
    configure_file(${_pkg_src}/debian/${script}.in ${out}/scripts/${script} @ONLY
                   FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
  endforeach()

  if(S_TARGET)
    install(TARGETS ${S_TARGET} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${component})
  else()
    set(skip "")
    foreach(f IN LISTS S_SKIP)
      list(APPEND skip PATTERN ${f} EXCLUDE)
    endforeach()
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${S_DIRECTORY}/ DESTINATION ${CMAKE_INSTALL_DATADIR}/nclink/${service}
            COMPONENT ${component} PATTERN "test" EXCLUDE PATTERN "tests" EXCLUDE PATTERN ".*" EXCLUDE
            PATTERN "CMakeLists.txt" EXCLUDE ${skip})
  endif()
  install(CODE "${_system_dirs_code}" COMPONENT ${component})
  install(FILES ${out}/${NCLINK_PACKAGE}.service DESTINATION "/\${NCLINK_UNIT_DIR}" COMPONENT ${component})
  if(S_CONFIG)
    install(FILES ${PROJECT_SOURCE_DIR}/${S_CONFIG} DESTINATION "/\${NCLINK_ETC_DIR}/nclink" RENAME ${service}${ext}
            COMPONENT ${component})
  endif()
  install(FILES ${_pkg_src}/sysusers/nclink.conf DESTINATION lib/sysusers.d
          RENAME ${NCLINK_PACKAGE}.conf COMPONENT ${component})
  install(FILES ${PROJECT_SOURCE_DIR}/docs/install.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${NCLINK_PACKAGE}
          RENAME README.md COMPONENT ${component})

  nclink_package(${component} NAME ${NCLINK_PACKAGE} SECTION net ARCHITECTURE "${S_ARCHITECTURE}"
    DEPENDS "${S_DEPENDS}" SUMMARY "${S_SUMMARY}" DESCRIPTION "${S_DESCRIPTION}"
    SCRIPTS ${out}/scripts/postinst ${out}/scripts/prerm ${out}/scripts/postrm
    CONFFILES ${conffiles})
  string(TOUPPER ${component} C)
  foreach(v IN ITEMS PACKAGE_NAME FILE_NAME PACKAGE_SECTION PACKAGE_DEPENDS PACKAGE_ARCHITECTURE PACKAGE_CONTROL_EXTRA)
    set(CPACK_DEBIAN_${C}_${v} "${CPACK_DEBIAN_${C}_${v}}" PARENT_SCOPE)
  endforeach()
  set(CPACK_COMPONENT_${C}_DESCRIPTION "${CPACK_COMPONENT_${C}_DESCRIPTION}" PARENT_SCOPE)
  set(NCLINK_PACKAGE_COMPONENTS ${NCLINK_PACKAGE_COMPONENTS} PARENT_SCOPE)
  set_property(GLOBAL APPEND PROPERTY NCLINK_SERVICE_UNITS ${out}/${NCLINK_PACKAGE}.service)
endfunction()

# The service table: one entry per program systemd runs.
nclink_service(agent TARGET nclink-agent
  EXEC "/usr/bin/nclink-agent --config /etc/nclink/agent.json --metrics 127.0.0.1:9470"
  RELOAD_CHECK "/usr/bin/nclink-agent --config /etc/nclink/agent.json --check-config"
  CONFIG packaging/config/agent.json
  DEPENDS "adduser"
  SUMMARY "NC-Link agent: registration, discovery, state, access control"
  DESCRIPTION "nclink-agent answers what GB/T 41970-2022 asks of an agent on top of any
MQTT broker: Register/Request, Discovery/Request, Notify/State, the model
version cache, DEV_UNREACHABLE and timeout answers, and access control with
a generated mosquitto ACL. Runs as the nclink user under systemd; reads
/etc/nclink/agent.json and reloads it on `systemctl reload nclink-agent`.")
# The bridge to MTConnect, GB/T 18759.6, SHDR and JSON. (Its program is the
# target nclink_bridge_tool: nclink_bridge is the library, which installs no program.)
nclink_service(bridge TARGET nclink_bridge_tool
  EXEC "/usr/bin/nclink-bridge --config /etc/nclink/bridge.json"
  RELOAD
  CONFIG packaging/config/bridge.json
  DEPENDS "adduser"
  SUMMARY "NC-Link machines as MTConnect, GB/T 18759.6, SHDR and JSON"
  DESCRIPTION "nclink-bridge serves the NC-Link machines on a broker over MTConnect 1.4
REST, GB/T 18759.6, SHDR and a JSON API, with a web dashboard (live
values, sample plots, Set) and Prometheus metrics on the same port. Runs as
the nclink user under systemd; reads /etc/nclink/bridge.json and reloads
it on `systemctl reload nclink-bridge`.")
# The OPC UA server (Node.js, from another branch): shipped with the
# node_modules `npm ci --omit=dev` put into its folder. It takes its options
# from /etc/nclink/opcua.env.
nclink_service(opcua DIRECTORY tools/nclink-opcua JIT ARCHITECTURE all SKIP nclink-opcua
  EXEC "/usr/bin/node /usr/share/nclink/opcua/{main} $NCLINK_OPCUA_OPTIONS"
  CONFIG packaging/config/opcua.env
  DEPENDS "adduser, nodejs (>= 18)"
  SUMMARY "NC-Link to OPC UA server (GB/T 39561.3 appendix B mapping)"
  DESCRIPTION "nclink-opcua serves NC-Link devices as an OPC UA address space. Runs as
the nclink user under systemd and takes its options from
/etc/nclink/opcua.env.")

# The Python package (python/, docs/python.md): `import nclink` for
# Debian's python3 (3.11), the extension module linked with the static library.
if(TARGET nclink_python)
  nclink_package(python NAME python3-nclink SECTION python
    DEPENDS "python3 (>= 3.11), python3 (<< 3.12)"
    SUMMARY "NC-Link (GB/T 41970-2022) client library for Python 3"
    DESCRIPTION "import nclink: an NC-Link application in Python over the nclink C++
client. Connect to a broker, probe, query and set data items, call methods
with progress, receive sample channels (callbacks, iterators, asyncio, pandas
DataFrames), dynamic sampling and events. Errors are exceptions carrying the
table-19 code.")
endif()

# ---------------------------------------------------------------- CPack
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME nclink)
set(CPACK_PACKAGE_VENDOR "nclink")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${NCLINK_PACKAGE_MAINTAINER}")
# CPack's own default summary, which it does not put in front of each
# package's description: every package's first line is its own synopsis.
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${CMAKE_PROJECT_NAME} built using CMake")
# Installs with DESTDIR and the prefix /usr, so the install-time system
# directories above resolve to /etc and /lib/systemd/system in the package.
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_PACKAGE_DIRECTORY ${CMAKE_BINARY_DIR}/packages)
set(CPACK_COMPONENTS_ALL ${NCLINK_PACKAGE_COMPONENTS})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${NCLINK_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_RELEASE ${NCLINK_PACKAGE_RELEASE})
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SECTION net)
set(CPACK_DEBIAN_PACKAGE_SOURCE ${NCLINK_SOURCE_PACKAGE})
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "")
# Depends of the programs and the library come from dpkg-shlibdeps.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The plant library links the terminal one, which lives in a sibling package
# built in the same run: dpkg-shlibdeps looks for it here (-l).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${CMAKE_LIBRARY_OUTPUT_DIRECTORY})
# libnclink0 gets a shlibs file for packages built against it (plugins have
# no soname and are left out).
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
# Binaries without debug information (a RelWithDebInfo build carries it).
set(CPACK_STRIP_FILES ON)
include(CPack)
